// (e) three.js shadows for a validate shadow scene (validate/scenes/render_shadow_scenes.py, the JSON's `shadow`):
// renderer.shadowMap.type = Basic / PCF / PCFSoft / VSM (three 0.187: PCFSoftShadowMap was removed — WebGLShadowMap
// warns and switches the type to PCFShadowMap, reported back as `shadow_type_used`); the box occluders cast, the
// receiver only receives (no self-shadowing, three's default bias 0); the light's shadow camera is the scene's
// frustum (directional: orthographic ±ortho_half m from light_distance m along −direction; spot: its perspective
// camera, near/far). Everything else (mapSize from the JSON, radius 1, blurSamples 8) is three's default.
import * as THREE from 'three';

const TYPES = {basic: THREE.BasicShadowMap, pcf: THREE.PCFShadowMap, pcfsoft: THREE.PCFSoftShadowMap,
               vsm: THREE.VSMShadowMap};
const NAMES = new Map(Object.entries(TYPES).map(([k, v]) => [v, k]));

// sets the shadows up on `scene` (lights already added) and returns {finish()} that reports and undoes them
export function addShadows(renderer, scene, receiver, sh) {
  if (!(sh.type in TYPES)) throw new Error(`three: shadow type ${sh.type} not one of ${Object.keys(TYPES)}`);
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
  }
  return {finish() {
    const used = NAMES.get(renderer.shadowMap.type);
    for (const light of lights) { light.shadow.dispose(); }
    for (const b of boxes) { b.geometry.dispose(); b.material.dispose(); }
    renderer.shadowMap.enabled = false;
    return {shadow_type_used: used};
  }};
}
