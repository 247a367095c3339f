// Babylon.js renders an exported scene file as a Babylon user does: @babylonjs/loaders' glTF loader
// (SceneLoader.ImportMeshAsync of the .glb: its PBRMaterials, KHR_lights_punctual lights, the glTF camera) into a
// right-handed scene (scene.useRightHandedSystem: no root conversion node), the environment file through core's
// EXRCubeTexture (its EXR decoder, panorama-to-cube, spherical polynomial for diffuse, prefiltered for specular),
// turned by rotationY (d.options.envRotationY). Image processing applied by a post process that is never attached
// (no tone mapping, exposure 1, linear), a TEXTURETYPE_FLOAT RenderTargetTexture read back with readPixels.
import * as BABYLON from '@babylonjs/core/index.js';
import '@babylonjs/loaders/glTF/index.js';
import {ExrLoaderGlobalConfiguration} from '@babylonjs/core/Materials/Textures/Loaders/EXR/exrLoader.configuration.js';
import * as fflate from '/node_modules/three/examples/jsm/libs/fflate.module.js';
import {f32ToB64} from './common.mjs';
import {linearScene} from './babylon_scene.mjs';

// Babylon's EXR decoder loads fflate (ZIP) as a script from ExrLoaderGlobalConfiguration.FFLATEUrl, by default
// https://unpkg.com/fflate@0.8.2 — unreachable offline (measured: EXRCubeTexture's onError, no message). The page
// provides window.fflate (three.js's copy, 0.8.3) and points the URL at a local script with nothing left to do.
window.fflate = fflate;
ExrLoaderGlobalConfiguration.FFLATEUrl = new URL('./babylon_fflate.js', import.meta.url).href;

export const version = BABYLON.Engine.Version;
let engine = null;
const envCache = new Map();  // environment url -> EXRCubeTexture (prefiltered once per file)

function getEngine() {
  if (!engine) {
    const canvas = document.createElement('canvas'); canvas.width = 64; canvas.height = 64;
    engine = new BABYLON.Engine(canvas, false, {preserveDrawingBuffer: true, stencil: false});
  }
  return engine;
}

async function environment(scene, url, size) {
  if (!envCache.has(url)) {
    let failed = null;
    const tex = new BABYLON.EXRCubeTexture(url, scene, size, false, true, false, true, null,
                                           (msg, exc) => { failed = `${msg || ''} ${exc || ''}`; });
    const t0 = performance.now();
    await new Promise((res, rej) => {
      const check = () => tex.isReady() ? res() : failed ? rej(new Error(`EXRCubeTexture ${url}: ${failed}`))
        : performance.now() - t0 > 120000 ? rej(new Error(`EXRCubeTexture ${url}: not ready after 120 s`)) : setTimeout(check, 20);
      check(); });
    envCache.set(url, tex);
  }
  return envCache.get(url);
}

export async function renderGltf(d) {
  const eng = getEngine();
  const {width, height} = d.image;
  const opts = d.options || {};
  const scene = linearScene(eng);  // linear output (babylon_scene.mjs)
  const t0 = performance.now();
  if (d.environment) {
    const tex = await environment(scene, d.environment, opts.cubeSize || 128);
    tex.rotationY = opts.envRotationY || 0;
    scene.environmentTexture = tex;
  }
  const env_ms = performance.now() - t0;
  const res = await BABYLON.SceneLoader.ImportMeshAsync('', '', d.glb, scene, null, '.glb');
  const cam = scene.cameras.find((c) => c.name !== 'default camera') || scene.cameras[0];
  if (!cam) throw new Error(`${d.glb}: no camera`);
  if (cam.mode === BABYLON.Camera.PERSPECTIVE_CAMERA) cam.fovMode = BABYLON.Camera.FOVMODE_VERTICAL_FIXED;
  scene.activeCamera = cam;
  const materials = [];
  for (const m of scene.materials) {
    if (opts.diffuseModel !== undefined && m.brdf) m.brdf.baseDiffuseModel = opts.diffuseModel;
    if ('skipFinalColorClamp' in m) m.skipFinalColorClamp = true;
    materials.push({type: m.getClassName(), diffuseModel: m.brdf && m.brdf.baseDiffuseModel,
                    metallicF0Factor: m.metallicF0Factor});
  }
  const lights = scene.lights.map((l) => ({type: l.getClassName(), intensity: l.intensity, falloff: l.falloffType,
                                           angle: l.angle, innerAngle: l.innerAngle}));
  const meshes = scene.meshes.filter((m) => m.getTotalVertices() > 0);
  const rt = new BABYLON.RenderTargetTexture('rt', {width, height}, scene, false, true,
                                             BABYLON.Constants.TEXTURETYPE_FLOAT, false, BABYLON.Texture.NEAREST_SAMPLINGMODE);
  rt.renderList = meshes; rt.activeCamera = cam; rt.clearColor = new BABYLON.Color4(0, 0, 0, 0);
  await scene.whenReadyAsync();
  for (let k = 0; k < 200 && !meshes.every((m) => !m.material || m.material.isReady(m)); k++) await new Promise(r => setTimeout(r, 20));
  const t1 = performance.now();
  rt.render();
  const px = await rt.readPixels();
  const frame_ms = performance.now() - t1;
  const out = new Float32Array(px.buffer, px.byteOffset, width * height * 4).slice();
  rt.dispose();
  scene.environmentTexture = null;  // the cached texture outlives the scene
  const keep = d.environment ? envCache.get(d.environment) : null;
  if (keep) scene.textures.splice(scene.textures.indexOf(keep), 1);
  scene.dispose();
  return {data: f32ToB64(out), frame_ms, env_ms, version, info: {lights, materials, camera: {type: cam.getClassName(), mode: cam.mode,
          fov: cam.fov, orthoLeft: cam.orthoLeft, orthoTop: cam.orthoTop}}};
}
