"""The überlight (Barzel's cinematographic light) as real-time shaders give it, vectorised in drjit.

Family ``uberlight`` (defined here): ``fn(light, points, normals, views, material, shadow=None) ->
(N,)`` outgoing radiance of each receiver (grey), where

* ``light``: mapping with ``position`` (3,), ``axes`` (3, 3) rows = light x, y, z (forward) in world
  space, ``intensity`` (I₀), ``width``, ``height``, ``width_edge``, ``height_edge``, ``roundness``,
  ``near``, ``far``, ``near_edge``, ``far_edge``; the Fore June technique also ``d0``, ``alpha``,
  ``max_intensity`` (M);
* ``points`` (N, 3), ``normals`` (N, 3) unit, ``views`` (N, 3) unit toward the viewer;
* ``material``: ``albedo`` (N,) or scalar ρ, ``ks`` (default 0), ``specular_exponent`` (default 20);
* ``shadow``: (N,) light visibility in [0, 1] (default 1).

Shaping, in light coordinates p = (x, y, z) of the receiver (Listing 12.6 [1]):

    superEllipseShape:  (x', y') = (x, y)/z  (projection onto z = 1),  w = width, W = w + width_edge,
                        h = height, H = h + height_edge, e₁ = 2/roundness, e₂ = −roundness/2,
                        inner = w h (|h x'|^e₁ + |w y'|^e₁)^e₂,  outer = W H (|H x'|^e₁ + |W y'|^e₁)^e₂,
                        A = 1 − smoothstep(inner, outer, 1)
    distanceShape:      D = smoothstep(near − nearEdge, near, z) · (1 − smoothstep(far, far + farEdge, z))

with GLSL's smoothstep(e₀, e₁, x) = t²(3 − 2t), t = clamp((x − e₀)/(e₁ − e₀), 0, 1). Two limits the
listing leaves undefined are fixed here: e₀ = e₁ (a zero edge width) is the step x ≥ e₁, and the
axis point x' = y' = 0 (0^e₂ = ∞) is inside (A = 1). Points behind the light (z ≤ 0) get A = 0.

Reflection, the "plastic" of Listing 12.7 [1] with no ambient term:

    L_o = C · shadow · (ρ_d · max(0, n·l) + k_s · max(0, n·h)^s),   ρ_d = ρ/π,   C = I₀ · A · D · F(d),

h = normalise(l + v), d = |p| the distance to the light. The 1/π makes the diffuse part Lambertian
(radiance of a surface of albedo ρ under irradiance C n·l); the book's K_d is ρ_d.

Techniques (F is the distance falloff; the listing has none):

* ``uberlight`` — Listing 12.6/12.7 as printed: F = 1 (C is then an irradiance); for receivers in front of
  the light and ks = 0 (the printed specular, (n·l)(n·h)·SurfaceRoughness, has no exponent; behind the
  light the listing still lights at depth |z|; see ``listings.orange_uberlight``, run as printed).
* ``uberlight_inverse_square`` — F = 1/d²: I₀ · A · D is a radiant intensity (W sr⁻¹).
* ``uberlight_fore_june`` — F from Barzel's falloff [2] as taught by Fore June ch. 20 §20.5 [3]:
  I(d) = K (d₀/d)^α for d ≥ d₀ and, in the near field, M exp(s (d/d₀)^β) with s = ln(K/M) and
  β = −α/s, which equals K and has the same slope −αK/d₀ at d = d₀ and tends to M as d → 0.
  Checked against the seed text: this is the near branch of the *listing* after eq. 20.47
  (``pow(z/d0, beta)``, C¹ at d₀); the printed eq. 20.47 has (d₀/d)^β, which meets the far branch with
  the opposite slope and → 0 as d → 0 (``listings.fore_june_falloff.uberlight_fore_june_printed``).
  Two differences from the listing remain: the listing falls off on the depth |z|, here on the
  distance d, and it fixes K = 1 (s = ln(1/M)).
  K = I₀/d₀^α so that α = 2 gives the far field I₀/d² exactly.

References
  [1] R. Rost, *OpenGL Shading Language*, 2nd ed., Addison-Wesley 2006, §12.4, Listings 12.6/12.7.
  [2] R. Barzel, "Lighting Controls for Computer Cinematography", JGT 2(1), 1997, 1–20.
  [3] Fore June, *An Introduction to 3D Computer Graphics, Stereoscopic Image, and Animation in
      OpenGL and C/C++*, ch. 20 §20.5 "Lighting of Cinematography".
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ...backend import float_type
from ...errors import ValidateError
from ..families import uberlight

SHAPE_KEYS = ("width", "height", "width_edge", "height_edge", "roundness")
DISTANCE_KEYS = ("near", "far", "near_edge", "far_edge")
NO_DISTANCE_SHAPING = {"near": 0.0, "far": 1.0e9, "near_edge": 0.0, "far_edge": 0.0}


def check_light(light: Mapping[str, Any], *extra: str) -> None:
    """One-line error naming the missing or invalid überlight parameters."""
    keys = ("position", "axes", "intensity") + SHAPE_KEYS + DISTANCE_KEYS + extra
    missing = [k for k in keys if k not in light]
    if missing:
        raise ValidateError(f"überlight light mapping: missing {', '.join(missing)}")
    bad = [k for k in ("width", "height", "roundness") if not float(light[k]) > 0]
    bad += [k for k in ("width_edge", "height_edge", "near_edge", "far_edge") if not float(light[k]) >= 0]
    if bad:
        raise ValidateError(f"überlight light mapping: {', '.join(bad)} must be > 0 (widths, roundness) or ≥ 0 "
                            "(edges)")


def _f(a: Any) -> Any:
    return float_type()(np.ascontiguousarray(np.asarray(a, dtype=np.float64).ravel(), dtype=np.float32))


def smoothstep(e0: Any, e1: Any, x: Any) -> Any:
    """GLSL smoothstep; e₀ = e₁ is the step x ≥ e₁ (module docstring)."""
    import drjit as dr

    width = e1 - e0
    t = dr.clip((x - e0) / dr.select(width > 0, width, 1.0), 0.0, 1.0)
    return dr.select(width > 0, t * t * (3.0 - 2.0 * t), dr.select(x >= e1, 1.0, 0.0))


def light_coordinates(light: Mapping[str, Any], points: np.ndarray) -> np.ndarray:
    """(N, 3) receiver positions in the light's frame (x, y, z = forward), float64."""
    axes = np.asarray(light["axes"], dtype=np.float64).reshape(3, 3)
    rel = np.asarray(points, dtype=np.float64).reshape(-1, 3) - np.asarray(light["position"], dtype=np.float64)
    return rel @ axes.T


def superellipse_shape(light: Mapping[str, Any], lc: Any) -> Any:
    """A = 1 − smoothstep(inner, outer, 1) of Listing 12.6 (drjit; ``lc`` = (x, y, z) drjit arrays)."""
    import drjit as dr

    x, y, z = lc
    front = z > 0
    zs = dr.select(front, z, 1.0)
    px, py = dr.abs(x / zs), dr.abs(y / zs)
    w, h = float(light["width"]), float(light["height"])
    ww, hh = w + float(light["width_edge"]), h + float(light["height_edge"])
    e1, e2 = 2.0 / float(light["roundness"]), -float(light["roundness"]) / 2.0
    at_axis = (px == 0) & (py == 0)
    inner = w * h * dr.power(dr.select(at_axis, 1.0, dr.power(h * px, e1) + dr.power(w * py, e1)), e2)
    outer = ww * hh * dr.power(dr.select(at_axis, 1.0, dr.power(hh * px, e1) + dr.power(ww * py, e1)), e2)
    shape = 1.0 - smoothstep(inner, outer, dr.full(type(inner), 1.0, dr.width(inner)))
    return dr.select(front, dr.select(at_axis, 1.0, shape), 0.0)


def distance_shape(light: Mapping[str, Any], z: Any) -> Any:
    """D = smoothstep(near − nearEdge, near, z) · (1 − smoothstep(far, far + farEdge, z)) (Listing 12.6)."""
    near, far = float(light["near"]), float(light["far"])
    ne, fe = float(light["near_edge"]), float(light["far_edge"])
    one = z * 0.0
    return smoothstep(one + (near - ne), one + near, z) * (1.0 - smoothstep(one + far, one + (far + fe), z))


def superellipse_shape_np(light: Mapping[str, Any], x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The same A in float64 numpy (the slow, obvious version the drjit one is tested against; the fits use it)."""
    def sstep(e0: np.ndarray, e1: np.ndarray, v: float) -> np.ndarray:
        wdt = e1 - e0
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.clip((v - e0) / np.where(wdt > 0, wdt, 1.0), 0.0, 1.0)
        return np.where(wdt > 0, t * t * (3 - 2 * t), (v >= e1).astype(float))

    front = z > 0
    zs = np.where(front, z, 1.0)
    px, py = np.abs(x / zs), np.abs(y / zs)
    w, h = float(light["width"]), float(light["height"])
    ww, hh = w + float(light["width_edge"]), h + float(light["height_edge"])
    e1, e2 = 2.0 / float(light["roundness"]), -float(light["roundness"]) / 2.0
    axis = (px == 0) & (py == 0)
    with np.errstate(divide="ignore", over="ignore"):
        inner = w * h * np.where(axis, 1.0, (h * px) ** e1 + (w * py) ** e1) ** e2
        outer = ww * hh * np.where(axis, 1.0, (hh * px) ** e1 + (ww * py) ** e1) ** e2
    return np.where(front & ~axis, 1.0 - sstep(inner, outer, 1.0), np.where(front, 1.0, 0.0))


def distance_shape_np(light: Mapping[str, Any], z: np.ndarray) -> np.ndarray:
    """The same D in float64 numpy (twin of :func:`distance_shape`)."""
    def sstep(e0: float, e1: float, v: np.ndarray) -> np.ndarray:
        if e1 > e0:
            t = np.clip((v - e0) / (e1 - e0), 0.0, 1.0)
            return t * t * (3 - 2 * t)
        return (v >= e1).astype(float)

    z = np.asarray(z, dtype=np.float64)
    near, far = float(light["near"]), float(light["far"])
    return sstep(near - float(light["near_edge"]), near, z) * (1.0 - sstep(far, far + float(light["far_edge"]), z))


def fore_june_falloff(d: np.ndarray, intensity: float, d0: float, alpha: float, max_intensity: float
                      ) -> np.ndarray:
    """Barzel's falloff (module docstring): K (d₀/d)^α for d ≥ d₀, M exp(s (d/d₀)^β) below, K = I₀/d₀^α."""
    d = np.asarray(d, dtype=np.float64)
    k = intensity / d0 ** alpha
    if not (max_intensity > k > 0 and d0 > 0 and alpha > 0):
        raise ValidateError(f"Fore June falloff: need M > K = I₀/d₀^α > 0 and d₀, α > 0 (M={max_intensity:g}, "
                            f"K={k:g}, d₀={d0:g}, α={alpha:g})")
    s = math.log(k / max_intensity)
    beta = -alpha / s
    with np.errstate(divide="ignore"):
        far = k * (d0 / np.maximum(d, 1e-30)) ** alpha
    return np.where(d >= d0, far, max_intensity * np.exp(s * (d / d0) ** beta))


def shade(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, views: np.ndarray,
          material: Mapping[str, Any], shadow: np.ndarray | None, falloff: np.ndarray | float) -> np.ndarray:
    """L_o of the module docstring with the per-point falloff F (array or scalar)."""
    import drjit as dr

    check_light(light)
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    lc64 = light_coordinates(light, p)
    lc = [_f(lc64[:, i]) for i in range(3)]
    a = superellipse_shape(light, lc) * distance_shape(light, lc[2])
    to_light = np.asarray(light["position"], dtype=np.float64) - p
    dist = np.linalg.norm(to_light, axis=1)
    ldir = to_light / np.maximum(dist, 1e-30)[:, None]
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    v = np.asarray(views, dtype=np.float64).reshape(-1, 3)
    half = ldir + v
    half /= np.maximum(np.linalg.norm(half, axis=1), 1e-30)[:, None]
    ndotl = dr.maximum(_f(np.einsum("nk,nk->n", n, ldir)), 0.0)
    ndoth = dr.maximum(_f(np.einsum("nk,nk->n", n, half)), 0.0)
    albedo = np.broadcast_to(np.asarray(material.get("albedo", 1.0), dtype=np.float64), (len(p),))
    ks, s = float(material.get("ks", 0.0)), float(material.get("specular_exponent", 20.0))
    refl = _f(albedo / math.pi) * ndotl + ks * dr.power(ndoth, s)
    vis = _f(np.ones(len(p)) if shadow is None else shadow)
    c = float(light["intensity"]) * a * _f(np.broadcast_to(np.asarray(falloff, dtype=np.float64), (len(p),)))
    return np.array(c * vis * refl, dtype=np.float64)


def _distance(light: Mapping[str, Any], points: np.ndarray) -> np.ndarray:
    return np.linalg.norm(np.asarray(points, dtype=np.float64).reshape(-1, 3) - np.asarray(light["position"]), axis=1)


@uberlight.register("uberlight", "Orange Book Listing 12.6/12.7 as printed: superellipse × distance shaping, "
                    "plastic reflection, no distance falloff")
def uberlight_listing(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, views: np.ndarray,
                      material: Mapping[str, Any], shadow: np.ndarray | None = None) -> np.ndarray:
    """Listing 12.6/12.7 [1] with F = 1."""
    return shade(light, points, normals, views, material, shadow, 1.0)


@uberlight.register("uberlight_inverse_square", "the listing's shaping with the physical falloff 1/d² "
                    "(I₀·A·D a radiant intensity)",
                    thresholds={"projector.max_rel": 1.0e-5},
                    source="float32 rounding + texture interpolation, derived: both sides are float32 (ε = 6·10⁻⁸; "
                           "≈ 50 roundings → ≤ 3·10⁻⁶ of the value); Mitsuba's bilinear lookup of the smooth "
                           "cos³θ-weighted texture errs by ≤ Δt²/8 · max|∂²(cos³θ)/∂t²| ≈ (1.4·10⁻³)²/8 · 3 "
                           "≈ 7·10⁻⁷ (Δt = 2 tan 35°/1024); 10⁻⁵ is > 2.5× their sum. Measured 9.2·10⁻⁷; a 1 % "
                           "width error moves the hard edge by 2.5 texels and flips pixels (error ≈ 0.57)")
def uberlight_inverse_square(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, views: np.ndarray,
                             material: Mapping[str, Any], shadow: np.ndarray | None = None) -> np.ndarray:
    """Listing 12.6/12.7 [1] with F = 1/d², d = |p − light position|."""
    return shade(light, points, normals, views, material, shadow, 1.0 / _distance(light, points) ** 2)


@uberlight.register("uberlight_fore_june", "the listing's shaping with Barzel's falloff K(d₀/d)^α and its "
                    "near-field clamp (Fore June §20.5)")
def uberlight_fore_june(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, views: np.ndarray,
                        material: Mapping[str, Any], shadow: np.ndarray | None = None) -> np.ndarray:
    """Listing 12.6/12.7 [1] with F = fore_june_falloff(d)/I₀ (light keys d0, alpha, max_intensity)."""
    check_light(light, "d0", "alpha", "max_intensity")
    i0 = float(light["intensity"])
    f = fore_june_falloff(_distance(light, points), i0, float(light["d0"]), float(light["alpha"]),
                          float(light["max_intensity"])) / i0
    return shade(light, points, normals, views, material, shadow, f)
