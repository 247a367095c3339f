// Babylon.js renders a validate render scene through its own pipeline: PBRMaterial (metallic-roughness;
// metallicF0Factor = KHR_materials_specular's factor, 0 for a Lambertian), HDRCubeTexture on the scene's .hdr
// file (its RGBE loader, panorama-to-cube, spherical polynomial for diffuse, HDRFiltering prefilter for
// specular), DirectionalLight in lux, PointLight / SpotLight in candela with falloffType = FALLOFF_GLTF (inverse
// square without range; a KHR spot as Babylon's glTF loader maps it: angle = 2·outer, innerAngle = 2·inner),
// HemisphericLight, a TEXTURETYPE_FLOAT RenderTargetTexture read back with readPixels.
// Image processing (tone mapping, exposure, gamma) is left to a post process that is never attached: linear radiance.
import * as BABYLON from '../../../node_modules/@babylonjs/core/index.js';

export const version = BABYLON.Engine.Version;
let engine = null, canvas = null;
const envCache = new Map();  // environment key -> prefiltered HDRCubeTexture (prefiltered once per environment)

function getEngine() {
  if (!engine) {
    canvas = document.createElement('canvas'); canvas.width = 64; canvas.height = 64;
    engine = new BABYLON.Engine(canvas, false, {preserveDrawingBuffer: true, stencil: false});
  }
  return engine;
}

async function environment(scene, env, cubeSize, opts = {}) {
  const cdf = opts.irradiance === 'cdf';  // (b) CDF irradiance scenes (babylon_cdf.mjs)
  const key = cdf ? cdfKey(env, opts, cubeSize) : env.key;
  if (envCache.has(key)) return envCache.get(key);
  const t0 = performance.now();
  const tex = cdf ? cdfCubeTexture(BABYLON, env.url, scene, cubeSize, opts.supersample)
    : new BABYLON.HDRCubeTexture(env.url, scene, cubeSize, false, true, false, true);
  await new Promise((res, rej) => { const check = () => tex.isReady() ? res() : setTimeout(check, 20); check(); });
  await scene.whenReadyAsync();
  const entry = {tex, ms: performance.now() - t0};
  envCache.set(key, entry);
  return entry;
}

function material(scene, m, opts) {
  const mat = new BABYLON.PBRMaterial('m', scene);
  mat.albedoColor = new BABYLON.Color3(...m.baseColor);
  mat.metallic = m.metallic; mat.roughness = m.roughness;
  mat.metallicF0Factor = m.specular;
  if (opts.diffuseModel !== undefined) mat.brdf.baseDiffuseModel = opts.diffuseModel;
  mat.skipFinalColorClamp = true;
  return mat;
}

const rgb = (c) => new BABYLON.Color3(c[0], c[1], c[2]);
const v3 = (v) => new BABYLON.Vector3(v[0], v[1], v[2]);

// A hemisphere of radiance sky / ground: Babylon's PBR hemispheric term is mix(ground, sky, ½ + ½ n·up) times the
// albedo with no 1/π (pbrDirectLightingFunctions computeHemisphericDiffuseLighting), so radiance L enters as colour
// L with intensity 1; its specular colour is black (a hemisphere has no highlight).
function addLight(scene, l) {
  let light;
  if (l.type === 'hemisphere') {
    light = new BABYLON.HemisphericLight('hemi', v3(l.up), scene);
    light.diffuse = rgb(l.sky); light.groundColor = rgb(l.ground); light.specular = new BABYLON.Color3(0, 0, 0);
    light.intensity = 1; return;
  }
  if (l.type === 'point') light = new BABYLON.PointLight('point', v3(l.position), scene);
  else if (l.type === 'spot') {
    light = new BABYLON.SpotLight('spot', v3(l.position), v3(l.direction), 2 * l.outer_deg * Math.PI / 180, 1, scene);
    light.innerAngle = 2 * l.inner_deg * Math.PI / 180;
  } else light = new BABYLON.DirectionalLight('sun', v3(l.direction), scene);
  if (l.type !== 'directional') light.falloffType = BABYLON.Light.FALLOFF_GLTF;
  light.intensity = l.intensity; light.diffuse = rgb(l.color); light.specular = rgb(l.color);
}

function geometry(scene, g) {
  if (g.type === 'plane') {
    // CreatePlane's front face looks down −z in Babylon's left-handed default; drawn double-sided with two-sided
    // lighting (the normal flipped towards the viewer) it faces the camera at +z in either handedness.
    return BABYLON.MeshBuilder.CreatePlane('plane', {size: g.size, sideOrientation: BABYLON.Mesh.DOUBLESIDE}, scene);
  }
  // MeshBuilder.CreateSphere's own steps (sphereBuilder.pure.js: new Mesh, the default side orientation, the vertex
  // data applied), with the vertex data built once per description: a 254-segment sphere is the same data every scene
  const options = {diameter: 2 * g.radius, segments: g.segments[1] - 2,
                   sideOrientation: BABYLON.Mesh._GetDefaultSideOrientation(undefined)};
  const key = JSON.stringify(options);
  if (!sphereData.has(key)) sphereData.set(key, BABYLON.CreateSphereVertexData(options));
  const sphere = new BABYLON.Mesh('s', scene);
  sphere._originalBuilderSideOrientation = options.sideOrientation;
  sphereData.get(key).applyToMesh(sphere, undefined);
  return sphere;
}
const sphereData = new Map();  // sphere options -> VertexData (CreateSphereVertexData, built once per page)

export async function renderBabylon(d) {
  const eng = getEngine();
  const {width, height} = d.image;
  const opts = d.options || {};
  const scene = new BABYLON.Scene(eng);
  scene.useRightHandedSystem = true;
  // Linear output: with image processing "applied by a post process" the PBR shader skips its own tone mapping
  // and its final toGammaSpace (measured: without this the target held radiance^(1/2.2)); no post process is
  // attached to the render target, so nothing applies it.
  scene.imageProcessingConfiguration.applyByPostProcess = true;
  scene.imageProcessingConfiguration.toneMappingEnabled = false;
  scene.imageProcessingConfiguration.exposure = 1.0;
  scene.imageProcessingConfiguration.contrast = 1.0;
  scene.clearColor = new BABYLON.Color4(0, 0, 0, 0);
  let prefilter_ms = 0;
  if (d.environment) {
    const e = await environment(scene, d.environment, opts.cubeSize || 128, opts);
    // the texture belongs to the first scene that loaded it; later scenes share it
    scene.environmentTexture = e.tex; prefilter_ms = e.ms; e.ms = 0;
  }
  for (const l of d.lights) addLight(scene, l);
  const g = d.geometry || {type: 'sphere', radius: d.sphere.radius, segments: d.sphere.segments};
  const sphere = geometry(scene, g);
  sphere.material = material(scene, d.material, opts);
  if (g.type === 'plane') { sphere.material.backFaceCulling = false; sphere.material.twoSidedLighting = true; }
  const shadows = d.shadow ? addShadows(scene, sphere, d.shadow) : null;  // (e) shadow scenes only
  const cam = new BABYLON.FreeCamera('c', new BABYLON.Vector3(...d.camera.position), scene);
  cam.upVector = new BABYLON.Vector3(...d.camera.up);
  cam.setTarget(new BABYLON.Vector3(...d.camera.target));
  cam.mode = BABYLON.Camera.ORTHOGRAPHIC_CAMERA;
  const e = d.camera.half_extent;
  cam.orthoLeft = -e; cam.orthoRight = e; cam.orthoTop = e; cam.orthoBottom = -e; cam.minZ = 0.1; cam.maxZ = 100;
  scene.activeCamera = cam;
  const rt = new BABYLON.RenderTargetTexture('rt', {width, height}, scene, false, true,
                                             BABYLON.Constants.TEXTURETYPE_FLOAT, false, BABYLON.Texture.NEAREST_SAMPLINGMODE);
  rt.renderList = [sphere]; rt.activeCamera = cam; rt.clearColor = new BABYLON.Color4(0, 0, 0, 0);
  await scene.whenReadyAsync();
  const t0 = performance.now();
  for (let k = 0; k < 200 && !sphere.material.isReady(sphere); k++) await new Promise(r => setTimeout(r, 20));
  if (shadows) await shadows.prepare();
  rt.render();
  const px = await rt.readPixels();
  const frame_ms = performance.now() - t0;
  const out = new Float32Array(px.buffer, px.byteOffset, width * height * 4).slice();
  const shadowInfo = shadows ? shadows.finish() : {};
  if (opts.irradiance === 'cdf') shadowInfo.cdf = cdfInfo(scene.environmentTexture);
  rt.dispose(); sphere.material.dispose(); sphere.dispose();
  if (scene.environmentTexture) scene.environmentTexture = null;  // keep the cached texture alive
  return {data: f32ToB64(out), frame_ms, prefilter_ms, version, info: shadowInfo};
}
import {f32ToB64} from './common.mjs';
import {addShadows} from './babylon_shadows.mjs';  // (e) shadows
import {cdfCubeTexture, cdfInfo, cdfKey} from './babylon_cdf.mjs';  // (b) CDF irradiance
