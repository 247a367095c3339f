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
  light the listing still lights at depth |z|; see ``uberlight.orange_uberlight``, run as printed).
* ``uberlight_inverse_square`` — F = 1/d²: I₀ · A · D is a radiant intensity (W sr⁻¹).
* ``uberlight_fore_june`` — F from Barzel's falloff [2] as taught by Fore June ch. 20 §20.5 [3]:
  I(d) = K (d₀/d)^α for d ≥ d₀ and, in the near field, M exp(s (d/d₀)^β) with s = ln(K/M) and
  β = −α/s, which equals K and has the same slope −αK/d₀ at d = d₀ and tends to M as d → 0.
  Checked against the seed text: this is the near branch of the *listing* after eq. 20.47
  (``pow(z/d0, beta)``, C¹ at d₀); the printed eq. 20.47 has (d₀/d)^β, which meets the far branch with
  the opposite slope and → 0 as d → 0 (``uberlight.fore_june_falloff.uberlight_fore_june_printed``).
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

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..families import uberlight
from .common import (  # noqa: F401 (re-exported: callers use orange_book.<helper>)
    DISTANCE_KEYS,
    NO_DISTANCE_SHAPING,
    SHAPE_KEYS,
    _distance,
    _f,
    check_light,
    distance_shape,
    distance_shape_np,
    fore_june_falloff,
    light_coordinates,
    shade,
    smoothstep,
    superellipse_shape,
    superellipse_shape_np,
)


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
