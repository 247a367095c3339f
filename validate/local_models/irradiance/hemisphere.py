"""Hemisphere lighting: blend a sky colour and a ground colour by the normal's tilt from "up".

    C(n) = w · C_sky + (1 − w) · C_ground

with one of two blend weights, as functions of θ, the angle between the normal N and the up axis U
(cos θ = N·U):

* ``exact``     f(θ) = ½ (1 + cos θ)                                  [1, 2]
* ``red_book``  a(θ) = 1 − ½ sin θ  for θ ≤ 90°,   a(θ) = ½ sin θ  for θ > 90°   [1]

For a *two-tone* sky — radiance L_s on the upper hemisphere (ω·U > 0), L_g on the lower one — the
irradiance is exactly  E(n) = π (f L_s + (1 − f) L_g): the upper hemisphere's view factor from a
plane tilted by θ is (1 + cos θ)/2 (Nusselt's unit-sphere projection: the sky's projected area on the
receiver's disc is the half disc plus a half ellipse of semi-axis cos θ; the ground's is the rest).
So ``exact`` with C_sky = L_s, C_ground = L_g returns E/π (the outgoing radiance of a white
Lambertian surface), and the ``red_book`` weight differs from it by

    a − f = ½ (1 − sin θ − cos θ)  (θ ≤ 90°),  ½ (sin θ − 1 − cos θ)  (θ > 90°),

which is 0 at θ = 0°, 90°, 180° and largest in magnitude, ½(√2 − 1) = 0.2071, at θ = 45° and 135°:
the Red Book's "actual analytic function" is not the analytic function of the two-tone sky.

Conventions: U is any unit vector (the world is y-up, so usually (0, 1, 0)); colours are linear
RGB and the result has the units of the colours (pass radiances to get E/π; multiply by π for
irradiance, :func:`hemisphere_irradiance`).

References
  [1] The hemisphere-lighting formulas as quoted by the project's seed chapter, which attributes the
      piecewise sine form to the OpenGL "Red Book" as "the actual analytic function"; the same pair
      appears in R. Rost, *OpenGL Shading Language* ("Orange Book"), hemisphere lighting section.
  [2] M. F. Cohen, J. R. Wallace, *Radiosity and Realistic Image Synthesis*, 1993, §4 (view factor
      of a differential area to a hemisphere-bounded region; Nusselt analog).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...errors import ValidateError
from ..precision import to_dr

FORMULAS = ("exact", "red_book")


def _as_float(a: np.ndarray) -> Any:
    return to_dr(a)


def _scalars(array_type: Any, values: list[float]) -> list[Any]:
    """The values as scalars of a drjit expression: opaque on a JIT variant (a Python float is a literal baked
    into the kernel, so each new value would compile a new kernel), plain floats otherwise."""
    import drjit as dr

    if dr.is_jit_v(array_type):
        return [dr.opaque(array_type, float(v)) for v in values]
    return [float(v) for v in values]


def sky_weight(cos_theta: Any) -> Any:
    """f = ½ (1 + cos θ) on any array type (numpy or drjit) [1, 2]."""
    return (cos_theta + 1.0) * 0.5


def red_book_weight(cos_theta: Any) -> Any:
    """a = 1 − ½ sin θ (cos θ ≥ 0), ½ sin θ (cos θ < 0), sin θ = √(1 − cos²θ) [1]; drjit arrays."""
    import drjit as dr

    s = dr.sqrt(dr.maximum(1.0 - cos_theta * cos_theta, 0.0))
    return dr.select(cos_theta >= 0.0, 1.0 - 0.5 * s, 0.5 * s)


def blend_weight(cos_theta: np.ndarray, formula: str = "exact") -> np.ndarray:
    """The blend weight of ``formula`` (``exact`` | ``red_book``) at cos θ (numpy in, drjit inside)."""
    c = np.asarray(cos_theta, dtype=np.float64)
    if formula not in FORMULAS:
        raise ValidateError(f"hemisphere formula {formula!r}: expected one of {', '.join(FORMULAS)}")
    if not np.all(np.isfinite(c)) or np.any(np.abs(c) > 1.0 + 1e-6):
        raise ValidateError("hemisphere blend weight: cos θ must be finite and within [−1, 1]")
    x = _as_float(np.clip(c, -1.0, 1.0))
    w = sky_weight(x) if formula == "exact" else red_book_weight(x)
    return np.array(w, dtype=np.float64).reshape(c.shape)


def _require_unit(v: np.ndarray, what: str) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    if v.shape[-1:] != (3,) or not np.all(np.isfinite(v)):
        raise ValidateError(f"hemisphere lighting: {what} must be finite 3-vectors, got shape {v.shape}")
    n = np.linalg.norm(v, axis=-1)
    if np.any(np.abs(n - 1.0) > 1e-4):
        raise ValidateError(f"hemisphere lighting: {what} must be unit vectors (|v| = {n.min():.4g}…{n.max():.4g})")
    return v


def hemisphere_lighting(normals: np.ndarray, sky: np.ndarray, ground: np.ndarray,
                        up: np.ndarray = (0.0, 1.0, 0.0), formula: str = "exact") -> np.ndarray:
    """C(n) = w C_sky + (1 − w) C_ground at unit ``normals`` (N, 3); colours (3,); returns (N, 3)."""
    n = _require_unit(normals, "normals").reshape(-1, 3)
    u = _require_unit(np.asarray(up, dtype=np.float64), "up")
    sky, ground = np.asarray(sky, dtype=np.float64), np.asarray(ground, dtype=np.float64)
    if sky.shape != (3,) or ground.shape != (3,):
        raise ValidateError(f"hemisphere lighting: sky and ground must be RGB triples, got {sky.shape}, {ground.shape}")
    w = blend_weight(np.clip(n @ u, -1.0, 1.0), formula)
    wf = _as_float(w)
    colour = _scalars(type(wf), [*sky, *ground])  # opaque on a JIT variant: one kernel for every colour pair
    out = [np.array(wf * colour[c] + (1.0 - wf) * colour[3 + c], dtype=np.float64) for c in range(3)]
    return np.stack(out, axis=-1)


def hemisphere_irradiance(normals: np.ndarray, sky: np.ndarray, ground: np.ndarray,
                          up: np.ndarray = (0.0, 1.0, 0.0), formula: str = "exact") -> np.ndarray:
    """π · :func:`hemisphere_lighting`: with radiances L_s, L_g this is the irradiance E(n)."""
    return np.pi * hemisphere_lighting(normals, sky, ground, up, formula)


def worst_red_book_deviation() -> tuple[float, float]:
    """(θ in degrees, max |a − f|) of the Red Book weight against the exact one: (45°, ½(√2 − 1))."""
    return 45.0, 0.5 * (np.sqrt(2.0) - 1.0)


# -- registered techniques (family ``irradiance``) ---------------------------------------------------
# Hemisphere lighting needs two colours; from an environment they are derived as the irradiance at the
# poles divided by π, C_sky = E(U)/π and C_ground = E(−U)/π (U = +y), so the technique is exact at
# β = 0° and 180° for every environment and, for a two-tone sky, C_sky = L_s and C_ground = L_g exactly
# (E(U) = π L_s when the whole upper hemisphere has radiance L_s): then ``hemisphere`` is the exact
# irradiance [2]. E(±U) is a cosine-weighted sum over the texels with their exact solid angles
# (:func:`pole_colours`), O(H·W), cheaper than an SH projection.
from ...scenes.latlong import (  # noqa: E402
    col_phi,
    row_solid_angles,
    row_sums,
    row_theta,
    spherical_to_direction,
    texel_solid_angles,
)
from ..families import irradiance as _irradiance  # noqa: E402

WORLD_UP = np.array([0.0, 1.0, 0.0])


def pole_colours(radiance: np.ndarray, up: np.ndarray = WORLD_UP) -> tuple[np.ndarray, np.ndarray]:
    """(C_sky, C_ground) = (E(U)/π, E(−U)/π) of a lat-long map (H, W, 3), E(n) = Σ_t L_t max(0, n·ω_t) Ω_t
    with the texels' exact solid angles Ω_t (:func:`validate.scenes.latlong.texel_solid_angles`)."""
    rad = np.asarray(radiance)
    if rad.ndim != 3 or rad.shape[2] != 3 or rad.shape[0] < 2:
        raise ValidateError(f"hemisphere lighting: radiance must be an (H ≥ 2, W, 3) map, got shape {rad.shape}")
    h, w = rad.shape[:2]
    u = np.asarray(up, dtype=np.float64)
    if np.allclose(u, WORLD_UP):  # U is the map's pole axis: ω·U = cos θ_row for a whole row (one pass over L)
        cos_u = np.cos(row_theta(h))
        rows = row_sums(rad) * texel_solid_angles(h, 1)[:, :1] / w  # Σ_cols L_t Ω_t per row, (H, 3)
        return (np.maximum(cos_u, 0.0) @ rows / np.pi, np.maximum(-cos_u, 0.0) @ rows / np.pi)
    sky, ground = np.zeros(3), np.zeros(3)
    omega, theta, phi = row_solid_angles(h, w), row_theta(h), col_phi(w)
    step = max(1, (1 << 20) // w)  # row blocks: no full-size float64 temporaries
    for s in range(0, h, step):
        cos_u = spherical_to_direction(theta[s:s + step, None], phi[None, :]) @ u
        block = np.asarray(rad[s:s + step], dtype=np.float64) * omega[s:s + step, None, None]
        sky += np.einsum("hwc,hw->c", block, np.maximum(cos_u, 0.0)) / np.pi
        ground += np.einsum("hwc,hw->c", block, np.maximum(-cos_u, 0.0)) / np.pi
    return sky, ground


@_irradiance.register("hemisphere", "hemisphere lighting, cosine blend ½(1 + N·U), C_sky/C_ground = E(±U)/π",
                      source="Cohen & Wallace 1993 §4 (view factor (1 + cos β)/2): exact for a two-tone sky")
def hemisphere_cosine(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """E′(n) = π (f C_sky + (1 − f) C_ground), f = ½(1 + n·U), colours from :func:`pole_colours` [1, 2]."""
    sky, ground = pole_colours(radiance)
    return hemisphere_irradiance(normals, sky, ground, WORLD_UP, "exact")


@_irradiance.register("hemisphere_red_book", "hemisphere lighting, Red Book weight 1 − ½ sin β / ½ sin β, "
                      "C_sky/C_ground = E(±U)/π")
def hemisphere_red_book(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """E′(n) = π (a C_sky + (1 − a) C_ground), the Red Book's piecewise-sine weight a [1]."""
    sky, ground = pole_colours(radiance)
    return hemisphere_irradiance(normals, sky, ground, WORLD_UP, "red_book")
