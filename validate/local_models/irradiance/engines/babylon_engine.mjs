// Babylon.js under test: CubeMapToSphericalPolynomialTools.ConvertCubeMapToSphericalPolynomial,
// unmodified, and the two shader paths of harmonicsFunctions.fx transcribed with float32 arithmetic:
//   "sh"          (SPHERICAL_HARMONICS, useSphericalHarmonics = true, the default): the uniforms
//                 vSphericalL00 … vSphericalL22 = polynomial.preScaledHarmonics;
//   "polynomial"  (useSphericalHarmonics = false): vSphericalX … vSphericalZX with
//                 vSphericalXX_ZZ = xx − zz and vSphericalYY_ZZ = yy − zz (materialHelper.functions.js).
// Both return E/π ("Lambertian radiance"); the caller multiplies by π.
import { CubeMapToSphericalPolynomialTools as Tools } from '@babylonjs/core/Misc/HighDynamicRange/cubemapToSphericalPolynomial.js';
import { PanoramaToCubeMapTools } from '@babylonjs/core/Misc/HighDynamicRange/panoramaToCubemap.js';
import { createRequire } from 'node:module';

const f = Math.fround;

export function versions() {
  const require = createRequire(import.meta.url);
  return { '@babylonjs/core': require('@babylonjs/core/package.json').version };
}

export async function project(faces, header) {
  if (header.type !== 'float32') throw new Error('babylon: faces must be float32 (cubeInfo.type = 1)');
  return fromCubeInfo({
    size: header.size, right: faces[0], left: faces[1], up: faces[2], down: faces[3], front: faces[4],
    back: faces[5], format: 5, type: 1, gammaSpace: false,
  }, header.clamp);
}

export const FACE_ORDER = ['right', 'left', 'up', 'down', 'front', 'back'];

// Babylon's own panorama path, as HDRCubeTexture / EquiRectangularCubeTexture run it on the CPU
// (hdr.js GetCubeMapTextureData): PanoramaToCubeMapTools.ConvertPanoramaToCubemap(data, width, height, size)
// with its defaults (supersample = false, invertY = true), then ConvertCubeMapToSphericalPolynomial(cubeInfo)
// (sphericalPolynomialTargetSize = 0: no downsampling). Returns the state and the six faces it made
// (RGB, in FACE_ORDER) so the caller can see what the engine integrated.
export async function projectPanorama(panorama, header) {
  const cube = PanoramaToCubeMapTools.ConvertPanoramaToCubemap(panorama, header.width, header.height, header.size);
  const n = header.size * header.size * 3;
  const faces = new Float32Array(6 * n);
  FACE_ORDER.forEach((name, i) => faces.set(cube[name], i * n));
  return { state: fromCubeInfo(cube, true), unclamped: fromCubeInfo(cube, false), faces };
}

function fromCubeInfo(cubeInfo, clamp) {
  const saved = Tools.MAX_HDRI_VALUE;
  if (clamp === false) Tools.MAX_HDRI_VALUE = Infinity;
  let poly;
  try {
    poly = Tools.ConvertCubeMapToSphericalPolynomial(cubeInfo);
  } finally {
    Tools.MAX_HDRI_VALUE = saved;
  }
  const h = poly.preScaledHarmonics;
  const v = (a) => [a.x, a.y, a.z];
  const sh = [h.l00, h.l1_1, h.l10, h.l11, h.l2_2, h.l2_1, h.l20, h.l21, h.l22].map((a) => v(a).map(f));
  const p = poly;
  const polynomial = {
    x: v(p.x), y: v(p.y), z: v(p.z), xx_zz: [0, 1, 2].map((c) => v(p.xx)[c] - v(p.zz)[c]),
    yy_zz: [0, 1, 2].map((c) => v(p.yy)[c] - v(p.zz)[c]), zz: v(p.zz), xy: v(p.xy), yz: v(p.yz), zx: v(p.zx),
  };
  for (const k of Object.keys(polynomial)) polynomial[k] = polynomial[k].map(f); // float32 uniforms
  return { sh, polynomial, coefficients: { preScaledHarmonics: sh, polynomial } };
}

function shPath(u, nx, ny, nz, c) {
  // vSphericalL00 + L1_1*y + L10*z + L11*x + L2_2*(y*x) + L2_1*(y*z) + L20*(3z²−1) + L21*(z*x) + L22*(x²−y²)
  let r = u[0][c];
  r = f(r + f(u[1][c] * ny));
  r = f(r + f(u[2][c] * nz));
  r = f(r + f(u[3][c] * nx));
  r = f(r + f(u[4][c] * f(ny * nx)));
  r = f(r + f(u[5][c] * f(ny * nz)));
  r = f(r + f(u[6][c] * f(f(f(3.0 * nz) * nz) - 1.0)));
  r = f(r + f(u[7][c] * f(nz * nx)));
  r = f(r + f(u[8][c] * f(f(nx * nx) - f(ny * ny))));
  return r;
}

function polynomialPath(p, nx, ny, nz, c) {
  // a1=Cyy_zz*Ny+Cy; a2=Cyz*Nz+a1; b1=Czx*Nz+Cx; b2=Cxy*Ny+b1; b3=Cxx_zz*Nx+b2;
  // t1=Cz*Nz+C1; t2=a2*Ny+t1; t3=b3*Nx+t2
  const a1 = f(f(p.yy_zz[c] * ny) + p.y[c]);
  const a2 = f(f(p.yz[c] * nz) + a1);
  const b1 = f(f(p.zx[c] * nz) + p.x[c]);
  const b2 = f(f(p.xy[c] * ny) + b1);
  const b3 = f(f(p.xx_zz[c] * nx) + b2);
  const t1 = f(f(p.z[c] * nz) + p.zz[c]);
  const t2 = f(f(a2 * ny) + t1);
  return f(f(b3 * nx) + t2);
}

export function evaluate(state, path, normals, count) {
  const out = new Float64Array(3 * count);
  for (let i = 0; i < count; i++) {
    const nx = f(normals[3 * i]);
    const ny = f(normals[3 * i + 1]);
    const nz = f(normals[3 * i + 2]);
    for (let c = 0; c < 3; c++) {
      let r;
      if (path === 'sh') r = shPath(state.sh, nx, ny, nz, c);
      else if (path === 'polynomial') r = polynomialPath(state.polynomial, nx, ny, nz, c);
      else throw new Error(`babylon: unknown path ${path}`);
      out[3 * i + c] = r * Math.PI; // the shader's E/π → E
    }
  }
  return out;
}
