// (e) three.js shadows for a validate shadow scene (validate/scenes/render_shadow_scenes.py, the JSON's `shadow`):
// renderer.shadowMap.type = Basic / PCF / PCFSoft / VSM (three 0.187: PCFSoftShadowMap was removed — WebGLShadowMap
// warns and switches the type to PCFShadowMap, reported back as `shadow_type_used`); the box occluders cast, the
// receiver has castShadow = false, three's default bias 0; the light's shadow camera is the scene's frustum
// (directional: orthographic ±ortho_half m from light_distance m along −direction; spot: its perspective camera,
// near/far). Everything else (mapSize from the JSON, radius 1, blurSamples 8) is three's default.
//
// VSM renders the receiver into its map all the same: WebGLShadowMap.renderObject draws every mesh with
// `castShadow || (receiveShadow && type === VSMShadowMap)`, so under VSM the plane shadows itself at bias 0 against
// its own blurred moments, which three stores as RG16F (HalfFloatType, rounded twice: mapPass after the vertical blur,
// map after the horizontal). Where the stored mean rounds below the fragment's float depth (by up to ~1.6 × half a
// half-float ulp, 2.4e-4 at depth ∈ [0.5, 1)) the hard test fails and Chebyshev's bound with three's light-bleeding
// remap, clamp((σ²/(σ² + d²) − 0.3)/0.65, 0, 1) with σ ≈ 6e-4, darkens the pixel: s down to 0.89 at 64², in whole
// columns, because the plane's light-space depth varies along one shadow-map axis only. Diagnosis in
// docs/experiments/renders.md ("three.js VSM columns"), scripts/diagnose_renders/vsm.py.
//
// `sh.diag` (diagnosis only; no run sets it, and without it nothing here differs): radius, blurSamples, bias override
// three's; excludeReceiver keeps the receiver out of the shadow map (the shadow cameras see layer 1, which only the
// boxes join); floatMoments re-allocates VSM's two targets as RG32F; dump returns the first light's shadow map
// (RGBA float32, row 0 = bottom) as `moments`.
import * as THREE from 'three';
import {f32ToB64} from './common.mjs';

const TYPES = {basic: THREE.BasicShadowMap, pcf: THREE.PCFShadowMap, pcfsoft: THREE.PCFSoftShadowMap,
               vsm: THREE.VSMShadowMap};
const NAMES = new Map(Object.entries(TYPES).map(([k, v]) => [v, k]));

// sets the shadows up on `scene` (lights already added) and returns {finish()} that reports and undoes them
export function addShadows(renderer, scene, receiver, sh) {
  if (!(sh.type in TYPES)) throw new Error(`three: shadow type ${sh.type} not one of ${Object.keys(TYPES)}`);
  const dg = sh.diag || {};
  renderer.shadowMap.enabled = true;
  renderer.shadowMap.type = TYPES[sh.type];
  renderer.shadowMap.needsUpdate = true;
  receiver.receiveShadow = true; receiver.castShadow = false;
  const boxes = sh.occluders.map((o) => {
    const m = new THREE.Mesh(new THREE.BoxGeometry(...o.size), new THREE.MeshStandardMaterial());
    m.position.set(...o.center); m.castShadow = true; m.receiveShadow = false; scene.add(m); return m;
  });
  const lights = [];
  scene.traverse((obj) => { if (obj.isDirectionalLight || obj.isSpotLight) lights.push(obj); });
  for (const light of lights) {
    light.castShadow = true;
    const s = light.shadow, cam = s.camera;
    s.mapSize.set(sh.map_size, sh.map_size);
    if (light.isDirectionalLight) {
      const dir = new THREE.Vector3().subVectors(light.target.position, light.position).normalize();
      light.position.copy(light.target.position).addScaledVector(dir, -sh.light_distance);
      cam.left = -sh.ortho_half; cam.right = sh.ortho_half; cam.top = sh.ortho_half; cam.bottom = -sh.ortho_half;
    }
    cam.near = sh.near; cam.far = sh.far; cam.updateProjectionMatrix();
    if (dg.radius !== undefined) s.radius = dg.radius;
    if (dg.blurSamples !== undefined) s.blurSamples = dg.blurSamples;
    if (dg.bias !== undefined) s.bias = dg.bias;
    if (dg.excludeReceiver) cam.layers.set(1);
  }
  if (dg.excludeReceiver) for (const b of boxes) b.layers.enable(1);
  if (dg.floatMoments && renderer.shadowMap.type === THREE.VSMShadowMap) {
    // a throwaway frame makes three allocate its VSM targets (and records VSM as the previous type, so the real
    // frame's shadow pass keeps them); disposed, they are set up again from their textures' type on next use
    const rt = new THREE.WebGLRenderTarget(1, 1), prev = renderer.getRenderTarget();
    renderer.setRenderTarget(rt); renderer.render(scene, new THREE.OrthographicCamera()); renderer.setRenderTarget(prev);
    rt.dispose();
    for (const light of lights) {
      for (const t of [light.shadow.map, light.shadow.mapPass]) { t.texture.type = THREE.FloatType; t.dispose(); }
    }
    renderer.shadowMap.needsUpdate = true;
  }
  return {finish() {
    const out = {shadow_type_used: NAMES.get(renderer.shadowMap.type)};
    if (dg.dump && lights.length && lights[0].shadow.map) {
      const gl = renderer.getContext(), m = lights[0].shadow.map, buf = new Float32Array(m.width * m.height * 4);
      renderer.setRenderTarget(m);
      gl.readPixels(0, 0, m.width, m.height, gl.RGBA, gl.FLOAT, buf);
      renderer.setRenderTarget(null);
      out.moments = f32ToB64(buf);
    }
    for (const light of lights) { light.shadow.dispose(); }
    for (const b of boxes) { b.geometry.dispose(); b.material.dispose(); }
    renderer.shadowMap.enabled = false;
    return out;
  }};
}
