// (e) Filament shadows for a validate shadow scene (validate/scenes/render_shadow_scenes.py, the JSON's `shadow`),
// through filament_render.mjs (its page set-up, its lights in the same units — DIRECTIONAL lux, SPOT Φ = π·cd — its
// 8-bit canvas readback). What this build (npm filament 1.53.4, WebGL2) lets a page set, measured:
// * the light: LightManager.Builder.castShadows(true) works; its ShadowOptions cannot be set — Builder.shadowOptions
//   and LightManager.setShadowOptions both throw "UnboundTypeError: ... due to unbound types" (the ShadowOptions
//   value type is not bound in the wasm), so Filament's C++ defaults hold: mapSize 1024 (not the JSON's map_size:
//   three/Babylon use 512), one cascade, constantBias 0.001 m, normalBias 1.0, polygonOffset 0.5 + 2.0·slope,
//   LiSPSM on (filament.js's Filament.shadowOptions lists the same values). applyShadowOptions still tries
//   {mapSize: map_size} and reports the outcome (`shadow_options` of the page's info), so a build that binds it
//   uses 512.
// * the shadow type: View$ShadowType (PCF, VSM, DPCF, PCSS, PCFd) is bound but View has no setShadowType (nor
//   setSoftShadowOptions / setVsmShadowOptions: View.prototype lists only their *Defaults helpers), so only the
//   View's default, PCF, runs; another type goes through view.setShadowType where a build binds it, else it is
//   refused. PCSS's light size (ShadowOptions.shadowBulbRadius) is out of reach for the same reason.
// * the light frustum is Filament's own: it fits the shadow camera to the view frustum ∩ the shadow casters' and
//   receivers' bounds (the JSON's light_distance, ortho_half, near, far are three's and Babylon's only). Two
//   measured conditions for any shadow on the plane: the receiver must also be a caster (with only the box casting,
//   neither scene shows a shadow, even with the box in view), and its glTF bounds must not be flat (the plane's
//   z-extent 0: no shadow; ±RECEIVER_PAD_M in the accessor's min/max: the shadow appears). So the plane casts and
//   receives (self-shadowing held off by Filament's default biases: measured, the lit plane stays lit), the box
//   (a second gltfio asset, grey Lambertian) only casts.
// * the spot light casts no shadow from a caster outside the camera's view (measured: the scene's box at x = 1.4
//   casts nothing; the same box moved to (0.6, 0, 0.5), in view, casts, and so does the scene's own box when the
//   orthographic view is widened to ±2 m, which takes it in) — so Filament culls a spot light's shadow casters by the
//   camera's frustum, where its directional light keeps the out-of-view caster; the experiment keeps it as a
//   regression claim (filament.py defects["shadows.pcf.shadow_spot.umbra"]).

// the shadow-casting light's ShadowOptions ({mapSize: map_size}); returns 'applied' or why not (this build: unbound)
export function applyShadowOptions(eng, ent, sh) {
  const lm = eng.getLightManager(), inst = lm.getInstance(ent);
  try {
    lm.setShadowOptions(inst, {mapSize: sh.map_size});
    return 'applied';
  } catch (e) {
    return String(e).split('\n')[0].slice(0, 160);
  } finally {
    inst.delete();
  }
}

// 24 vertices (4 per face, its own normal), 12 triangles, positions baked at the box's centre
function boxMesh(center, size) {
  const pos = [], nrm = [], idx = [];
  for (let axis = 0; axis < 3; axis++) {
    for (const sgn of [-1, 1]) {
      const u = (axis + 1) % 3, v = (axis + 2) % 3, base = pos.length / 3;
      for (const [a, b] of [[-1, -1], [1, -1], [1, 1], [-1, 1]]) {
        const p = [0, 0, 0], n = [0, 0, 0];
        p[axis] = sgn; p[u] = a; p[v] = b; n[axis] = sgn;
        for (let k = 0; k < 3; k++) pos.push(center[k] + 0.5 * size[k] * p[k]);
        nrm.push(...n);
      }
      if (sgn > 0) idx.push(base, base + 1, base + 2, base, base + 2, base + 3);
      else idx.push(base, base + 2, base + 1, base, base + 3, base + 2);
    }
  }
  return {pos: new Float32Array(pos), nrm: new Float32Array(nrm), idx: new Uint32Array(idx)};
}

const GREY = {baseColor: [0.5, 0.5, 0.5], metallic: 0.0, roughness: 1.0, specular: 0.0};

// sets the shadows up: `receiver` = the plane's asset (already in `scene`), `glb` = filament_render's glTF writer;
// returns {finish()} that reports and undoes them
export async function addShadows(eng, scene, view, loader, receiver, sh, glb) {
  const settable = typeof view.setShadowType === 'function';
  if (sh.type !== 'pcf' && !settable) {
    throw new Error(`filament: shadow type ${sh.type}: this build's View has no setShadowType (PCF only)`);
  }
  if (settable) {
    const t = Filament.View$ShadowType[sh.type.toUpperCase()];
    if (t === undefined) throw new Error(`filament: shadow type ${sh.type} not in View$ShadowType`);
    view.setShadowType(t);
  }
  const rm = eng.getRenderableManager();
  const flags = (asset, cast, receive) => {
    for (const e of asset.getRenderableEntities()) {
      const inst = rm.getInstance(e);
      rm.setCastShadows(inst, cast); rm.setReceiveShadows(inst, receive);
      inst.delete();
    }
  };
  flags(receiver, true, true);  // the receiver must cast too (header)
  const boxes = [];
  for (const o of sh.occluders) {
    const a = loader.createAsset(glb(boxMesh(o.center, o.size), GREY, true));
    await new Promise((res) => a.loadResources(res, null, null, 1));
    flags(a, true, false);
    scene.addEntities(a.getEntities());
    boxes.push(a);
  }
  return {finish() {
    for (const a of boxes) { scene.removeEntities(a.getEntities()); loader.destroyAsset(a); }
    return {shadow_type_used: settable ? sh.type : 'pcf', shadow_type_settable: settable};
  }};
}
