"""What the ``brdfs`` experiment lights: materials (one parameter set, one Mitsuba BSDF), direction grids
and the V-groove microsurface.

Frame: the local shading frame, normal +z (Mitsuba's BSDF frame). Directions are unit (N, 3).

Materials
  A :class:`Material` carries the physical parameters every ``brdf`` technique reads (see
  :mod:`validate.local_models.brdf.classic_brdfs`) and the Mitsuba BSDF dict that is its ground truth. The
  parameters of the Phong-type models follow from the microfacet roughness α:

  * Blinn–Phong exponent s_b = 2/α² − 2, i.e. α = √(2/(s_b + 2)): Walter et al. 2007 [1] §5.2
    (the Phong distribution (s+2)/(2π) cos^s θ_h that matches Beckmann of width α);
  * Phong (r·v) exponent s_p = s_b/4: near the peak the angle between r and v is twice the angle between
    n and h, so cos^{s_p}(2θ) ≈ exp(−2 s_p θ²) = cos^{4 s_p}(θ) to second order [2];
  * k_s = F₀ = ((η − 1)² + k²)/((η + 1)² + k²), the normal-incidence reflectance (no Fresnel in Phong).

V-grooves
  Oren & Nayar's microsurface [3]: long symmetric V-cavities whose two facets have slope ±θ_a, tops in
  the mean plane z = 0. :func:`vgroove_mesh` builds G adjacent grooves along y (cross-section a
  triangle wave in x of period w, depth (w/2) tan θ_a) over a square of side :data:`VGROOVE_EXTENT`.
  The isotropic surface of [3] mixes groove orientations φ_a uniformly and slopes with the Gaussian
  facet-slope density P(θ_a) ∝ exp(−θ_a²/(2σ²)) over solid angle (weight ∝ P(θ_a) sin θ_a dθ_a dφ_a,
  [3] eq. 2 and 28); :func:`vgroove_quadrature` gives Gauss–Legendre nodes and weights for it.

References
  [1] B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet models for refraction through rough
      surfaces", EGSR 2007.
  [2] F. Fisher, A. Woo, "R·E versus N·H specular highlights", Graphics Gems IV, 1994.
  [3] M. Oren, S. K. Nayar, "Generalization of Lambert's reflectance model", SIGGRAPH 1994.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np

from ..errors import ValidateError

# An arbitrary coloured conductor (the same numbers go to the models and to Mitsuba): F₀ ≈ (0.95, 0.64, 0.54)
CONDUCTOR_ETA = (0.27, 0.68, 1.10)
CONDUCTOR_K = (3.61, 2.62, 2.29)
PLASTIC_ETA = 1.5
VGROOVE_EXTENT = 1.0  # side of the V-groove square (mean plane)
VGROOVE_COUNT = 64  # grooves across it
VGROOVE_FOOTPRINT = 0.5  # side of the central square whose mean radiance is measured (32 grooves across)
MAX_SLOPE_DEG = 80.0  # deepest facet slope in the quadrature


def blinn_exponent(alpha: float) -> float:
    """s_b = 2/α² − 2 (Walter et al. 2007 §5.2)."""
    return 2.0 / (alpha * alpha) - 2.0


def phong_exponent(alpha: float) -> float:
    """s_p = s_b/4 (Fisher & Woo 1994)."""
    return blinn_exponent(alpha) / 4.0


def alpha_from_blinn(s: float) -> float:
    """α = √(2/(s + 2)) (Walter et al. 2007 §5.2)."""
    return float(np.sqrt(2.0 / (s + 2.0)))


@dataclass(frozen=True)
class Material:
    """A test case: the models' parameters and the Mitsuba BSDF they are judged against."""

    name: str
    description: str
    params: dict[str, Any]
    bsdf: dict[str, Any] = field(default_factory=dict)


def _rgb(v: tuple[float, float, float] | float) -> dict[str, Any]:
    return {"type": "rgb", "value": list(v) if isinstance(v, tuple) else [v, v, v]}


def specular_params(alpha: float, distribution: str, eta: Any, k: Any) -> dict[str, Any]:
    """Parameters of a specular material of roughness α (Phong exponents by the mappings above)."""
    f0 = ((np.asarray(eta) - 1) ** 2 + np.asarray(k) ** 2) / ((np.asarray(eta) + 1) ** 2 + np.asarray(k) ** 2)
    return {"albedo": 0.0, "ks": np.broadcast_to(f0, (3,)).tolist(), "alpha": alpha, "distribution": distribution,
            "exponent": blinn_exponent(alpha), "phong_exponent": phong_exponent(alpha), "eta": eta, "k": k,
            "sigma": 0.0, "minnaert_k": 1.0}


def conductor(alpha: float, distribution: str = "beckmann", coloured: bool = True) -> Material:
    """roughconductor of roughness α; ``coloured``: :data:`CONDUCTOR_ETA`/``K``, else a perfect mirror (F = 1)."""
    eta, k = (CONDUCTOR_ETA, CONDUCTOR_K) if coloured else (0.0, 1.0)
    kind = "conductor" if coloured else "mirror"
    bsdf = {"type": "roughconductor", "distribution": distribution, "alpha": alpha, "eta": _rgb(eta), "k": _rgb(k)}
    return Material(f"{kind}_{distribution}_a{alpha:g}",
                    f"Mitsuba roughconductor, {distribution}, α = {alpha:g}, "
                    + (f"η = {eta}, k = {k}" if coloured else "F = 1 (η = 0, k = 1)"),
                    specular_params(alpha, distribution, eta, k), bsdf)


def dielectric_interface(alpha: float, eta: float = PLASTIC_ETA) -> Material:
    """The reflection of a rough dielectric interface (η real, k = 0; F₀ = 0.04 at η = 1.5), Beckmann: Mitsuba's
    roughconductor with k = 0 (its Fresnel term is then the dielectric one; nothing is transmitted or added)."""
    bsdf = {"type": "roughconductor", "distribution": "beckmann", "alpha": alpha, "eta": eta, "k": 0.0}
    return Material(f"dielectric_beckmann_a{alpha:g}", f"rough dielectric interface (reflection only), Beckmann, "
                    f"α = {alpha:g}, η = {eta:g}", specular_params(alpha, "beckmann", eta, 0.0), bsdf)


def diffuse(albedo: float = 0.8) -> Material:
    """Mitsuba ``diffuse`` of albedo ρ (every rough-diffuse model at σ = 0; η = 1, k = 0: no specular interface,
    F = 0 for the microfacet models)."""
    p = {**specular_params(0.3, "beckmann", 1.0, 0.0), "albedo": albedo, "ks": 0.0, "sigma": 0.0}
    return Material(f"diffuse_r{albedo:g}", f"Mitsuba diffuse, ρ = {albedo:g}", p,
                    {"type": "diffuse", "reflectance": _rgb(albedo)})


def modified_phong(s: float, plugin: str) -> Material:
    """The suite's normalised modified-Phong BSDF (plugin name from the reference) of exponent s."""
    alpha = alpha_from_blinn(4.0 * s)
    p = {**specular_params(alpha, "beckmann", 0.0, 1.0), "ks": 1.0, "phong_exponent": s, "exponent": 4.0 * s}
    return Material(f"modphong_s{s:g}", f"suite's normalised modified Phong, s = {s:g}", p,
                    {"type": plugin, "exponent": s, "reflectance": 1.0})


def vgroove_material(sigma_deg: float, albedo: float) -> Material:
    """A rough diffuse surface of facet-slope deviation σ: parameters only (the reference is the V-grooves)."""
    p = {**specular_params(0.3, "beckmann", 1.0, 0.0), "albedo": albedo, "ks": 0.0,
         "sigma": float(np.radians(sigma_deg))}
    return Material(f"vgroove_s{sigma_deg:g}", f"V-groove microsurface, σ = {sigma_deg:g}°, facet ρ = {albedo:g}", p)


# ---------------------------------------------------------------------------------------------
# Direction grids

def direction(theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """(sin θ cos φ, sin θ sin φ, cos θ), (..., 3)."""
    theta, phi = np.broadcast_arrays(np.asarray(theta, dtype=np.float64), np.asarray(phi, dtype=np.float64))
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1)


def hemisphere_quadrature(n_theta: int, n_phi: int) -> tuple[np.ndarray, np.ndarray]:
    """(directions (M, 3), solid-angle weights (M,)) over the upper hemisphere: Gauss–Legendre in cos θ ∈ [0, 1]
    × uniform midpoint φ; Σ w = 2π, exact for polynomials in cos θ of degree < 2 n_theta."""
    if n_theta < 1 or n_phi < 1:
        raise ValidateError(f"hemisphere_quadrature: n_theta={n_theta}, n_phi={n_phi}; both must be ≥ 1")
    d, w = _hemisphere_quadrature(int(n_theta), int(n_phi))
    return d.copy(), w.copy()


@lru_cache(maxsize=32)
def _hemisphere_quadrature(n_theta: int, n_phi: int) -> tuple[np.ndarray, np.ndarray]:
    """:func:`hemisphere_quadrature`, computed once per (n_theta, n_phi): the experiments ask for the same grid
    thousands of times and ``leggauss`` (an eigenvalue problem) dominated the furnace loops; callers get copies."""
    x, w = np.polynomial.legendre.leggauss(n_theta)
    mu, wmu = 0.5 * (x + 1.0), 0.5 * w
    phi = (np.arange(n_phi) + 0.5) * (2.0 * np.pi / n_phi)
    mm, pp = np.meshgrid(mu, phi, indexing="ij")
    d = direction(np.arccos(mm), pp).reshape(-1, 3)
    return d, np.repeat(wmu, n_phi) * (2.0 * np.pi / n_phi)


def brdf_grid(n_theta: int, n_phi: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pairs (l, v) for the error integral ∫∫ · cos θ_v dω_l dω_v over both hemispheres, using isotropy:
    v at azimuth 0, l over Gauss–Legendre cos θ_l × uniform Δφ ∈ [0, π] (mirror symmetry), v over Gauss–Legendre
    cos θ_v. Returns (lights (M, 3), views (M, 3), weights (M,) including cos θ_v and the 2π of v's azimuth)."""
    lights, views, weights = _brdf_grid(int(n_theta), int(n_phi))
    return lights.copy(), views.copy(), weights.copy()


@lru_cache(maxsize=8)
def _brdf_grid(n_theta: int, n_phi: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`brdf_grid`, computed once per (n_theta, n_phi); callers get copies."""
    x, w = np.polynomial.legendre.leggauss(n_theta)
    mu, wmu = 0.5 * (x + 1.0), 0.5 * w
    dphi = (np.arange(n_phi) + 0.5) * (np.pi / n_phi)
    ml, mv, pp = np.meshgrid(mu, mu, dphi, indexing="ij")
    wl, wv = np.meshgrid(wmu, wmu, indexing="ij")
    lights = direction(np.arccos(ml), pp).reshape(-1, 3)
    views = direction(np.arccos(mv), np.zeros_like(pp)).reshape(-1, 3)
    weights = (wl[..., None] * wv[..., None] * mv * (2.0 * np.pi / n_phi) * 2.0 * np.pi).reshape(-1)
    return lights, views, weights


def vgroove_configurations(thetas_deg: list[float], dphis_deg: list[float]) -> tuple[np.ndarray, np.ndarray]:
    """Every (θ_l, θ_v, Δφ) of the lists: lights (M, 3), views (M, 3) with v at azimuth 0."""
    tl, tv, dp = np.meshgrid(np.radians(thetas_deg), np.radians(thetas_deg), np.radians(dphis_deg), indexing="ij")
    return direction(tl, dp).reshape(-1, 3), direction(tv, np.zeros_like(tv)).reshape(-1, 3)


# ---------------------------------------------------------------------------------------------
# V-grooves

def vgroove_quadrature(sigma: float, n_slope: int, n_orient: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(slopes θ_a (S,), orientations φ_a (O,), weights (S, O) summing to 1) for the Gaussian facet-slope
    density P(θ_a) ∝ exp(−θ_a²/2σ²) sin θ_a on [0, min(4σ, 80°)] and uniform φ_a ∈ [0, π) (a V-groove is
    symmetric under φ_a → φ_a + π)."""
    if not sigma > 0:
        raise ValidateError(f"vgroove_quadrature: sigma={sigma} must be > 0")
    top = min(4.0 * sigma, np.radians(MAX_SLOPE_DEG))
    x, w = np.polynomial.legendre.leggauss(n_slope)
    th = 0.5 * top * (x + 1.0)
    wt = 0.5 * top * w * np.exp(-th * th / (2.0 * sigma * sigma)) * np.sin(th)
    phi = (np.arange(n_orient) + 0.5) * (np.pi / n_orient)
    weights = wt[:, None] * np.full(n_orient, 1.0 / n_orient)[None, :]
    return th, phi, weights / weights.sum()


def vgroove_mesh(slope: float, count: int = VGROOVE_COUNT, extent: float = VGROOVE_EXTENT
                 ) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (V, 3), faces (F, 3)): ``count`` V-grooves along y with facet slope ``slope`` (radians), tops at
    z = 0, spanning [−extent/2, extent/2]² in the mean plane (two triangles per facet)."""
    if not 0.0 <= slope < np.pi / 2 or count < 1:
        raise ValidateError(f"vgroove_mesh: slope={slope}, count={count}; expected 0 ≤ slope < π/2 and count ≥ 1")
    period = extent / count
    xs = -0.5 * extent + 0.5 * period * np.arange(2 * count + 1)
    zs = np.where(np.arange(2 * count + 1) % 2 == 1, -0.5 * period * np.tan(slope), 0.0)
    y0, y1 = -0.5 * extent, 0.5 * extent
    verts = np.concatenate([np.stack([xs, np.full_like(xs, y0), zs], -1), np.stack([xs, np.full_like(xs, y1), zs], -1)])
    m = len(xs)
    i = np.arange(m - 1)
    faces = np.concatenate([np.stack([i, i + 1, m + i + 1], -1), np.stack([i, m + i + 1, m + i], -1)])
    return verts.astype(np.float64), faces.astype(np.int64)


# ---------------------------------------------------------------------------------------------
# Tessellated sphere (Gouraud vs per-fragment shading)

def _midpoint(verts: list[np.ndarray], cache: dict[tuple[int, int], int], a: int, b: int) -> int:
    """Index of the (new or shared) vertex halfway along edge ab, pushed onto the unit sphere."""
    key = (min(a, b), max(a, b))
    if key not in cache:
        p = verts[a] + verts[b]
        verts.append(p / np.linalg.norm(p))
        cache[key] = len(verts) - 1
    return cache[key]


def icosphere(level: int) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (V, 3) on the unit sphere, faces (F, 3)): the icosahedron subdivided ``level`` times (each
    triangle into 4, new vertices pushed to the sphere); F = 20·4^level. A vertex's normal is its position."""
    if not 0 <= level <= 7:
        raise ValidateError(f"icosphere: level={level}; expected 0 … 7")
    t = (1.0 + np.sqrt(5.0)) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    verts = [np.asarray(p, dtype=np.float64) / np.linalg.norm(p) for p in v]
    faces = [tuple(x) for x in f]
    for _ in range(level):
        cache: dict[tuple[int, int], int] = {}
        new = []
        for a, b, c in faces:
            ab, bc, ca = (_midpoint(verts, cache, i, j) for i, j in ((a, b), (b, c), (c, a)))
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return np.asarray(verts), np.asarray(faces, dtype=np.int64)


def sphere_pixels(size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Orthographic view of the unit sphere from +z over [−1, 1]²: (pixel centres x (S, S), y (S, S), inside mask)."""
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    x, y = np.meshgrid(c, -c)
    return x, y, x * x + y * y < 1.0
