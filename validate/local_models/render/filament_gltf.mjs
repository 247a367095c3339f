// Filament (npm filament 1.53.4, WebAssembly + WebGL2) renders an exported scene file as a Filament user does:
// gltfio's AssetLoader reads the .glb (ubershader materials, its KHR_lights_punctual lights as gltfio converts them,
// the glTF camera: asset.getCameraEntities()), the entities go into the scene unchanged. Nothing is converted by hand.
// The one thing a user must choose is the exposure (gltfio's camera keeps Filament's default f/16, 1/125 s, ISO 100:
// e ≈ 2.6e-5); it is picked from Filament's own frames so the 8-bit canvas fills its range (filament_frames.mjs), as
// the hand-built page does (filament_render.mjs): e = ISO/100 at f/1, 1.2 s. Post-processing off (no tone mapping, dithering,
// FXAA): the canvas holds e × radiance in RGBA8 (linear), read with the context's gl.readPixels (row 0 = bottom).
// Shadows as a user turns them on: every light of the asset casts, every renderable casts and receives.
import {exposeAndRead, maxColour} from './filament_frames.mjs';  // frames, readback, auto exposure

export let version = '';
let engine = null, renderer = null, swapChain = null, canvas = null, gl = null, loader = null;

export async function initFilament() {
  await new Promise((res) => Filament.init([], res));
  version = (await (await fetch('/node_modules/filament/package.json')).json()).version;
}

function getEngine(w, h) {
  if (!engine) {
    canvas = document.createElement('canvas'); canvas.width = w; canvas.height = h;
    document.body.appendChild(canvas);
    engine = Filament.Engine.create(canvas, {alpha: true, premultipliedAlpha: false, preserveDrawingBuffer: true,
                                             antialias: false});
    gl = canvas.getContext('webgl2');
    swapChain = engine.createSwapChain(); renderer = engine.createRenderer(); loader = engine.createAssetLoader();
  }
  canvas.width = w; canvas.height = h;
  return engine;
}

export async function renderGltf(d) {
  const {width, height} = d.image;
  const opts = d.options || {};
  const eng = getEngine(width, height);
  const bytes = new Uint8Array(await (await fetch(d.glb)).arrayBuffer());
  const asset = loader.createAsset(bytes);
  await new Promise((res) => asset.loadResources(res, null, null, 1));
  const scene = eng.createScene(), view = eng.createView();
  scene.addEntities(asset.getEntities());
  const camEnts = asset.getCameraEntities();
  if (!camEnts.length) throw new Error(`${d.glb}: no camera`);
  const cam = eng.getCameraComponent(camEnts[0]);
  // gltfio 1.53.4 reads an orthographic camera's xmag/ymag as the full width/height (its projection scales x by
  // 2/xmag; glTF 2.0 §3.10.3: 1/xmag, xmag the half width): measured, the exported scenes came out at twice the
  // magnification. With options.orthoHalfExtent the page sets the projection glTF specifies, from the file's own
  // camera (d.camera: xmag, ymag, znear, zfar), and reports that it did.
  const orthoFixed = Boolean(opts.orthoHalfExtent && d.camera && d.camera.type === 'orthographic');
  if (orthoFixed) {
    const c = d.camera;
    cam.setProjection(Filament.Camera$Projection.ORTHO, -c.xmag, c.xmag, -c.ymag, c.ymag, c.znear, c.zfar);
  }
  view.setCamera(cam); view.setScene(scene);
  view.setViewport([0, 0, width, height]);
  view.setPostProcessingEnabled(false);
  if (opts.shadows) {
    const lm = eng.getLightManager(), rm = eng.getRenderableManager();
    for (const e of asset.getLightEntities()) lm.setShadowCaster(lm.getInstance(e), true);
    for (const e of asset.getRenderableEntities()) { const i = rm.getInstance(e); rm.setCastShadows(i, true); rm.setReceiveShadows(i, true); i.delete(); }
  }
  renderer.setClearOptions({clearColor: [0, 0, 0, 0], clear: true});
  const lights = [];
  const lm = eng.getLightManager();
  for (const e of asset.getLightEntities()) {
    const i = lm.getInstance(e);
    lights.push({intensity: lm.getIntensity(i), falloff: lm.getFalloff(i)});
  }
  const t0 = performance.now();
  const {exposure, px, drawn} = await exposeAndRead({renderer, swapChain, gl}, cam, view, eng, width, height);
  const frame_ms = performance.now() - t0;
  const projection = JSON.stringify(cam.getProjectionMatrix());
  scene.removeEntities(asset.getEntities()); loader.destroyAsset(asset);
  eng.destroyView(view); eng.destroyScene(scene);
  let s = ''; for (let i = 0; i < px.length; i += 0x8000) s += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
  return {data: btoa(s), encoding: 'unorm8_linear', exposure, frame_ms, version,
          info: {exposure, frames: drawn, max_lsb: maxColour(px), lights, projection, ortho_fixed: orthoFixed}};
}
