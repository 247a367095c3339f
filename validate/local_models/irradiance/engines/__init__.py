"""Shipping engines under test: three.js and Babylon.js SH irradiance, run headless in Node.

Each engine's own, unmodified code runs in one Node process per engine (:mod:`.worker`, runner.mjs);
the faces it receives are rendered here from the same lat-long radiance the reference integrates
(:mod:`.cube_faces`, N = ``FACE_SIZE`` = 64 texels per edge, float32, texel-averaged: SH9 needs no
more — Babylon.js PR 18186 downsamples to 32–64 for the same reason — and it keeps the engines' cost
in a full ``sh9`` run to a few seconds; the ``engines`` experiment sweeps N = 16…256). Three
techniques of the ``irradiance`` family:

* ``three_sh`` — three.js r187: ``LightProbeGenerator.fromCubeRenderTarget`` [1] projects the faces
  onto 9 SH coefficients with texel weight w = 4/r³ (r = distance of the texel centre from the cube
  centre, r³ ∝ 1/dω per unit face area: the solid angle *approximated* at the texel centre),
  normalised so Σ w = 4π; ``SphericalHarmonics3.getIrradianceAt`` [2] returns
  E(n) = Σ_l A_l Σ_m L_lm Y_lm(n) (A_0 = π, A_1 = 2π/3, A_2 = π/4; R&H 2001 eq. 8) — irradiance E,
  not E/π.
* ``babylon_sh`` — Babylon.js 9.35: ``CubeMapToSphericalPolynomialTools.ConvertCubeMapToSphericalPolynomial``
  [3] weights each texel by its exact solid angle (atan2 area element), rescales to Σ Ω = 4π, clamps
  every channel to [0, MAX_HDRI_VALUE = 4096], convolves with A_l and divides by π; the default shader
  path (``SPHERICAL_HARMONICS``, useSphericalHarmonics = true) evaluates ``preScaledHarmonics`` [4]:
  E/π; the technique returns ×π.
* ``babylon_polynomial`` — the same projection, shader path useSphericalHarmonics = false: the
  spherical polynomial (x, y, z, xx − zz, yy − zz, zz, xy, yz, zx) [4, 5], ×π.

The faces each engine makes itself from a panorama (Babylon's PanoramaToCubeMapTools, three.js's equirect
shader transcribed) are in :mod:`.own_faces`; the ``engines`` experiment measures both face sources.

Conventions: faces in OpenGL's cube-map layout [6, Table 8.19], which both engines read (tested).
Babylon's world is left-handed; its axes are identified with Mitsuba's, i.e. the environment and
the normals are mirrored together — irradiance errors are invariant under that reflection (the SH
projection and the cosine kernel commute with orthogonal maps). Shader arithmetic is float32
(Math.fround); three.js's CPU ``getIrradianceAt`` is float64, as it runs.

Availability: the techniques are registered only when ``node`` is on PATH (or ``VALIDATE_NODE`` names
it; a path that does not exist turns the engines off) and ``python -m validate setup --engines`` has installed
``three`` and ``@babylonjs/core`` (:func:`validate.setup.paths.node_modules`). Importing starts no process; the first
call does, and that one process per engine serves every later call of the run. Without them nothing
is registered (the rest of the family and every other experiment are unchanged) and the ``engines``
experiment is skipped with the reason (:func:`.worker.unavailable_reason`).

References
  [1] three.js r187, examples/jsm/lights/LightProbeGenerator.js (fromCubeRenderTarget).
  [2] three.js r187, src/math/SphericalHarmonics3.js (getIrradianceAt, getBasisAt).
  [3] Babylon.js 9.35, Misc/HighDynamicRange/cubemapToSphericalPolynomial.ts.
  [4] Babylon.js 9.35, Shaders/ShadersInclude/harmonicsFunctions.fx; Materials/materialHelper.functions.ts
      (the uniforms bound for each path).
  [5] Babylon.js 9.35, Maths/sphericalPolynomial.ts (FromHarmonics, FromPolynomial, preScaledHarmonics).
  [6] M. Segal, K. Akeley, "The OpenGL Graphics System: A Specification (4.6 Core)", §8.13, Table 8.19.
  [7] R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
      SIGGRAPH 2001.
"""

from __future__ import annotations

import numpy as np

from ...families import irradiance as _irradiance
from .worker import FACE_SIZE, FaceSettings, engine_irradiance, unavailable_reason

ENGINE_TECHNIQUES = {  # technique → (engine process, evaluation path)
    "three_sh": ("three", "getIrradianceAt"),
    "babylon_sh": ("babylon", "sh"),
    "babylon_polynomial": ("babylon", "polynomial"),
}
DESCRIPTIONS = {
    "three_sh": "three.js r187 LightProbeGenerator + SphericalHarmonics3.getIrradianceAt (E)",
    "babylon_sh": "Babylon.js 9.35 spherical harmonics, preScaledHarmonics shader path (E/π × π)",
    "babylon_polynomial": "Babylon.js 9.35 spherical polynomial shader path (E/π × π)",
}


def _technique(name: str):  # noqa: ANN202 (returns the technique function)
    engine, path = ENGINE_TECHNIQUES[name]

    def fn(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
        return engine_irradiance(engine, path, radiance, normals, FaceSettings())

    fn.__name__ = fn.__qualname__ = name
    fn.__doc__ = f"{DESCRIPTIONS[name]}; faces {FACE_SIZE}² float32 rendered from the lat-long radiance."
    return fn


UNAVAILABLE = unavailable_reason()  # a file-system check only: no process is started here
if UNAVAILABLE is None:
    for _name in ENGINE_TECHNIQUES:
        _irradiance.register(_name, DESCRIPTIONS[_name], engine=ENGINE_TECHNIQUES[_name][0],
                             path=ENGINE_TECHNIQUES[_name][1], face_size=FACE_SIZE)(_technique(_name))

__all__ = ["DESCRIPTIONS", "ENGINE_TECHNIQUES", "FACE_SIZE", "UNAVAILABLE"]
