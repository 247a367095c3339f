"""Phong-prefiltered specular maps and the seed's mixing shader.

A specular map of Phong exponent s stores, per direction r, the environment filtered by the
*normalised Phong lobe* around r [1, 2, 3]:

    P_s(r) = ∫_{S²} L(ω) K_s(r·ω) dω,        K_s(c) = (s + 1)/(2π) · max(0, c)^s,   ∫ K_s dω = 1,

and shading looks it up at the reflection vector r = 2(n·v)n − v. It is built by brute-force
convolution of the lat-long texels (:func:`validate.local_models.irradiance.irradiance_map.convolve_zonal`, the
ratio estimator Σ K Φ / Σ K Ω) on a cube map whose resolution follows the lobe.

What it leaves out, against the *normalised modified-Phong BRDF* [4, 5]
f_r(v, ω) = (s + 2)/(2π) · max(0, r·ω)^s (the Mitsuba BSDF of :mod:`validate.reference.ibl_render`),
whose reflected radiance is L_o(v) = ∫_{H(n)} L(ω) f_r cos θ_ω dω:

* the cosine cos θ_ω inside the lobe and the horizon (ω below the surface);
* at *normal incidence* (v = n, so r = n and cos θ_ω = r·ω) the two are the same function:
  (s + 2)/(2π) cos^{s+1} = K_{s+1}. So a map of exponent s + 1 (:func:`map_exponent_for_brdf`) is
  exact there but for its discretisation; a map of the BRDF's own exponent s — the usual practice —
  is a slightly wider lobe (see the ``ibl`` experiment for the measured cost).

Error at (near-)normal incidence, θ_v ≤ :data:`NORMAL_INCIDENCE_DEG`, for the map of exponent s + 1
built with the default rules (largest texel 2/N ≤ σ_s/:data:`TEXELS_PER_LOBE`, σ_s = 1/√s): the map is
exact at v = n but for its discretisation (bilinear interpolation, node merging) and, once v ≠ n, for
the cosine and the horizon. This module states no error budget of its own: the ``ibl`` experiment
bounds it per pixel from textbook theorems computed on the environment
(:func:`validate.experiments.ibl_checks.phong_bound`: h²/8 interpolation bound with the lobe's second
derivatives, |cos θ_ω − cos α| ≤ θ_v sin(α + θ_v), the horizon) and claims the measured error stays
within that bound (claim ``ibl.phong.normal_incidence``).

Registered techniques (family ``specular``, BRDF model ``phong``): ``phong_prefiltered`` (map of
exponent s + 1) and ``phong_prefiltered_s`` (map of the BRDF's own exponent, the usual practice).

References
  [1] G. Miller, C. R. Hoffman, "Illumination and Reflection Maps", SIGGRAPH 1984 course notes.
  [2] J. Kautz, M. McCool, "Approximation of Glossy Reflection with Prefiltered Environment Maps",
      Graphics Interface 2000 (Phong-lobe prefiltering and its error at grazing angles).
  [3] P. Debevec et al., HDRShop, "Specular convolution" (Phong exponent) — the maps of the seed shader.
  [4] E. Lafortune, Y. Willems, "Using the modified Phong reflectance model for physically based
      rendering", Tech. Rep. CW197, KU Leuven, 1994 (normalisation (s + 2)/2π).
  [5] R. R. Lewis, "Making shaders more physically plausible", Computer Graphics Forum 13(2), 1994.
  [6] R. J. Rost, "OpenGL Shading Language", 2nd ed., Addison-Wesley 2006, ch. 12 (the diffuse +
      specular cube-map shader with BaseColor, DiffusePercent, SpecularPercent).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ..families import specular
from ..irradiance.irradiance_map import (
    CubeMap,
    EnvironmentNodes,
    Kernel,
    convolve_zonal,
    environment_nodes,
)
from ..precision import packed_to_dr, to_np
from .common import (
    array_digest,
    block_deg_for_width,
    cached,
    face_size_for_width,
)

EXPONENT_RANGE = (0.5, 10000.0)
SUPPORT_EPS = 1e-7  # K_s < 1e-7 · K_s(1) is dropped: cos^s α < 1e-7
NORMAL_INCIDENCE_DEG = 5.0  # "normal incidence": view within 5° of the normal


def _check_exponent(s: float) -> float:
    lo, hi = EXPONENT_RANGE
    if not (isinstance(s, (int, float)) and lo <= s <= hi):
        raise ValidateError(f"Phong exponent {s!r}: expected a number in [{lo:g}, {hi:g}]")
    return float(s)


def phong_kernel(s: float) -> Kernel:
    """K_s(c) = (s + 1)/(2π) max(0, c)^s, the normalised Phong lobe (∫ K_s dω = 1)."""
    s = _check_exponent(s)
    norm = (s + 1.0) / (2.0 * math.pi)

    def kernel(c: np.ndarray) -> np.ndarray:  # in the input's precision (float32 in the dense path)
        c = np.asarray(c)
        pos = np.maximum(c, 0)
        np.power(pos, c.dtype.type(s), out=pos)  # in place: the same operations as norm · max(0, c)^s
        pos *= norm
        return pos

    return kernel


def phong_lobe_width(s: float) -> float:
    """σ_s = 1/√s rad: cos^s α ≈ exp(−sα²/2) near the peak."""
    return 1.0 / math.sqrt(_check_exponent(s))


def phong_support_cos(s: float) -> float:
    """cos α below which cos^s α < :data:`SUPPORT_EPS` (−1: the whole hemisphere matters)."""
    c = SUPPORT_EPS ** (1.0 / _check_exponent(s))
    return c if c > 0.5 else -1.0


def phong_face_size(s: float) -> int:
    """Cube face size for exponent s (module docstring): 8, 32, 128, 256 for s = 1, 10, 100, 1000."""
    return face_size_for_width(phong_lobe_width(s))


def map_exponent_for_brdf(s: float) -> float:
    """Exponent of the map that equals the modified-Phong BRDF (exponent s) at normal incidence: s + 1."""
    return _check_exponent(s) + 1.0


def prefilter_phong_cube(radiance: np.ndarray, s: float, face_size: int | None = None,
                         needed: np.ndarray | None = None, nodes: EnvironmentNodes | None = None) -> CubeMap:
    """Phong-prefiltered cube map P_s at texel directions (only the lookup footprint of ``needed``
    reflection vectors, if given)."""
    sigma = phong_lobe_width(s)
    n = face_size if face_size is not None else phong_face_size(s)
    if nodes is None:
        nodes = environment_nodes(radiance, block_deg_for_width(sigma))
    kernel, support = phong_kernel(s), phong_support_cos(s)
    return CubeMap.build(lambda d: convolve_zonal(nodes, d, kernel, 1.0, support), n, needed)


def reflect_dr(normals: np.ndarray, views: np.ndarray) -> tuple[Any, Any, Any]:
    """r = 2(n·v)n − v as three drjit arrays of the active dtype (n, v gathered from one packed input,
    :func:`~validate.local_models.precision.packed_to_dr`)."""
    nx, ny, nz, vx, vy, vz = packed_to_dr(*np.asarray(normals, dtype=np.float64).reshape(-1, 3).T,
                                          *np.asarray(views, dtype=np.float64).reshape(-1, 3).T)
    two_nv = 2.0 * (nx * vx + ny * vy + nz * vz)
    return two_nv * nx - vx, two_nv * ny - vy, two_nv * nz - vz


def shade_phong_map(specular_map: CubeMap, normals: np.ndarray, views: np.ndarray, ks: float = 1.0) -> np.ndarray:
    """L_o ≈ k_s P_s(r): the prefiltered map looked up at the reflection vector r = 2(n·v)n − v, both in drjit in
    the active dtype (:func:`reflect_dr`, :meth:`CubeMap.lookup`); (N, 3) float64."""
    return ks * specular_map.lookup(reflect_dr(normals, views))


def mix_shader(base_color: np.ndarray | float, diffuse_percent: float, specular_percent: float,
               diffuse: np.ndarray, specular: np.ndarray) -> np.ndarray:
    """The seed's fragment shader [6], with diffuse = the diffuse map at n (E/π of a white Lambertian
    surface), specular = the specular map at r:

        color = mix(BaseColor, diffuse · BaseColor, DiffusePercent)
        color = mix(color, specular + color, SpecularPercent)
              = BaseColor (1 − DiffusePercent) + DiffusePercent · BaseColor · diffuse
                + SpecularPercent · specular          (mix(a, b, t) = a(1 − t) + b t).

    The first term is unlit; with DiffusePercent = 1 the shader is the physical blend
    (1 − w) ρ E/π + w P_s of Mitsuba's ``blendbsdf`` (weight w, diffuse ρ, Phong) when
    BaseColor = (1 − w) ρ and SpecularPercent = w.
    """
    if not (0.0 <= diffuse_percent <= 1.0 and 0.0 <= specular_percent <= 1.0):
        raise ValidateError(f"mix_shader: DiffusePercent={diffuse_percent}, SpecularPercent={specular_percent}: "
                            "expected both in [0, 1]")
    base = np.asarray(base_color, dtype=np.float64)
    color = base * (1.0 - diffuse_percent) + np.asarray(diffuse) * base * diffuse_percent
    return color * (1.0 - specular_percent) + (np.asarray(specular) + color) * specular_percent


# ---------------------------------------------------------------------------------------------
# Registered techniques (family ``specular``) and a small map cache
# ---------------------------------------------------------------------------------------------


def cached_phong_cube(radiance: np.ndarray, s: float, directions: np.ndarray) -> CubeMap:
    """:func:`prefilter_phong_cube` of exponent ``s`` (face per :func:`phong_face_size`), sparse on the
    lookup footprint of ``directions``, memoised on the content of both arrays."""
    key = ("phong", array_digest(radiance), float(s), array_digest(directions))
    return cached(key, lambda: prefilter_phong_cube(radiance, s, needed=directions))  # type: ignore[return-value]


def _footprint(r: tuple[Any, Any, Any]) -> np.ndarray:
    """The drjit reflection vectors as (N, 3) float64 numpy: the sparse map is evaluated on the lookup footprint of
    the very (float32) r the lookup reads, so no lookup lands on an unevaluated (NaN) texel because r was rounded
    differently (only the face-coordinate arithmetic differs, float64 here, float32 in the lookup)."""
    return np.stack([to_np(c) for c in r], axis=-1)


def _phong_exponent(brdf: Mapping[str, object]) -> tuple[float, float]:
    if brdf.get("model") != "phong" or "exponent" not in brdf:
        raise ValidateError(f"Phong-prefiltered map: BRDF {dict(brdf)!r}: expected {{'model': 'phong', 'exponent': s}}")
    return _check_exponent(float(brdf["exponent"])), float(brdf.get("reflectance", 1.0))  # type: ignore[arg-type]


@specular.register("phong_prefiltered", "Phong-prefiltered cube map of exponent s + 1 at r (exact at normal "
                   "incidence for the modified-Phong BRDF of exponent s)", brdf=("phong",))
def phong_prefiltered(radiance: np.ndarray, brdf: Mapping[str, object], normals: np.ndarray,
                      views: np.ndarray) -> np.ndarray:
    """L_o ≈ k_s P_{s+1}(r), r = 2(n·v)n − v (module docstring: the map of exponent s + 1 equals the
    modified-Phong BRDF (s + 2)/2π cos^s α · cos θ at v = n)."""
    s, ks = _phong_exponent(brdf)
    r = reflect_dr(normals, views)
    return ks * cached_phong_cube(radiance, map_exponent_for_brdf(s), _footprint(r)).lookup(r)


@specular.register("phong_prefiltered_s", "Phong-prefiltered cube map of the BRDF's own exponent s at r (the "
                   "usual practice, HDRShop [3])", brdf=("phong",))
def phong_prefiltered_s(radiance: np.ndarray, brdf: Mapping[str, object], normals: np.ndarray,
                        views: np.ndarray) -> np.ndarray:
    """L_o ≈ k_s P_s(r): the same-exponent map (a slightly wider lobe than the BRDF's at v = n)."""
    s, ks = _phong_exponent(brdf)
    r = reflect_dr(normals, views)
    return ks * cached_phong_cube(radiance, s, _footprint(r)).lookup(r)
