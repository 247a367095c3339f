// three.js renders an exported scene file as a three.js user does: GLTFLoader reads the .glb (meshes, materials,
// textures, KHR_lights_punctual, KHR_materials_specular, the camera), EXRLoader (float) reads the environment, set
// as scene.environment with EquirectangularReflectionMapping (the renderer's own PMREM) turned by
// scene.environmentRotation (d.envRotationY: three's equirect lookup faces +x at the image centre, the manifest's
// +z). Nothing is converted by hand: the lights are GLTFLoader's (directional lux, point/spot candela, decay 2,
// distance = range or 0; spot angle = outer, penumbra = 1 − inner/outer). No tone mapping, linear output, a
// FloatType render target read back with readRenderTargetPixels (row 0 = bottom); alpha = coverage.
import * as THREE from 'three';
import {GLTFLoader} from 'three/addons/loaders/GLTFLoader.js';
import {EXRLoader} from 'three/addons/loaders/EXRLoader.js';
import {f32ToB64} from './common.mjs';
import {renderFloat} from './three_target.mjs';

export const version = THREE.REVISION;
let renderer = null;
const envCache = new Map();  // environment url -> equirect DataTexture (the renderer caches its PMREM per texture)

function getRenderer(w, h) {
  if (!renderer) {
    renderer = new THREE.WebGLRenderer({canvas: document.createElement('canvas'), antialias: false, alpha: true});
    renderer.toneMapping = THREE.NoToneMapping;
    renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
  }
  renderer.setSize(w, h, false);
  return renderer;
}

async function environment(url) {
  if (!envCache.has(url)) {
    const tex = await new EXRLoader().setDataType(THREE.FloatType).loadAsync(url);
    tex.mapping = THREE.EquirectangularReflectionMapping;
    envCache.set(url, tex);
  }
  return envCache.get(url);
}

export async function renderGltf(d) {
  const {width, height} = d.image;
  const opts = d.options || {};
  const r = getRenderer(width, height);
  const gltf = await new GLTFLoader().loadAsync(d.glb);
  const scene = new THREE.Scene();  // GLTFLoader's gltf.scene is a Group: added to a Scene, as users do
  scene.add(gltf.scene);
  const cam = gltf.cameras[0];
  if (!cam) throw new Error(`${d.glb}: no camera`);
  if (cam.isPerspectiveCamera) { cam.aspect = width / height; cam.updateProjectionMatrix(); }
  let env_ms = 0;
  if (d.environment) {
    const t = performance.now();
    scene.environment = await environment(d.environment);
    scene.environmentRotation.set(0, opts.envRotationY || 0, 0);
    env_ms = performance.now() - t;
  }
  // shadows as a three.js user turns them on (GLTFLoader leaves them off): the renderer's shadow map (PCF),
  // every light casting, every mesh casting and receiving
  r.shadowMap.enabled = Boolean(opts.shadows); r.shadowMap.type = THREE.PCFShadowMap;
  if (opts.shadows) scene.traverse((o) => { if (o.isLight && !o.isAmbientLight) o.castShadow = true;
                                            if (o.isMesh) { o.castShadow = true; o.receiveShadow = true; } });
  const lights = [];
  scene.traverse((o) => { if (o.isLight) lights.push({type: o.type, intensity: o.intensity, decay: o.decay,
                                                      distance: o.distance, angle: o.angle, penumbra: o.penumbra,
                                                      power: o.power}); });
  const materials = [];
  scene.traverse((o) => { if (o.isMesh) materials.push({type: o.material.type, specularIntensity: o.material.specularIntensity,
                                                        ior: o.material.ior}); });
  const {out, frame_ms} = renderFloat(r, scene, cam, width, height);
  scene.traverse((o) => { if (o.isMesh) { o.geometry.dispose(); for (const v of Object.values(o.material)) if (v && v.isTexture) v.dispose(); o.material.dispose(); } });
  return {data: f32ToB64(out), frame_ms, env_ms, version, info: {lights, materials}};
}
