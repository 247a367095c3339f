// (e) Babylon.js shadows for a validate shadow scene (validate/scenes/render_shadow_scenes.py, the JSON's `shadow`):
// one ShadowGenerator(map_size) per directional or spot light with the box occluders as casters and the receiver
// receiving: `pcf` usePercentageCloserFiltering (filteringQuality QUALITY_HIGH, its default), `pcss`
// useContactHardeningShadow (Babylon's PCSS; contactHardeningLightSizeUVRatio 0.1, its default), `esm`
// useExponentialShadowMap (depthScale 50), `blur_esm` useBlurExponentialShadowMap; bias 5e-5 (default). The light
// frustum is the scene's: directional at light_distance m along −direction, autoUpdateExtends off, ortho ±ortho_half
// with shadowOrthoScale 0 (so the projection is exactly that); shadowMinZ/MaxZ = near/far.
import * as BABYLON from '../../../node_modules/@babylonjs/core/index.js';

const TYPES = {pcf: 'usePercentageCloserFiltering', pcss: 'useContactHardeningShadow',
               esm: 'useExponentialShadowMap', blur_esm: 'useBlurExponentialShadowMap'};

export function addShadows(scene, receiver, sh) {
  if (!(sh.type in TYPES)) throw new Error(`babylon: shadow type ${sh.type} not one of ${Object.keys(TYPES)}`);
  const boxes = sh.occluders.map((o, k) => {
    const b = BABYLON.MeshBuilder.CreateBox(`occluder${k}`, {width: o.size[0], height: o.size[1], depth: o.size[2]},
                                            scene);
    b.position = new BABYLON.Vector3(...o.center); return b;
  });
  const gens = [];
  for (const light of scene.lights) {
    const dirLight = light instanceof BABYLON.DirectionalLight;
    if (!dirLight && !(light instanceof BABYLON.SpotLight)) continue;
    if (dirLight) {
      light.position = light.direction.normalizeToNew().scale(-sh.light_distance);
      light.autoUpdateExtends = false; light.shadowOrthoScale = 0;
      light.orthoLeft = -sh.ortho_half; light.orthoRight = sh.ortho_half;
      light.orthoTop = sh.ortho_half; light.orthoBottom = -sh.ortho_half;
    }
    light.shadowMinZ = sh.near; light.shadowMaxZ = sh.far;
    const g = new BABYLON.ShadowGenerator(sh.map_size, light);
    for (const b of boxes) g.addShadowCaster(b);
    g[TYPES[sh.type]] = true;
    gens.push(g);
  }
  receiver.receiveShadows = true;
  return {
    // the shadow maps are render targets of the scene's frame; `rt` is drawn alone, so they are drawn first, here
    async prepare() {
      await scene.whenReadyAsync();
      for (const g of gens) g.getShadowMap().render();
    },
    finish() {
      const used = gens.map((g) => Object.entries(TYPES).filter(([, p]) => g[p]).map(([k]) => k).join('+'));
      for (const g of gens) g.dispose();
      for (const b of boxes) b.dispose();
      return {shadow_type_used: used.join(',')};
    },
  };
}
