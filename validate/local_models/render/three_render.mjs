// three.js renders a validate render scene through its own pipeline: MeshPhysicalMaterial (MeshStandardMaterial
// plus KHR_materials_specular's specularIntensity, 0 for a Lambertian), PMREMGenerator.fromEquirectangular on a
// float DataTexture, DirectionalLight in lux, PointLight / SpotLight in candela (physically based units, the default
// since r155; distance 0 = no range, decay 2 = inverse square; a KHR spot's cone as GLTFLoader maps it: angle =
// outer, penumbra = 1 − inner/outer), HemisphereLight (or a LightProbe, options.hemisphereProbe), a FloatType
// render target, NoToneMapping, LinearSRGBColorSpace; read back with readRenderTargetPixels (row 0 = bottom).
import * as THREE from 'three';
import {f32ToB64, environmentTexels} from './common.mjs';
import {renderFloat} from './three_target.mjs';
import {addShadows} from './three_shadows.mjs';  // (e) shadows
import {RectAreaLightUniformsLib} from '/node_modules/three/examples/jsm/lights/RectAreaLightUniformsLib.js';

let ltcReady = false;  // RectAreaLight's LTC tables (RectAreaLightUniformsLib.init, once per page)

export const version = THREE.REVISION;
let renderer = null;
const pmremCache = new Map();  // environment key -> PMREM render target (the prefilter runs once per environment)

function getRenderer(w, h) {
  if (!renderer) {
    const canvas = document.createElement('canvas');
    renderer = new THREE.WebGLRenderer({canvas, antialias: false, alpha: true});
    renderer.toneMapping = THREE.NoToneMapping;
    renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
  }
  renderer.setSize(w, h, false);
  return renderer;
}

function environment(r, env) {
  const t = environmentTexels(env);
  // three's equirect lookup puts v = 1 at the zenith; a DataTexture is not flipped, so row 0 must be the nadir
  const rows = new Float32Array(t.data.length), stride = 4 * t.width;
  for (let y = 0; y < t.height; y++) rows.set(t.data.subarray(y * stride, (y + 1) * stride), (t.height - 1 - y) * stride);
  const tex = new THREE.DataTexture(rows, t.width, t.height, THREE.RGBAFormat, THREE.FloatType);
  tex.mapping = THREE.EquirectangularReflectionMapping;
  tex.colorSpace = THREE.LinearSRGBColorSpace;
  tex.magFilter = THREE.LinearFilter; tex.minFilter = THREE.LinearFilter;
  tex.needsUpdate = true;
  const pmrem = new THREE.PMREMGenerator(r);
  const target = pmrem.fromEquirectangular(tex);
  pmrem.dispose(); tex.dispose();
  return target;
}

function material(m) {
  const c = new THREE.Color().setRGB(m.baseColor[0], m.baseColor[1], m.baseColor[2], THREE.LinearSRGBColorSpace);
  return new THREE.MeshPhysicalMaterial({color: c, metalness: m.metallic, roughness: m.roughness,
                                         specularIntensity: m.specular});
}

const rgb = (c) => new THREE.Color().setRGB(c[0], c[1], c[2], THREE.LinearSRGBColorSpace);

// A hemisphere of radiance sky (y > 0) / ground (y < 0). HemisphereLight's colours are the *irradiance* a full sky
// of them delivers (its shader adds mix(ground, sky, ½ + ½ n·up) · BRDF_Lambert, no π), so radiance L enters as
// colour L with intensity π (three PR 16271: "that factor of PI"). The probe path builds the SH of the radiance as
// three's HemisphereLightProbe did (r150 src/lights/HemisphereLightProbe.js: c0 = √π (sky + ground),
// c1 = √π √¾ (sky − ground) on the y band), intensity 1.
function hemisphere(l, probe) {
  if (!probe) return new THREE.HemisphereLight(rgb(l.sky), rgb(l.ground), Math.PI);
  const lp = new THREE.LightProbe();
  const c0 = Math.sqrt(Math.PI), c1 = c0 * Math.sqrt(0.75);
  const sky = new THREE.Vector3(...l.sky), ground = new THREE.Vector3(...l.ground);
  lp.sh.coefficients[0].copy(sky).add(ground).multiplyScalar(c0);
  lp.sh.coefficients[1].copy(sky).sub(ground).multiplyScalar(c1);
  return lp;
}

// returns the light's `power` getter (three's luminous power in lm) for point and spot lights, else null
function addLight(scene, l, opts) {
  if (l.type === 'hemisphere') { scene.add(hemisphere(l, opts.hemisphereProbe)); return null; }
  if (l.type === 'rect') {  // luminance in nits (RectAreaLight.intensity; its .power = π·w·h·intensity lm)
    if (!ltcReady) { RectAreaLightUniformsLib.init(); ltcReady = true; }
    const light = new THREE.RectAreaLight(rgb(l.color), l.intensity, l.width, l.height);
    light.position.set(...l.position); light.lookAt(...l.target); scene.add(light); return light.power;
  }
  if (l.type === 'point') {
    const light = new THREE.PointLight(rgb(l.color), l.intensity, 0, 2);
    light.position.set(...l.position); scene.add(light); return light.power;
  }
  if (l.type === 'spot') {
    const outer = l.outer_deg * Math.PI / 180, inner = l.inner_deg * Math.PI / 180;
    const light = new THREE.SpotLight(rgb(l.color), l.intensity, 0, outer, 1 - inner / outer, 2);
    light.position.set(...l.position); light.target.position.set(...l.target);
    scene.add(light); scene.add(light.target); return light.power;
  }
  const light = new THREE.DirectionalLight(rgb(l.color), l.intensity);
  light.position.set(-l.direction[0], -l.direction[1], -l.direction[2]);  // shines from position to target (origin)
  scene.add(light); scene.add(light.target);
  return null;
}

// One geometry per description for the page's life (never disposed): a 512 × 256 sphere takes ~0.2 s to build on
// SwiftShader's 2 cores and is the same vertex data every scene, so it is built and uploaded once.
const geometryCache = new Map();
function geometry(g) {
  const key = JSON.stringify(g);
  if (!geometryCache.has(key)) {
    geometryCache.set(key, g.type === 'plane' ? new THREE.PlaneGeometry(g.size, g.size)  // z = 0, normal +z
      : new THREE.SphereGeometry(g.radius, g.segments[0], g.segments[1]));
  }
  return geometryCache.get(key);
}

export async function renderThree(d) {
  const {width, height} = d.image;
  const r = getRenderer(width, height);
  const scene = new THREE.Scene();
  let pmrem_ms = 0;
  if (d.environment) {
    const key = d.environment.key;
    if (!pmremCache.has(key)) { const t = performance.now(); pmremCache.set(key, environment(r, d.environment)); pmrem_ms = performance.now() - t; }
    scene.environment = pmremCache.get(key).texture;
  }
  const opts = d.options || {};
  const powers = d.lights.map((l) => addLight(scene, l, opts));
  const g = d.geometry || {type: 'sphere', radius: d.sphere.radius, segments: d.sphere.segments};
  const mesh = new THREE.Mesh(geometry(g), material(d.material));
  scene.add(mesh);
  const shadows = d.shadow ? addShadows(r, scene, mesh, d.shadow) : null;  // (e) shadow scenes only
  const e = d.camera.half_extent;
  const cam = new THREE.OrthographicCamera(-e, e, e, -e, 0.1, 100);
  cam.position.set(...d.camera.position); cam.up.set(...d.camera.up); cam.lookAt(...d.camera.target);
  const {out, frame_ms} = renderFloat(r, scene, cam, width, height);
  mesh.material.dispose();  // the geometry stays cached (geometryCache)
  const shadowInfo = shadows ? shadows.finish() : {};
  return {data: f32ToB64(out), frame_ms, prefilter_ms: pmrem_ms, version, info: {light_power_lm: powers, ...shadowInfo}};
}
