// Filament (npm filament, WebAssembly + WebGL2) renders a validate render scene through its own pipeline: the
// geometry as a glTF 2.0 binary built here (a UV sphere of the scene's segments, or the plane z = 0, normal +z,
// doubleSided), loaded by gltfio's AssetLoader, whose built-in ubershader materials shade it
// (pbrMetallicRoughness; KHR_materials_ior ior = 1 → F0 = ((ior − 1)/(ior + 1))² = 0 and KHR_materials_specular
// factor 0: a Lambertian). Lights from LightManager in Filament's units: DIRECTIONAL intensity = lux; POINT / SPOT
// intensity = luminous power Φ in lm, which Filament (FLightManager::setIntensity) turns into candela I = Φ/(4π)
// for POINT and I = Φ/π for SPOT (the cone does not enter), so Φ = 4π·cd resp. π·cd is passed (measured: with
// 4π·cd the spot came out 3.95× too bright). falloff = FALLOFF_M: Filament windows the inverse square by
// (1 − (d/r)⁴)² (getSquareFalloffAttenuation), 1 − 6e-11 at d = 2.3 m, r = 1000 m. A SPOT's cone = KHR's half
// angles; Filament's attenuation saturate(cd·scale + offset)² is KHR's reference formula, with cos θ_i, cos θ_o
// from its fast::cos (FLightManager::setSpotLightCone). Camera: orthographic; exposure e (pre-exposed lights:
// output = e × radiance) picked from Filament's own frames so the image fills the 8-bit range (renderFilament),
// set as ISO (filament_frames.mjs). Post-processing off (no tone mapping, dithering, FXAA): the colour pass writes
// e × radiance straight into the canvas's RGBA8 (linear, no OETF: the swap chain is not sRGB; measured: at e = 1
// the directional sphere's peak ρE/π = 0.955 read 242–243 of 255), read back with the context's gl.readPixels
// (Filament's JS Renderer has no readPixels). Row 0 = bottom. (e) Shadow scenes: filament_shadows.mjs (the lights
// cast, the receiver's glTF bounds padded by RECEIVER_PAD_M).
import {addShadows, applyShadowOptions} from './filament_shadows.mjs';  // (e) shadows
import {exposeAndRead, maxColour} from './filament_frames.mjs';  // frames, readback, auto exposure

export let version = '';
let engine = null, renderer = null, swapChain = null, canvas = null, gl = null, loader = null;
export const FALLOFF_M = 1000.0;
export const RECEIVER_PAD_M = 1e-3;  // (e) filament_shadows.mjs
let shadowOptionsApplied = '';

export async function initFilament() {
  await new Promise((res) => Filament.init([], res));
  const pkg = await (await fetch('/node_modules/filament/package.json')).json();
  version = pkg.version;
}

function getEngine(w, h) {
  if (!engine) {
    canvas = document.createElement('canvas');
    canvas.width = w; canvas.height = h;
    document.body.appendChild(canvas);
    engine = Filament.Engine.create(canvas, {alpha: true, premultipliedAlpha: false, preserveDrawingBuffer: true,
                                             antialias: false});
    gl = canvas.getContext('webgl2');
    swapChain = engine.createSwapChain();
    renderer = engine.createRenderer();
    loader = engine.createAssetLoader();
  }
  canvas.width = w; canvas.height = h;
  return engine;
}

// ---- a glTF binary (glb) of the scene's geometry -------------------------------------------------------------
function sphereMesh(radius, nw, nh) {
  const pos = new Float32Array((nw + 1) * (nh + 1) * 3), nrm = new Float32Array(pos.length);
  let k = 0;
  for (let j = 0; j <= nh; j++) {
    const th = Math.PI * j / nh;
    for (let i = 0; i <= nw; i++, k += 3) {
      const ph = 2 * Math.PI * i / nw;
      const x = -Math.cos(ph) * Math.sin(th), y = Math.cos(th), z = Math.sin(ph) * Math.sin(th);
      nrm[k] = x; nrm[k + 1] = y; nrm[k + 2] = z;
      pos[k] = radius * x; pos[k + 1] = radius * y; pos[k + 2] = radius * z;
    }
  }
  const idx = [];
  for (let j = 0; j < nh; j++) for (let i = 0; i < nw; i++) {
    const a = j * (nw + 1) + i, b = a + nw + 1;
    if (j !== 0) idx.push(a, b, a + 1);
    if (j !== nh - 1) idx.push(a + 1, b, b + 1);
  }
  return {pos, nrm, idx: new Uint32Array(idx)};
}

function planeMesh(size) {
  const h = size / 2;
  const pos = new Float32Array([-h, -h, 0, h, -h, 0, h, h, 0, -h, h, 0]);
  const nrm = new Float32Array([0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1]);
  return {pos, nrm, idx: new Uint32Array([0, 1, 2, 0, 2, 3])};
}

function glb(mesh, m, doubleSided, pad = 0) {
  const bufs = [mesh.pos, mesh.nrm, mesh.idx];
  const views = [], chunks = [];
  let off = 0;
  for (const [i, b] of bufs.entries()) {
    views.push({buffer: 0, byteOffset: off, byteLength: b.byteLength, target: i < 2 ? 34962 : 34963});
    chunks.push(new Uint8Array(b.buffer, b.byteOffset, b.byteLength)); off += b.byteLength;
  }
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let k = 0; k < mesh.pos.length; k++) { lo[k % 3] = Math.min(lo[k % 3], mesh.pos[k]); hi[k % 3] = Math.max(hi[k % 3], mesh.pos[k]); }
  for (let k = 0; k < 3; k++) { lo[k] -= pad; hi[k] += pad; }  // (e) a flat receiver's bounds given a thickness
  const json = {
    asset: {version: '2.0', generator: 'validate'},
    extensionsUsed: ['KHR_materials_ior', 'KHR_materials_specular'],
    scene: 0, scenes: [{nodes: [0]}], nodes: [{mesh: 0, name: 'shape'}],
    meshes: [{primitives: [{attributes: {POSITION: 0, NORMAL: 1}, indices: 2, material: 0}]}],
    materials: [{pbrMetallicRoughness: {baseColorFactor: [...m.baseColor, 1], metallicFactor: m.metallic,
                                        roughnessFactor: m.roughness},
                 doubleSided,
                 extensions: {KHR_materials_ior: {ior: m.specular === 0 ? 1.0 : 1.5},
                              KHR_materials_specular: {specularFactor: m.specular}}}],
    accessors: [{bufferView: 0, componentType: 5126, count: mesh.pos.length / 3, type: 'VEC3', min: lo, max: hi},
                {bufferView: 1, componentType: 5126, count: mesh.nrm.length / 3, type: 'VEC3'},
                {bufferView: 2, componentType: 5125, count: mesh.idx.length, type: 'SCALAR'}],
    bufferViews: views, buffers: [{byteLength: off}],
  };
  let js = new TextEncoder().encode(JSON.stringify(json));
  const jsLen = (js.length + 3) & ~3, binLen = (off + 3) & ~3;
  const out = new Uint8Array(12 + 8 + jsLen + 8 + binLen);
  const dv = new DataView(out.buffer);
  dv.setUint32(0, 0x46546C67, true); dv.setUint32(4, 2, true); dv.setUint32(8, out.length, true);
  dv.setUint32(12, jsLen, true); dv.setUint32(16, 0x4E4F534A, true);
  out.fill(0x20, 20, 20 + jsLen); out.set(js, 20);
  let p = 20 + jsLen;
  dv.setUint32(p, binLen, true); dv.setUint32(p + 4, 0x004E4942, true); p += 8;
  for (const c of chunks) { out.set(c, p); p += c.length; }
  return out;
}

function addLight(eng, scene, l, shadow) {
  const LM = Filament.LightManager;
  const ent = Filament.EntityManager.get().create();
  let b;
  if (l.type === 'directional') {
    b = LM.Builder(LM$Type('DIRECTIONAL')).direction(l.direction).intensity(l.intensity);
  } else if (l.type === 'point') {
    b = LM.Builder(LM$Type('POINT')).position(l.position).intensity(4 * Math.PI * l.intensity).falloff(FALLOFF_M);
  } else if (l.type === 'spot') {
    b = LM.Builder(LM$Type('SPOT')).position(l.position).direction(l.direction)
      .intensity(Math.PI * l.intensity).falloff(FALLOFF_M)
      .spotLightCone(l.inner_deg * Math.PI / 180, l.outer_deg * Math.PI / 180);
  } else throw new Error(`filament: light type ${l.type} not rendered`);
  const casts = Boolean(shadow) && l.type !== 'point';  // (e) the shadow scenes' directional or spot light
  b.color(l.color).castShadows(casts).build(eng, ent);
  if (casts) shadowOptionsApplied = applyShadowOptions(eng, ent, shadow);
  scene.addEntity(ent);
  return ent;
}
const LM$Type = (n) => Filament.LightManager$Type[n];

export async function renderFilament(d) {
  const {width, height} = d.image;
  const opts = d.options || {};
  const eng = getEngine(width, height);
  const scene = eng.createScene();
  const view = eng.createView();
  const camEnt = Filament.EntityManager.get().create();
  const cam = eng.createCamera(camEnt);
  const e = d.camera.half_extent;
  cam.setProjection(Filament.Camera$Projection.ORTHO, -e, e, -e, e, 0.1, 100.0);
  cam.lookAt(d.camera.position, d.camera.target, d.camera.up);
  view.setCamera(cam); view.setScene(scene);
  view.setViewport([0, 0, width, height]);
  view.setPostProcessingEnabled(false);
  renderer.setClearOptions({clearColor: [0, 0, 0, 0], clear: true});
  const g = d.geometry;
  const mesh = g.type === 'plane' ? planeMesh(g.size) : sphereMesh(g.radius, g.segments[0], g.segments[1]);
  const asset = loader.createAsset(glb(mesh, d.material, g.type === 'plane', d.shadow ? RECEIVER_PAD_M : 0));
  await new Promise((res) => asset.loadResources(res, null, null, 1));
  scene.addEntities(asset.getEntities());
  const lights = d.lights.map((l) => addLight(eng, scene, l, d.shadow));
  const shadows = d.shadow ? await addShadows(eng, scene, view, loader, asset, d.shadow, glb) : null;  // (e)
  const t0 = performance.now();
  const {exposure, px, drawn} = await exposeAndRead({renderer, swapChain, gl}, cam, view, eng, width, height,
                                                  opts.exposure);
  const frame_ms = performance.now() - t0;
  const camInfo = {aperture: cam.getAperture(), shutter: cam.getShutterSpeed(), iso: cam.getSensitivity()};
  const shadowInfo = shadows ? {...shadows.finish(), shadow_options: shadowOptionsApplied} : {};
  scene.removeEntities(asset.getEntities()); loader.destroyAsset(asset);
  for (const l of lights) { scene.remove(l); eng.destroyEntity(l); }
  eng.destroyView(view); eng.destroyScene(scene); eng.destroyCameraComponent(camEnt);
  let s = ''; for (let i = 0; i < px.length; i += 0x8000) s += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
  return {data: btoa(s), encoding: 'unorm8_linear', exposure, frame_ms, version,
          info: {exposure, frames: drawn, max_lsb: maxColour(px), ...camInfo, ...shadowInfo}};
}
