"""Each engine's own path from a lat-long panorama to the cube faces it projects (issue 21 item 5).

The suite's faces (:mod:`.cube_faces`) hold each texel's *average* radiance; a user hands an engine the
panorama and the engine makes its own faces:

* **Babylon.js** (CPU, its own code, run in Node): ``HDRCubeTexture`` → ``hdr.js GetCubeMapTextureData`` →
  ``PanoramaToCubeMapTools.ConvertPanoramaToCubemap(data, width, height, size)`` with its defaults
  (``supersample = false``, ``invertY = true``) — one *nearest* panorama pixel per face texel
  (``Math.round`` of the texel's (θ, φ)), the sample taken at the texel's corner (``fy = y/size``,
  ``xv1 = corner + x·Δ``) — then ``ConvertCubeMapToSphericalPolynomial(cubeInfo)`` on exactly those faces
  (its 4096 clamp included). The panorama is handed over as float32 RGB, rows top first, as
  ``RGBE_ReadPixels`` decodes a .hdr file (the RGBE quantisation of a file is not applied: the suite's maps
  are already float).
* **three.js**: no CPU path exists — ``WebGLCubeRenderTarget.fromEquirectangularTexture`` renders a box with
  the fragment shader ``texture2D(tEquirect, equirectUv(normalize(vWorldDirection)))`` through a
  ``CubeCamera`` on the GPU. :func:`three_equirect_faces` is a numpy *transcription* of that shader, not
  three.js's code: ``equirectUv(d) = (atan(d.z, d.x)/2π + ½, asin(d.y)/π + ½)`` evaluated at every fragment
  centre (the cube texel centre), sampled with ``LinearFilter`` (the HDRLoader/EXRLoader default, no mipmaps:
  GL_LINEAR, texel centres at ((j + ½)/W, (i + ½)/H)) and ``ClampToEdgeWrapping`` (a DataTexture's default; the
  seam is not wrapped), rows as HDRLoader uploads them (``flipY = true``: the panorama's top row at v = 1), into
  a float32 target (three's HDRLoader default is HalfFloatType; float32 isolates the sampling). A GPU's 8-bit
  sub-texel weights are not modelled (float64 weights). The faces then go through three.js's own
  ``LightProbeGenerator.fromCubeRenderTarget`` as usual.

Orientation. Neither path's world axes need to agree with Mitsuba's: each engine's field is the panorama's up
to an orthogonal map A (L_engine(w) = L_map(A w)), measured by :func:`orientation` from the engine's own
pipeline — a panorama whose RGB is 2 + d (d the Mitsuba direction of each pixel, :func:`latlong.texel_directions`)
gives E_c(w) = 2π + (2π/3)(A w)_c exactly (SH9 is exact on bands ≤ 1), so A_ck = (E_c(e_k) − E_c(−e_k))/(4π/3).
A is rounded to the signed permutation it must be (both engines relabel cube axes) and the raw fit is kept for
the check. The engine is then asked at w = Aᵀn for the normal n; irradiance is invariant under A (the SH
projection and the cosine kernel commute with orthogonal maps).
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

from ....errors import ValidateError
from ....geometry import cube_texel_directions
from ....scenes import latlong
from . import worker

BABYLON_ORDER = ("right", "left", "up", "down", "front", "back")  # = +X, −X, +Y, −Y, +Z, −Z as Babylon reads them
ORIENTATION_MAP = (64, 128)  # (H, W) of the direction-encoding panorama of :func:`orientation`
PATHS = {"three": "getIrradianceAt", "babylon": "sh"}


def three_equirect_faces(radiance: np.ndarray, size: int) -> np.ndarray:
    """three.js's equirect→cube fragment shader transcribed (module docstring): (6, N, N, 3) float32 in the
    layout ``LightProbeGenerator`` reads (OpenGL cube-map order, texel centres)."""
    h, w = radiance.shape[:2]
    d = cube_texel_directions(size)
    u = np.arctan2(d[..., 2], d[..., 0]) / (2.0 * np.pi) + 0.5
    v = np.arcsin(np.clip(d[..., 1], -1.0, 1.0)) / np.pi + 0.5
    x = u * w - 0.5
    y = (1.0 - v) * h - 0.5  # flipY: texture row from the top = file row
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    xi0, xi1 = np.clip(x0, 0, w - 1).astype(np.int64), np.clip(x0 + 1, 0, w - 1).astype(np.int64)
    yi0, yi1 = np.clip(y0, 0, h - 1).astype(np.int64), np.clip(y0 + 1, 0, h - 1).astype(np.int64)
    r = radiance
    top = r[yi0, xi0] * (1 - fx) + r[yi0, xi1] * fx
    bot = r[yi1, xi0] * (1 - fx) + r[yi1, xi1] * fx
    return (top * (1 - fy) + bot * fy).astype(np.float32)


def babylon_panorama(radiance: np.ndarray, size: int, clamp: bool = True) -> tuple[str, np.ndarray]:
    """Babylon's own panorama → faces → spherical polynomial (one request projects with and without the clamp);
    returns the Node key of the one asked for and the faces (6, N, N, 3) float32 in +X, −X, +Y, −Y, +Z, −Z order
    (the order and texel layout its projection reads)."""
    pano = np.ascontiguousarray(radiance, dtype=np.float32)
    key = f"pano:{worker.radiance_digest(pano)}:{size}"
    w = worker.worker("babylon")
    cached = _BABYLON_FACES.get(key)
    if key not in w.keys or cached is None:
        reply, body = w.request({"op": "project_panorama", "key": key, "width": int(pano.shape[1]),
                                 "height": int(pano.shape[0]), "size": int(size)}, pano.tobytes())
        w.keys[key] = reply["coefficients"]
        cached = np.frombuffer(body, dtype=np.float32).reshape(6, size, size, 3).copy()
        _BABYLON_FACES[key] = cached
        while len(_BABYLON_FACES) > 2 * worker.FACE_CACHE:
            _BABYLON_FACES.pop(next(iter(_BABYLON_FACES)))
    return (key if clamp else f"{key}:unclamped"), cached


_BABYLON_FACES: dict[str, np.ndarray] = {}


def own_faces(engine: str, radiance: np.ndarray, size: int) -> np.ndarray:
    """The faces the engine itself makes from the panorama (engine frame, OpenGL layout), (6, N, N, 3) float32."""
    if engine == "babylon":
        return babylon_panorama(radiance, size)[1]
    if engine == "three":
        return three_equirect_faces(radiance, size)
    raise ValidateError(f"own faces: unknown engine {engine!r}")


def _raw_irradiance(engine: str, radiance: np.ndarray, w_dirs: np.ndarray, size: int, clamp: bool) -> np.ndarray:
    """The engine's E at engine-frame directions ``w_dirs`` (no orientation applied)."""
    if engine == "babylon":
        key, _ = babylon_panorama(radiance, size, clamp)
        return worker.evaluate("babylon", key, PATHS[engine], w_dirs)
    faces = three_equirect_faces(radiance, size)
    key, _ = worker.project("three", faces, worker.FaceSettings(size=size), faces=faces)
    return worker.evaluate("three", key, PATHS[engine], w_dirs)


@functools.lru_cache(maxsize=8)
def orientation(engine: str, size: int = worker.FACE_SIZE) -> tuple[np.ndarray, float]:
    """(A, fit error): the signed permutation A with L_engine(w) = L_map(A w), and max |A_raw − A| of the raw
    fit (module docstring); a fit that is not a signed permutation to within 0.1 is an error."""
    h, w = ORIENTATION_MAP
    pano = (2.0 + latlong.texel_directions(h, w)).astype(np.float32)
    axes = np.concatenate([np.eye(3), -np.eye(3)])
    e = _raw_irradiance(engine, pano, axes, size, clamp=True)
    raw = ((e[:3] - e[3:]) / (4.0 * np.pi / 3.0)).T  # raw[c, k] = (A e_k)_c
    a = np.round(raw)
    fit = float(np.max(np.abs(raw - a)))
    if fit > 0.1 or not np.allclose(np.abs(a).sum(axis=0), 1) or not np.allclose(np.abs(a).sum(axis=1), 1):
        raise ValidateError(f"own faces: {engine}'s orientation fit {raw.round(3).tolist()} is not a signed "
                            "permutation")
    return a, fit


def own_irradiance(engine: str, radiance: np.ndarray, normals: np.ndarray, size: int = worker.FACE_SIZE,
                   clamp: bool = True) -> np.ndarray:
    """E (N, 3) at Mitsuba-frame ``normals`` from the engine's own faces and projection, asked at w = Aᵀn."""
    a, _ = orientation(engine, size)
    return _raw_irradiance(engine, radiance, np.asarray(normals, dtype=np.float64) @ a, size, clamp)


def to_engine_frame(engine: str, normals: np.ndarray, size: int = worker.FACE_SIZE) -> np.ndarray:
    """w = Aᵀn for each row n (the engine-frame direction of a Mitsuba-frame normal)."""
    return np.asarray(normals, dtype=np.float64) @ orientation(engine, size)[0]


def describe() -> dict[str, Any]:
    return {"babylon": "PanoramaToCubeMapTools.ConvertPanoramaToCubemap (nearest pixel at texel corners) → "
                       "ConvertCubeMapToSphericalPolynomial (Babylon's code)",
            "three": "fromEquirectangularTexture's fragment shader transcribed (bilinear at texel centres) → "
                     "LightProbeGenerator (three's code)"}


__all__ = ["BABYLON_ORDER", "PATHS", "babylon_panorama", "describe", "orientation", "own_faces", "own_irradiance",
           "three_equirect_faces", "to_engine_frame"]
