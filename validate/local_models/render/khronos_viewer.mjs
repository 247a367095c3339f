// The Khronos glTF Sample Viewer (npm @khronosgroup/gltf-viewer 1.1.0) rendering an exported scene file
// (validate/local_models/render/khronos_viewer.py). Everything goes through the viewer's own public API:
// ResourceLoader.loadGltf (its glTF loader), ResourceLoader.loadEnvironment (its RGBE reader and its WebGL IBL sampler:
// panorama → cube, Lambertian / GGX / Charlie filtering, its GGX LUT), GltfView.renderFrame (its PBR shader).
// Tone mapping: ToneMaps.NONE ("linear mapping, clamped at 1.0"); the shader still applies its output transfer
// pow(c, 1/2.2) (tonemapping.glsl linearTosRGB) before the 8-bit canvas, which is all renderFrame draws to. The page
// reads the canvas with gl.readPixels (RGBA8, row 0 = bottom) and picks an exposure (the viewer's own
// renderingParameters.exposure, a factor before the transfer) that keeps every value below 255; Python decodes
// radiance = (q/255)^2.2 / exposure.
// The ResourceLoader is built directly (not GltfView.createResourceLoader, which starts libktx and Draco from globals
// a page must load from a CDN: the exported scenes use neither).
// The IBL sampler's sizes: its iblSampler class (not exported) fixes them in its constructor (textureSize 256,
// lutResolution 1024, lowestMipLevel 4, 2048 Lambertian / 1024 GGX / 64 Charlie samples); at those sizes one
// environment took 560 s of SwiftShader on 2 cores (measured). The module's text is loaded as it is published and
// one statement is appended to that constructor — Object.assign(this, globalThis.khronosIblSettings) — so the page
// can set those instance fields per environment (khronos_viewer.py IBL_*); nothing else of the viewer is changed.
const MODULE = '/node_modules/@khronosgroup/gltf-viewer/dist/gltf-viewer.module.js';
const MARKER = 'this.lutResolution = 1024;';
async function loadViewer() {
  const src = await (await fetch(MODULE)).text();
  if (src.split(MARKER).length !== 2) throw new Error(`${MODULE}: the iblSampler constructor is not the one of 1.1.0`);
  const patched = src.replace(MARKER, MARKER + ' Object.assign(this, globalThis.khronosIblSettings || {});');
  return import(URL.createObjectURL(new Blob([patched], {type: 'text/javascript'})));
}
const {GltfView, GltfState, ResourceLoader} = await loadViewer();

export const version = '1.1.0';
const LIBS = '/node_modules/@khronosgroup/gltf-viewer/dist/libs/';
let canvas, gl, view, loader;
const environments = new Map(); // url → loaded environment (its IBL filtered once per page)

function setup() {
  if (view) return;
  canvas = document.createElement('canvas');
  gl = canvas.getContext('webgl2', {antialias: false, alpha: true, premultipliedAlpha: false,
                                    preserveDrawingBuffer: true});
  if (!gl) throw new Error('no WebGL2 context');
  view = new GltfView(gl);
  loader = new ResourceLoader(view, LIBS);
}

async function environment(d) {
  const key = d.env + JSON.stringify(d.iblSettings);
  if (!environments.has(key)) {
    const t0 = performance.now();
    globalThis.khronosIblSettings = d.iblSettings;
    const env = await loader.loadEnvironment(d.env, {lut_sheen_E_file: d.sheenLut});
    gl.finish();
    environments.set(key, {env, ms: performance.now() - t0});
  }
  return environments.get(key);
}

function frame(state, w, h, exposure) {
  state.renderingParameters.exposure = exposure;
  view.renderFrame(state, w, h);
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  return px;
}

// d: {glb, env (URL of an RGBE .hdr; a black one when the scene has none), ibl (bool), iblSettings (the sampler's fields), sheenLut, width, height, exposures: [e0, e1, …] tried in order}
export async function renderKhronos(d) {
  setup();
  const t0 = performance.now();
  canvas.width = d.width; canvas.height = d.height;
  const state = view.createState();
  state.gltf = await loader.loadGltf(d.glb);
  state.sceneIndex = state.gltf.scene ?? 0;
  state.cameraIndex = 0;
  const rp = state.renderingParameters;
  rp.toneMap = GltfState.ToneMaps.NONE;
  rp.clearColor = [0, 0, 0, 0];
  rp.renderEnvironmentMap = false;
  rp.usePunctual = true;
  rp.useDirectionalLightsWithDisabledIBL = false;
  let envMs = 0;
  const e = await environment(d);  // renderFrame needs an environment object even with IBL off
  state.environment = e.env; envMs = e.ms;
  rp.useIBL = d.ibl;
  const load = performance.now() - t0;
  let px, exposure, tries = 0, frameMs = 0;
  for (exposure of d.exposures) {
    tries += 1;
    const f0 = performance.now();
    px = frame(state, d.width, d.height, exposure);
    frameMs = performance.now() - f0;
    let sat = false;
    for (let i = 0; i < px.length; i += 4) {
      if (px[i + 3] > 0 && (px[i] === 255 || px[i + 1] === 255 || px[i + 2] === 255)) { sat = true; break; }
    }
    if (!sat) break;
  }
  let s = '';
  for (let i = 0; i < px.length; i += 0x8000) s += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
  const env = state.environment;
  return {pixels: btoa(s), exposure, tries, frame_ms: frameMs, load_ms: load, env_ms: envMs,
          ibl: env ? {mipCount: env.mipCount, intensityScale: env.iblIntensityScale} : null,
          renderer: gl.getParameter(gl.RENDERER)};
}
