// three.js under test: LightProbeGenerator.fromCubeRenderTarget + SphericalHarmonics3.getIrradianceAt,
// unmodified, fed by a stand-in renderer that hands over the faces (the only renderer members the
// generator touches: isWebGLRenderer, coordinateSystem, readRenderTargetPixelsAsync).
import { FloatType, HalfFloatType, LinearSRGBColorSpace, REVISION, Vector3, WebGLCoordinateSystem } from 'three';
import { LightProbeGenerator } from 'three/addons/lights/LightProbeGenerator.js';

class FaceReadbackRenderer {
  constructor(faces) {
    this.isWebGLRenderer = true;
    this.coordinateSystem = WebGLCoordinateSystem;
    this.faces = faces;
  }

  // WebGLRenderer.readRenderTargetPixelsAsync(renderTarget, x, y, width, height, buffer, activeCubeFaceIndex)
  async readRenderTargetPixelsAsync(renderTarget, x, y, width, height, buffer, faceIndex) {
    buffer.set(this.faces[faceIndex]);
    return buffer;
  }
}

export function versions() {
  return { three: REVISION };
}

export async function project(faces, header) {
  const renderer = new FaceReadbackRenderer(faces);
  const target = {
    width: header.size,
    height: header.size,
    texture: { type: header.type === 'float16' ? HalfFloatType : FloatType, colorSpace: LinearSRGBColorSpace },
  };
  const probe = await LightProbeGenerator.fromCubeRenderTarget(renderer, target);
  return { probe, coefficients: { sh: probe.sh.coefficients.map((v) => [v.x, v.y, v.z]) } };
}

export function evaluate(state, path, normals, count) {
  if (path !== 'getIrradianceAt') throw new Error(`three: unknown path ${path}`);
  const out = new Float64Array(3 * count);
  const n = new Vector3();
  const e = new Vector3();
  for (let i = 0; i < count; i++) {
    n.set(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
    state.probe.sh.getIrradianceAt(n, e); // irradiance E (not E/π)
    out[3 * i] = e.x;
    out[3 * i + 1] = e.y;
    out[3 * i + 2] = e.z;
  }
  return out;
}
