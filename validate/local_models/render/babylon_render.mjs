// Babylon.js renders a validate render scene through its own pipeline: PBRMaterial (metallic-roughness;
// metallicF0Factor = KHR_materials_specular's factor, 0 for a Lambertian), HDRCubeTexture on the scene's .hdr
// file (its RGBE loader, panorama-to-cube, spherical polynomial for diffuse, HDRFiltering prefilter for
// specular), DirectionalLight in lux, PointLight / SpotLight in candela with falloffType = FALLOFF_GLTF (inverse
// square without range; a KHR spot as Babylon's glTF loader maps it: angle = 2·outer, innerAngle = 2·inner),
// HemisphericLight, RectAreaLight (below), a TEXTURETYPE_FLOAT RenderTargetTexture read back with readPixels.
// RectAreaLight: Babylon's own shader (ltcHelperFunctions, pbrDirectLightingFunctions computeAreaDiffuseLighting)
// with Heitz et al. 2016's GGX LTC tables as three.js ships them (RectAreaLightTexturesLib LTC_MAT_1 / LTC_MAT_2,
// from selfshadow/ltc_code fit/results/ltc.js): Babylon 9.35's own areaLightsLTC.bin comes from assets.babylonjs.com
// and is not obtainable offline. Babylon 9.35 has no public LTC provider (the `scene.areaLightLTCProvider` of PR
// 16078's description is not in the package): AreaLight's constructor creates and fetches the tables only when
// `scene._ltcTextures` (areaLight.types.d.ts, @internal) is unset, so the tables are put there first, as the
// textures Babylon itself makes (RGBA half float, bilinear, clamped; CreateSceneLTCTextures).
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
function addLight(scene, l, opts = {}) {
  let light;
  if (l.type === 'rect') return rectLight(scene, l, opts);
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

export const LTC_LABEL = "Babylon's RectAreaLight shader with Heitz's tables (Babylon's own areaLightsLTC.bin is not " +
  'obtainable offline)';
const ltcData = new Map();  // table name -> [LTC1, LTC2] half floats (Uint16Array(64·64·4) each)
// The channel layout Babylon's shader reads (ltcHelperFunctions computeAreaLightSpecularDiffuseFresnel):
// LTC1 = t1 with mInv = mat3(vec3(t1.x, 0, t1.y), vec3(0, 1, 0), vec3(t1.z, 0, t1.w)), i.e. t1 = (m[0][0], m[0][2],
// m[2][0], m[2][2]) in GLSL's m[column][row] (selfshadow's packTab order), and LTC2 = t2 = (magnitude, Fresnel, 0,
// sphere) in pbrDirectLightingFunctions computeAreaSpecularLighting: specularColor·t2.x·R0 + (1 − specularColor)·
// t2.y·R90 (specularColor = the light's: white drops the t2.y term); uv = (roughness, √(1 − N·V))·63/64 + 0.5/64
// (LTCUv). three.js's lights_physical_pars_fragment reads LTC_FLOAT_1 / LTC_FLOAT_2 with the same matrix, the
// same uv and the same (x, y) Fresnel pair, so three's arrays go in unchanged. 'constant' (a sanity check only): mInv = I, t2 = (1, 1,
// 0, 1) at every texel — a table that is wrong everywhere.
async function ltcTables(name) {
  if (ltcData.has(name)) return ltcData.get(name);
  let f1, f2;
  if (name === 'constant') {
    f1 = new Float32Array(64 * 64 * 4); f2 = new Float32Array(64 * 64 * 4);
    for (let i = 0; i < 64 * 64; i++) { f1.set([1, 0, 0, 1], 4 * i); f2.set([1, 1, 0, 1], 4 * i); }
  } else {
    const {RectAreaLightTexturesLib} = await import('/node_modules/three/examples/jsm/lights/RectAreaLightTexturesLib.js');
    RectAreaLightTexturesLib.init();
    f1 = RectAreaLightTexturesLib.LTC_FLOAT_1.image.data; f2 = RectAreaLightTexturesLib.LTC_FLOAT_2.image.data;
  }
  const half = (f) => Uint16Array.from(f, (x) => BABYLON.ToHalfFloat(x));  // as Babylon's LTC tool encoded its .bin
  ltcData.set(name, [half(f1), half(f2)]);
  return ltcData.get(name);
}

function ltcTexture(scene, data) {
  const t = BABYLON.RawTexture.CreateRGBATexture(data, 64, 64, scene, false, false, BABYLON.Texture.BILINEAR_SAMPLINGMODE,
                                                 BABYLON.Constants.TEXTURETYPE_HALF_FLOAT);
  t.wrapU = BABYLON.Texture.CLAMP_ADDRESSMODE; t.wrapV = BABYLON.Texture.CLAMP_ADDRESSMODE;
  return t;
}

// A one-sided rectangle of radiance l.intensity (nits) centred at l.position facing l.target. Babylon's units: its
// photometric scale for LIGHTTYPEID_RECT_AREALIGHT is 1 ("area lights interpret their intensity directly",
// light.js _getPhotometricScale), vLightDiffuse = diffuse · intensity, and the diffuse term is
// areaLightDiffuse · vLightDiffuse with areaLightDiffuse = LTCEvaluate(identity) = the rectangle's form factor
// (1 for a whole hemisphere): the outgoing Lambertian radiance is albedo · F · intensity, so intensity is the
// emitted radiance (per unit area and solid angle), the scene's nits unchanged. The rectangle spans ±width/2 along
// the light's local x and ±height/2 along y and emits towards local −z (rectAreaLight.js: corners position ±
// halfWidth ± halfHeight; lit where dot(cross(c1 − c0, c3 − c0), P − c0) ≥ 0); a parent TransformNode at
// l.position carries three's Object3D.lookAt frame for a light: z = normalize(position − target),
// x = normalize(up × z) (up +y), y = z × x.
async function rectLight(scene, l, opts) {
  const [d1, d2] = await ltcTables(opts.ltcTable || 'heitz');
  scene._ltcTextures = {LTC1: ltcTexture(scene, d1), LTC2: ltcTexture(scene, d2)};
  const z = v3(l.position).subtract(v3(l.target)).normalize();
  const x = BABYLON.Vector3.Cross(new BABYLON.Vector3(0, 1, 0), z).normalize();
  const y = BABYLON.Vector3.Cross(z, x);
  const frame = new BABYLON.TransformNode('rectFrame', scene);
  frame.position = v3(l.position);
  frame.rotationQuaternion = BABYLON.Quaternion.RotationQuaternionFromAxis(x, y, z);
  const light = new BABYLON.RectAreaLight('rect', BABYLON.Vector3.Zero(), l.width, l.height, scene);
  light.parent = frame;
  light.intensity = l.intensity; light.diffuse = rgb(l.color); light.specular = rgb(l.color);
  frame.computeWorldMatrix(true);
  light._computeTransformedInformation();
  const c = light._pointTransformedPosition, hw = light._pointTransformedWidth.scale(0.5),
        hh = light._pointTransformedHeight.scale(0.5);
  // the corners the shader builds (c0 = p + hw − hh, c1 = p − hw − hh, c2 = p − hw + hh, c3 = p + hw + hh)
  const corners = [[1, -1], [-1, -1], [-1, 1], [1, 1]].map(([a, b]) => c.add(hw.scale(a)).add(hh.scale(b)).asArray());
  return {ltc_tables: opts.ltcTable === 'constant' ? 'constant (sanity check: mInv = I, t2 = (1, 1, 0, 1))'
            : LTC_LABEL, rect_corners: corners, intensity: light.getScaledIntensity()};
}

export async function renderBabylon(d) {
  const eng = getEngine();
  const {width, height} = d.image;
  const opts = d.options || {};
  const scene = linearScene(eng);  // linear output (babylon_scene.mjs)
  let prefilter_ms = 0;
  if (d.environment) {
    const e = await environment(scene, d.environment, opts.cubeSize || 128, opts);
    // the texture belongs to the first scene that loaded it; later scenes share it
    scene.environmentTexture = e.tex; prefilter_ms = e.ms; e.ms = 0;
  }
  const lightInfo = [];
  for (const l of d.lights) { const i = await addLight(scene, l, opts); if (i) lightInfo.push(i); }
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
  if (lightInfo.length) shadowInfo.lights = lightInfo;  // (d) RectAreaLight: its tables, corners, intensity
  rt.dispose(); sphere.material.dispose(); sphere.dispose();
  if (scene.environmentTexture) scene.environmentTexture = null;  // keep the cached texture alive
  return {data: f32ToB64(out), frame_ms, prefilter_ms, version, info: shadowInfo};
}
import {f32ToB64} from './common.mjs';
import {addShadows} from './babylon_shadows.mjs';  // (e) shadows
import {linearScene} from './babylon_scene.mjs';
import {cdfCubeTexture, cdfInfo, cdfKey} from './babylon_cdf.mjs';  // (b) CDF irradiance
