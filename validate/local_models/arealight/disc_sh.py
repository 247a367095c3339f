"""Spherical harmonics of a uniform disc light (a spherical cap), rotated to any direction.

A distant disc of half-angle α and unit radiance, centred on the SH polar axis, is the zonal function
L(ω) = 1 for cos θ ≥ cos α. Its zonal coefficients are (real SH of :mod:`validate.local_models.irradiance.sh`,
Y_l0 = √((2l+1)/4π) P_l)

    z_l = 2π ∫_{cos α}^{1} Y_l0(x) dx = √((2l+1)/4π) · 2π ∫_{cos α}^{1} P_l(x) dx,

and with the Legendre integral ∫ P_l dx = (P_{l+1} − P_{l−1}) / (2l+1) (DLMF §14.10 [4]; P_l(1) = 1)

    z_0 = √π (1 − cos α),        z_l = √(π / (2l+1)) · (P_{l−1}(cos α) − P_{l+1}(cos α))   (l ≥ 1).

For l ≤ 2 this is the seed chapter's table [1]: L00 = 1.77245 (1 − cos α), L10 = 1.53499 sin²α,
L20 = 1.98166 (cos α − cos³α) (√π, (3/2)√(π/3), (5/2)√(π/5)).

Rotation to a light direction d (zonal rotation [2, 3]):  L_lm = √(4π/(2l+1)) z_l Y_lm(d).

Irradiance (R&H 2001 [5], E = Σ Â_l L_lm Y_lm(n), Â_l = A_l of the clamped cosine): by the addition
theorem Σ_m Y_lm(d) Y_lm(n) = (2l+1)/4π P_l(d·n), so with z = cos θ = d·n

    E_N(z) = Σ_{l ≤ N} A_l z_l √((2l+1)/4π) P_l(z),

which at N = 2 is the seed's E = 1.57079 (1 − cos α) + 1.57080 sin²α z + 0.490874 (cos α − cos³α)(3z² − 1)
(π/2, π/2 and 5π/32). At α = 20°: 0.0947305 + 0.183748 z + 0.0539584 (3z² − 1).

Two evaluation paths that must agree (tests): the *zonal* path (:func:`disc_irradiance_sh`,
Legendre polynomials of d·n) and the *rotated* path (:func:`disc_coefficients` → full (N+1)² SH
vector → :func:`validate.local_models.irradiance.sh.render_irradiance`), the one an engine runs. The slow,
obviously correct path is :func:`project_cap_numerical` (quadrature of the cap in its own frame).

Precision: the zonal coefficients of one light (:func:`zonal_cap`, a few numbers) are float64 numpy;
1 − cos α is evaluated as 2 sin²(α/2) and cos α − cos³α as cos α sin²α to avoid cancellation at small α.
The registered techniques see a different cap from every receiver, so they compute z_l per receiver in
drjit (:func:`zonal_cap_dr`) in the ``arealight`` family's dtype, float64: P_{l−1}(cos α) − P_{l+1}(cos α)
cancels as α → 0 (float32 loses 1.6·10⁻⁴ of π sin²σ at sin²σ = 10⁻⁴, :mod:`..families`). Helpers called
directly (:func:`disc_irradiance_sh`) run in the active dtype of :mod:`..precision` (float32 by default).

References
  [1] The project's seed chapter: SH projection of a disc light, and the order-2 irradiance above.
  [2] P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008 — zonal harmonics and their
      rotation, L_lm = √(4π/(2l+1)) z_l Y_lm(d).
  [3] P.-P. Sloan, B. Luna, J. Snyder, "Local, Deformable Precomputed Radiance Transfer", SIGGRAPH
      2005 (zonal harmonics and their rotation).
  [4] NIST DLMF §14.10 (Legendre recurrences): (2l+1) P_l = P′_{l+1} − P′_{l−1}.
  [5] R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
      SIGGRAPH 2001 — eq. 8; A_l from "On the relationship between radiance and irradiance", 2001.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...errors import ValidateError
from ..irradiance import sh
from ..precision import to_dr, to_np

# The seed chapter's rounded constants [1] (unit radiance).
SEED_L00 = 1.77245  # √π
SEED_L10 = 1.53499  # (3/2)√(π/3)
SEED_L20 = 1.98166  # (5/2)√(π/5)
SEED_E0 = 1.57079  # π/2      (times 1 − cos α)
SEED_E1 = 1.57080  # π/2      (times sin²α · z)
SEED_E2 = 0.490874  # 5π/32   (times (cos α − cos³α)(3z² − 1))
SEED_E_20DEG = (0.0947305, 0.183748, 0.0539584)  # the seed's α = 20° coefficients of 1, z, 3z² − 1


def _check_alpha(alpha: Any) -> np.ndarray:
    a = np.asarray(alpha, dtype=np.float64)
    if not np.all(np.isfinite(a)) or np.any(a <= 0.0) or np.any(a > np.pi):
        raise ValidateError(f"disc light: half-angle α must lie in (0, π] radians, got {alpha}")
    return a


def _check_lmax(lmax: int) -> int:
    if not (isinstance(lmax, (int, np.integer)) and 0 <= lmax <= 32):
        raise ValidateError(f"SH order l_max = {lmax!r}: expected an integer in [0, 32]")
    return int(lmax)


def legendre(x: Any, lmax: int) -> list[Any]:
    """[P_0(x), …, P_lmax(x)] by Bonnet's recurrence (l+1) P_{l+1} = (2l+1) x P_l − l P_{l−1}; any array type."""
    out = [x * 0.0 + 1.0, x * 1.0]
    for l in range(1, lmax):
        out.append((out[l] * x * (2 * l + 1) - out[l - 1] * l) * (1.0 / (l + 1)))
    return out[: lmax + 1]


def zonal_cap(alpha: Any, lmax: int) -> np.ndarray:
    """Zonal coefficients z_0 … z_lmax (rows) of a unit-radiance cap of half-angle α (radians)."""
    a = _check_alpha(alpha)
    lmax = _check_lmax(lmax)
    c = np.cos(a)
    p = legendre(c, lmax + 1)
    z = [math.sqrt(math.pi) * 2.0 * np.sin(0.5 * a) ** 2]
    for l in range(1, lmax + 1):
        z.append(math.sqrt(math.pi / (2 * l + 1)) * (p[l - 1] - p[l + 1]))
    return np.stack(np.broadcast_arrays(*z), axis=0)


def seed_zonal_order2(alpha: Any) -> np.ndarray:
    """The seed's (L00, L10, L20) = (1.77245 (1 − cos α), 1.53499 sin²α, 1.98166 (cos α − cos³α)) [1]."""
    a = _check_alpha(alpha)
    c, s2 = np.cos(a), np.sin(a) ** 2
    return np.stack(np.broadcast_arrays(SEED_L00 * 2.0 * np.sin(0.5 * a) ** 2, SEED_L10 * s2, SEED_L20 * c * s2))


def seed_irradiance_order2(alpha: float, z: np.ndarray) -> np.ndarray:
    """The seed's E = 1.57079 (1 − cos α) + 1.57080 sin²α z + 0.490874 (cos α − cos³α)(3z² − 1) [1]."""
    a = float(_check_alpha(alpha))
    z = np.asarray(z, dtype=np.float64)
    c, s2 = math.cos(a), math.sin(a) ** 2
    return SEED_E0 * 2.0 * math.sin(0.5 * a) ** 2 + SEED_E1 * s2 * z + SEED_E2 * c * s2 * (3 * z * z - 1)


def irradiance_polynomial_order2(alpha: float) -> tuple[float, float, float]:
    """Exact (k0, k1, k2) of E_2 = k0 + k1 z + k2 (3z² − 1) from the zonal coefficients:
    k_l = A_l z_l √((2l+1)/4π) × (1, 1, ½) — compare :data:`SEED_E_20DEG` at α = 20°."""
    z = zonal_cap(alpha, 2)
    k = [sh.clamped_cosine_al(l) * float(z[l]) * math.sqrt((2 * l + 1) / (4 * math.pi)) for l in range(3)]
    return k[0], k[1], 0.5 * k[2]


def rotate_zonal(zonal: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """L_lm = √(4π/(2l+1)) z_l Y_lm(d) [2]: ((lmax+1)²,) coefficients of the zonal function turned to d."""
    zonal = np.asarray(zonal, dtype=np.float64).ravel()
    d = np.asarray(direction, dtype=np.float64)
    if d.shape != (3,) or abs(np.linalg.norm(d) - 1.0) > 1e-6:
        raise ValidateError(f"zonal rotation: direction must be a unit 3-vector, got {direction}")
    lmax = zonal.size - 1
    y = sh.eval_basis_numpy(d, lmax)
    scale = np.array([math.sqrt(4 * math.pi / (2 * sh.degree_of(k) + 1)) * zonal[sh.degree_of(k)]
                      for k in range(sh.n_coeffs(lmax))])
    return scale * y


def disc_coefficients(alpha: float, direction: np.ndarray, lmax: int,
                      radiance: np.ndarray = (1.0, 1.0, 1.0)) -> np.ndarray:
    """((lmax+1)², 3) SH coefficients of a disc of half-angle α and RGB ``radiance`` centred on d."""
    rgb = np.asarray(radiance, dtype=np.float64)
    if rgb.shape != (3,):
        raise ValidateError(f"disc light: radiance must be an RGB triple, got shape {rgb.shape}")
    return rotate_zonal(zonal_cap(float(alpha), lmax), direction)[:, None] * rgb[None, :]


def zonal_irradiance_dr(zonal: np.ndarray, cos_theta: Any) -> Any:
    """E_N = Σ_l A_l z_l √((2l+1)/4π) P_l(cos θ) on drjit arrays (zonal irradiance, [5] + addition theorem)."""
    lmax = len(zonal) - 1
    p = legendre(cos_theta, lmax)
    e = cos_theta * 0.0
    for l in range(lmax + 1):
        k = sh.clamped_cosine_al(l) * float(zonal[l]) * math.sqrt((2 * l + 1) / (4 * math.pi))
        if k != 0.0:
            e = e + p[l] * k
    return e


def disc_irradiance_sh(alpha: float, cos_theta: np.ndarray, lmax: int) -> np.ndarray:
    """Order-``lmax`` SH irradiance of a unit-radiance disc (half-angle α) at normals with d·n = cos θ."""
    c = np.asarray(cos_theta, dtype=np.float64)
    if not np.all(np.isfinite(c)) or np.any(np.abs(c) > 1.0 + 1e-6):
        raise ValidateError("disc SH irradiance: cos θ must be finite and within [−1, 1]")
    e = zonal_irradiance_dr(zonal_cap(float(alpha), lmax), to_dr(np.clip(c, -1, 1)))
    return to_np(e, c.shape)


def disc_irradiance_sh_rotated(alpha: float, direction: np.ndarray, normals: np.ndarray, lmax: int) -> np.ndarray:
    """The engine path: rotate the zonal vector to d, then E(n) = Σ Â_l L_lm Y_lm(n) ([5] eq. 8); (N,)."""
    coeffs = disc_coefficients(alpha, direction, lmax)[:, :1]
    return sh.render_irradiance(np.repeat(coeffs, 3, axis=1), np.asarray(normals, dtype=np.float64), lmax)[:, 0]


def project_cap_numerical(alpha: float, direction: np.ndarray, lmax: int, nodes: int = 48) -> np.ndarray:
    """Slow, obviously correct projection: L_lm = ∫_cap Y_lm(ω) dω by quadrature in the cap's frame.

    ω = cos t · d + sin t (cos φ e1 + sin φ e2), dω = sin t dt dφ, t ∈ [0, α] by ``nodes``-point
    Gauss–Legendre (smooth integrand), φ by the (4·lmax + 8)-point midpoint rule, which is exact for
    the trigonometric polynomials of degree ≤ lmax that Y_lm(ω(t, ·)) is. Returns ((lmax+1)²,).
    """
    a = float(_check_alpha(alpha))
    lmax = _check_lmax(lmax)
    d = np.asarray(direction, dtype=np.float64)
    d = d / np.linalg.norm(d)
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(d, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(d, e1)
    xg, wg = np.polynomial.legendre.leggauss(nodes)
    t, wt = 0.5 * a * (xg + 1.0), 0.5 * a * wg
    m = 4 * lmax + 8
    phi = (np.arange(m) + 0.5) * (2 * np.pi / m)
    tt, pp = np.meshgrid(t, phi, indexing="ij")
    w = (np.sin(tt) * wt[:, None] * (2 * np.pi / m)).ravel()
    dirs = (np.cos(tt)[..., None] * d + np.sin(tt)[..., None]
            * (np.cos(pp)[..., None] * e1 + np.sin(pp)[..., None] * e2)).reshape(-1, 3)
    return sh.eval_basis_numpy(dirs, lmax).T @ w


def zonal_cap_dr(alpha: Any, lmax: int) -> list[Any]:
    """:func:`zonal_cap` on a drjit array of half-angles (one per receiver), in its dtype:
    z_0 = 2√π sin²(α/2), z_l = √(π/(2l+1)) (P_{l−1}(cos α) − P_{l+1}(cos α)) — the difference cancels as
    α → 0, which is why the ``arealight`` family computes in float64 (:mod:`..families`)."""
    import drjit as dr

    p = legendre(dr.cos(alpha), lmax + 1)
    h = dr.sin(0.5 * alpha)
    return [2.0 * math.sqrt(math.pi) * h * h] + [math.sqrt(math.pi / (2 * l + 1)) * (p[l - 1] - p[l + 1])
                                                 for l in range(1, lmax + 1)]


def cap_irradiance_sh_dr(sin2_sigma: Any, cos_theta: Any, lmax: int) -> Any:
    """E_N = Σ_l A_l z_l √((2l+1)/4π) P_l(cos θ) on drjit arrays, z_l(α) of each receiver's cap,
    α = asin √sin²σ (:func:`zonal_cap_dr`)."""
    import drjit as dr

    s2 = dr.clip(sin2_sigma, 0.0, 1.0)
    z = zonal_cap_dr(dr.atan2(dr.sqrt(s2), dr.sqrt(1.0 - s2)), lmax)  # α = asin √sin²σ (atan2: drjit.scalar lacks asin)
    x = dr.clip(cos_theta, -1.0, 1.0)
    p = legendre(x, lmax)
    e = x * 0.0
    for l in range(lmax + 1):
        k = sh.clamped_cosine_al(l) * math.sqrt((2 * l + 1) / (4 * math.pi))
        if k != 0.0:
            e = e + p[l] * z[l] * k
    return e


def cap_irradiance_sh(sin2_sigma: np.ndarray, cos_theta: np.ndarray, lmax: int) -> np.ndarray:
    """Order-``lmax`` SH irradiance of unit-radiance caps, one (sin²σ, cos θ) per receiver; numpy in/out,
    :func:`cap_irradiance_sh_dr` in the active dtype inside; (N,)."""
    s2 = np.asarray(sin2_sigma, dtype=np.float64).ravel()
    c = np.asarray(cos_theta, dtype=np.float64).ravel()
    return to_np(cap_irradiance_sh_dr(to_dr(s2), to_dr(c), lmax), (s2.size,))


# -- registered techniques (family ``arealight``) ----------------------------------------------------
from ..families import arealight as _arealight  # noqa: E402
from .sphere_cap import light_geometry_dr  # noqa: E402


def _sh_technique(lmax: int):  # noqa: ANN202 (returns the technique function)
    def fn(light: Any, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
        import drjit as dr

        g = light_geometry_dr(light, points, normals)
        e = cap_irradiance_sh_dr(g["sin2_sigma"], g["cos_theta"], lmax) * g["radiance"]
        return to_np(e * dr.maximum(g["cos_psi"], 0.0), (g["n"],))
    fn.__doc__ = (f"Order-{lmax} zonal SH of the cap each receiver sees (sphere: sin α = r/d; disc: the cap of its "
                  "axis, tan α = r/d, times max(0, cos ψ)), irradiance Σ_l A_l z_l √((2l+1)/4π) P_l(cos θ) [1, 5].")
    fn.__name__ = fn.__qualname__ = f"sh_order{lmax}"
    return fn


for _l, _why in ((2, "the seed's order 2 (9 coefficients)"), (4, "order 4 (25 coefficients)"),
                 (8, "order 8 (81 coefficients)")):
    _arealight.add(f"sh_order{_l}", _sh_technique(_l), f"disc/sphere light as a cap in zonal SH, {_why}",
                   shapes=("sphere", "disc"), lmax=_l)
