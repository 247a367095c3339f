"""Exact irradiance from a uniform spherical cap on a tilted plane (sphere and disc lights).

A light of constant radiance L whose silhouette, seen from the receiving point, is a spherical cap
of angular radius σ whose axis makes the angle θ with the receiver's normal gives the irradiance

    E / L = ∫_cap max(0, n·ω) dω.

Which lights are caps:
* a sphere of radius r whose centre is at distance d:        sin²σ = r² / d²           (any point);
* a disc of radius r facing the point on its axis at d:     sin²σ = r² / (r² + d²)    (tan σ = r/d).

Closed form (Snyder 1996 [1]; Lagarde & de Rousiers 2014 [2], §4.7.2):

* cap entirely above the horizon, θ ≤ π/2 − σ  ⇔  cos θ ≥ sin σ:   E/L = π sin²σ cos θ
  (Nusselt: the cap's projection onto the tangent disc is an ellipse of area π sin²σ cos θ);
* cap entirely below the horizon, θ ≥ π/2 + σ:                     E/L = 0;
* cap cut by the horizon, |cos θ| < sin σ:  with x = √(1/sin²σ − 1) (= cot σ), y = −x cos θ / sin θ,
      E/L = (cos θ · acos y − x sin θ √(1 − y²)) sin²σ + atan(sin θ √(1 − y²) / x).

The issue text states the first branch as "if cos²θ > sin²σ, E/L = π sin²σ cos θ". The test
cos²θ > sin²σ is also true for a cap entirely *below* the horizon (cos θ < −sin σ), where that
expression is negative; [2]'s code multiplies by saturate(cos θ), i.e. returns 0 there, and so does
:func:`cap_irradiance`. With that clamp the published horizon-clipped form needs no correction: it is
continuous at both branch points (θ = π/2 − σ gives y = −1, acos y = π, so E/L = π sin²σ cos θ;
θ = π/2 + σ gives y = 1 and E/L = 0), at θ = π/2 it gives E/L = σ − sin σ cos σ (≈ ⅔σ³, the
half-disc moment), and evaluated in float64 it agrees with a brute-force quadrature of
∫_cap max(0, n·ω) dω (:func:`cap_irradiance_quadrature`) to 4·10⁻¹⁴ of π sin²σ for sin²σ ∈ {10⁻⁴,
0.1, 0.25, 0.5, 0.9, 0.999} and θ ∈ [0°, 180°] in 0.05° steps. No factor is missing. The float32
drjit evaluation (:func:`cap_irradiance`) holds 6·10⁻⁷ of π sin²σ for sin²σ ≥ 0.1 and 2.3·10⁻⁵ at
sin²σ = 10⁻⁴, where atan(·) and x sin θ √(1 − y²) sin²σ nearly cancel near the horizon.

References
  [1] J. Snyder, "Area light sources for real-time graphics", Microsoft Research MSR-TR-96-11, 1996.
  [2] S. Lagarde, C. de Rousiers, "Moving Frostbite to Physically Based Rendering 3.0", SIGGRAPH
      2014 course notes, §4.7.2 (sphere and disk lights; horizon handling, "illuminanceSphereOrDisk").
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...errors import ValidateError
from ..precision import constants_dr, to_dr, to_np, vec_to_dr

X_FLOOR = 1e-30  # cot σ floor in the atan term: float32-normal, far below any x > 0 (cap_irradiance_dr)


def sin2_sigma_sphere(radius: float, distance: float) -> float:
    """sin²σ = r²/d² of a sphere of radius r at centre distance d > r."""
    if not (radius > 0 and distance > radius):
        raise ValidateError(f"sphere light: need 0 < radius < distance, got radius={radius}, distance={distance}")
    return float(radius * radius / (distance * distance))


def sin2_sigma_disc(radius: float, distance: float) -> float:
    """sin²σ = r²/(r² + d²) of a disc of radius r facing a point on its axis at distance d > 0."""
    if not (radius > 0 and distance > 0):
        raise ValidateError(f"disc light: need radius > 0 and distance > 0, got radius={radius}, distance={distance}")
    return float(radius * radius / (radius * radius + distance * distance))


def _check(cos_theta: np.ndarray, sin2_sigma: float) -> np.ndarray:
    c = np.asarray(cos_theta, dtype=np.float64)
    if not (0.0 < sin2_sigma < 1.0):
        raise ValidateError(f"spherical cap: sin²σ = {sin2_sigma} must lie in (0, 1)")
    if not np.all(np.isfinite(c)) or np.any(np.abs(c) > 1.0 + 1e-6):
        raise ValidateError("spherical cap: cos θ must be finite and within [−1, 1]")
    return np.clip(c, -1.0, 1.0)


def cap_irradiance_dr(cos_theta: Any, sin2_sigma: Any) -> Any:
    """E/L of the cap on drjit arrays (the formula of the module docstring [1, 2], branch-free).

    ``sin2_sigma`` is one float for every point or a drjit array with one sin²σ per point (a disc light
    seen from many receivers, :func:`validate.local_models.shadow.shadow_map.disc_irradiance`); it must lie in
    (0, 1], unchecked. x = cot σ is floored at 10⁻³⁰ inside atan(sin θ √(1 − y²) / x) only, so a
    sin²σ that rounds to 1 in float32 (x = 0) gives atan2's limit (π/2, or 0 at sin θ = 0), not NaN;
    every x > 0 is unchanged by the floor."""
    import drjit as dr

    c = cos_theta
    s = dr.sqrt(dr.maximum(1.0 - c * c, 0.0))
    above = c * c > sin2_sigma
    e_full = dr.pi * sin2_sigma * dr.maximum(c, 0.0)
    x = dr.sqrt(dr.maximum(1.0 / sin2_sigma - 1.0, 0.0))  # cot σ
    y = dr.clip(-x * c / dr.maximum(s, 1e-12), -1.0, 1.0)
    sq = s * dr.sqrt(dr.maximum(1.0 - y * y, 0.0))
    e_clip = (c * dr.acos(y) - x * sq) * sin2_sigma + dr.atan(sq / dr.maximum(x, X_FLOOR))
    return dr.select(above, e_full, dr.maximum(e_clip, 0.0))


def cap_irradiance(cos_theta: np.ndarray, sin2_sigma: float) -> np.ndarray:
    """E/L of a uniform cap (sin²σ) whose axis makes angle θ with the normal; numpy in/out, drjit inside in the
    active dtype (:mod:`validate.local_models.precision`: float32 when called directly, as the arealights
    experiment's closed-form claim does; the family's float64 inside ``arealight.call``)."""
    c = _check(cos_theta, sin2_sigma)
    return to_np(cap_irradiance_dr(to_dr(c), sin2_sigma), c.shape)


def cap_irradiance_unclipped(cos_theta: np.ndarray, sin2_sigma: float) -> np.ndarray:
    """π sin²σ max(cos θ, 0): the first branch used everywhere (what a point light gives; no horizon
    clipping). Used as a negative control for the reference comparisons."""
    c = _check(cos_theta, sin2_sigma)
    return np.pi * sin2_sigma * np.maximum(c, 0.0)


def cap_irradiance_quadrature(cos_theta: np.ndarray, sin2_sigma: float, nodes: int = 256) -> np.ndarray:
    """Slow, obviously correct E/L: ∫_cap max(0, n·ω) dω by quadrature in the cap's own frame.

    The cap is parametrised by the angle t ∈ [0, σ] from its axis and the azimuth φ around it,
    dω = sin t dt dφ. For each t the azimuths where n·ω > 0 form one interval whose end points are
    solved for exactly (n·ω = cos t cos θ + sin t sin θ cos φ is linear in cos φ), and the integrand
    is integrated over φ in closed form: ∫ (A + B cos φ) dφ = A Δφ + B Δ(sin φ). Only the t integral
    is numerical: ``nodes``-point Gauss–Legendre on each side of t_h = |π/2 − θ|, the circle that
    touches the horizon (where the φ interval starts to shrink), so no kink lies inside a panel.
    """
    c = _check(cos_theta, sin2_sigma).ravel()
    sigma = float(np.arcsin(np.sqrt(sin2_sigma)))
    xg, wg = np.polynomial.legendre.leggauss(nodes)
    u, wu = 0.5 * (xg + 1.0), 0.5 * wg  # Gauss–Legendre on [0, 1]
    th = np.arccos(c)
    split = np.minimum(np.abs(0.5 * np.pi - th), sigma)[:, None]  # (M, 1)
    t = np.concatenate([split * u[None, :], split + (sigma - split) * u[None, :]], axis=1)  # (M, 2n)
    wt = np.concatenate([split * wu[None, :], (sigma - split) * wu[None, :]], axis=1)
    a = np.cos(t) * c[:, None]  # A(t): the part independent of φ
    b = np.sin(t) * np.sin(th)[:, None]  # B(t) ≥ 0: the coefficient of cos φ
    # n·ω ≥ 0  ⇔  cos φ ≥ −A/B; the positive set is |φ| ≤ φ0 with φ0 = acos(clip(−A/B)).
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(b > 0, -a / b, np.where(a >= 0, -np.inf, np.inf))
    phi0 = np.arccos(np.clip(ratio, -1.0, 1.0))
    inner = 2.0 * (a * phi0 + b * np.sin(phi0))  # ∫_{−φ0}^{φ0} (A + B cos φ) dφ
    return (inner * np.sin(t) * wt).sum(axis=1).reshape(np.shape(cos_theta))


# -- the ``arealight`` family: light mapping → per-receiver cap geometry ---------------------------
def _vec3(light: Any, key: str) -> np.ndarray:
    v = np.asarray(light.get(key, (0.0, 0.0, 1.0) if key == "normal" else None), dtype=np.float64)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValidateError(f"area light: '{key}' must be a finite 3-vector, got {light.get(key)!r}")
    return v


def _checked_light(light: Any) -> tuple[str, np.ndarray, np.ndarray, float, float]:
    """(shape, centre, normal, radius, radiance) of a disc or sphere light mapping; one-line errors otherwise."""
    shape = light.get("shape") if hasattr(light, "get") else None
    if shape not in ("disc", "sphere"):
        raise ValidateError(f"area light: shape {shape!r} not supported by the cap techniques (disc, sphere)")
    c, m = _vec3(light, "center"), _vec3(light, "normal")
    r, rad = float(light.get("radius", np.nan)), float(light.get("radiance", 1.0))
    if not (np.isfinite(r) and r > 0 and np.isfinite(rad) and rad >= 0):
        raise ValidateError(f"area light: need radius > 0 and radiance ≥ 0, got radius={r}, radiance={rad}")
    return shape, c, m, r, rad


def light_geometry(light: Any, points: np.ndarray, normals: np.ndarray) -> dict[str, np.ndarray]:
    """What every cap-based arealight technique needs, per receiver (arrays of length N):

    ``distance`` d = |c − p|, ``cos_theta`` = n·(c − p)/d (normal vs direction to the centre),
    ``cos_psi`` = m·(p − c)/d (the light's normal m vs the direction to the receiver; 1 for a sphere),
    ``sin2_sigma``: sphere r²/d²; disc r²/(r² + d²) (the cap a facing disc subtends from its axis [2]),
    ``radius``, ``radiance``. A receiver inside a sphere light (d ≤ r) is an error."""
    shape, c, m, r, rad = _checked_light(light)
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    v = c[None, :] - p
    d = np.linalg.norm(v, axis=1)
    if shape == "sphere" and np.any(d <= r):
        raise ValidateError("area light: a receiver lies inside the sphere light (distance ≤ radius)")
    if np.any(d <= 0):
        raise ValidateError("area light: a receiver lies at the light's centre")
    u = v / d[:, None]
    cos_psi = np.ones_like(d) if shape == "sphere" else -(u @ (m / np.linalg.norm(m)))
    s2 = r * r / (d * d) if shape == "sphere" else r * r / (r * r + d * d)
    return {"distance": d, "cos_theta": np.clip(np.einsum("ij,ij->i", n, u), -1.0, 1.0), "cos_psi": cos_psi,
            "sin2_sigma": s2, "radius": np.full_like(d, r), "radiance": np.full_like(d, rad), "shape": shape}


def light_geometry_dr(light: Any, points: np.ndarray, normals: np.ndarray) -> dict[str, Any]:
    """:func:`light_geometry` computed on drjit arrays of the active dtype (:mod:`..precision`): the same keys,
    ``distance``, ``cos_theta``, ``cos_psi``, ``sin2_sigma`` as flat drjit arrays, ``radius`` and ``radiance``
    as opaque width-1 drjit arrays (:func:`~..precision.constants_dr`), ``shape`` and ``n`` (the receiver
    count). The light's parameters and the receivers' distances are checked as there (one-line errors)."""
    import drjit as dr

    shape, c, m, r, rad = _checked_light(light)
    px, py, pz = vec_to_dr(points)
    nx, ny, nz = vec_to_dr(normals)
    # the light's numbers as opaque values: a Python float is a kernel literal, a new light a new kernel
    cx, cy, cz, mx, my, mz, rr, rl = constants_dr(np.r_[c, m / np.linalg.norm(m), r, rad])
    vx, vy, vz = cx - px, cy - py, cz - pz
    d = dr.sqrt(vx * vx + vy * vy + vz * vz)
    d_np = to_np(d)
    if shape == "sphere" and np.any(d_np <= r):
        raise ValidateError("area light: a receiver lies inside the sphere light (distance ≤ radius)")
    if np.any(d_np <= 0):
        raise ValidateError("area light: a receiver lies at the light's centre")
    inv = 1.0 / d
    ux, uy, uz = vx * inv, vy * inv, vz * inv
    cos_psi = d * 0.0 + 1.0 if shape == "sphere" else -(ux * mx + uy * my + uz * mz)
    s2 = rr * rr / (d * d) if shape == "sphere" else rr * rr / (rr * rr + d * d)
    return {"distance": d, "cos_theta": dr.clip(nx * ux + ny * uy + nz * uz, -1.0, 1.0), "cos_psi": cos_psi,
            "sin2_sigma": s2, "radius": rr, "radiance": rl, "shape": shape, "n": int(d_np.size)}
