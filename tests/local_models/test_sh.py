"""Real SH basis, clamped-cosine A_l, R&H 2001 constants and SH irradiance (validate.local_models.irradiance.sh).

Oracles: numerical quadrature (Gram matrix, Legendre projection), scipy's complex SH (an independent
implementation), closed forms printed in Ramamoorthi & Hanrahan 2001 [1, eq. 8, 12] and JOSA 2001
[2, eq. 19], and the directional-light theorem: for a delta light SH9 irradiance errs by exactly
3/32·Φ at the terminator and by 0.030674·Φ on average over the sphere.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import special

from validate.local_models.irradiance import sh
from validate.metrics import irradiance_error
from validate.scenes import latlong, procedural

LMAX_TESTED = 8
# float64 evaluation of polynomials of degree ≤ 8 with O(1) coefficients: ~1e-15 per term.
FLOAT64_TOL = 1e-12
# R&H print their constants to six decimals: the rounding error is at most 5e-7.
SIX_DECIMALS_TOL = 5e-7


def _random_directions(n: int, seed: int) -> np.ndarray:
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def _gauss_legendre_sphere(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Product rule: n Gauss–Legendre nodes in z = cos θ × 2n uniform φ. Exact for polynomials in
    (x, y, z) of degree ≤ 2n − 1 (z) and < 2n in the azimuthal frequency."""
    z, wz = np.polynomial.legendre.leggauss(n)
    phi = (np.arange(2 * n) + 0.5) * (np.pi / n)
    zz, pp = np.meshgrid(z, phi, indexing="ij")
    r = np.sqrt(1 - zz**2)
    d = np.stack([r * np.cos(pp), r * np.sin(pp), zz], axis=-1).reshape(-1, 3)
    w = (wz[:, None] * np.full(2 * n, np.pi / n)[None, :]).reshape(-1)
    return d, w


def real_sh_scipy(d: np.ndarray, lmax: int) -> np.ndarray:
    """Slow, obviously correct reference: real SH without the Condon–Shortley phase from scipy's
    complex Y_l^m (which includes (−1)^m):  Y_l0 = Y_l^0,  Y_lm = √2 (−1)^m Re Y_l^m,
    Y_l,−m = √2 (−1)^m Im Y_l^m  (m > 0); θ from +z, φ = atan2(y, x)."""
    theta = np.arccos(np.clip(d[:, 2], -1, 1))
    phi = np.arctan2(d[:, 1], d[:, 0])
    out = np.zeros((d.shape[0], (lmax + 1) ** 2))
    for l in range(lmax + 1):
        out[:, sh.sh_index(l, 0)] = special.sph_harm_y(l, 0, theta, phi).real
        for m in range(1, l + 1):
            c = special.sph_harm_y(l, m, theta, phi) * (-1) ** m * math.sqrt(2)
            out[:, sh.sh_index(l, m)] = c.real
            out[:, sh.sh_index(l, -m)] = c.imag
    return out


# --- the basis --------------------------------------------------------------------------------------

def test_orthonormal_gauss_legendre() -> None:
    """Y_lm·Y_l'm' has degree ≤ 16: a 24-node product rule integrates it exactly (float64 only)."""
    d, w = _gauss_legendre_sphere(24)
    y = sh.eval_basis_numpy(d, LMAX_TESTED)
    gram = (y * w[:, None]).T @ y
    assert np.abs(gram - np.eye(sh.n_coeffs(LMAX_TESTED))).max() < FLOAT64_TOL


def test_orthonormal_latlong_texel_quadrature() -> None:
    """The same Gram matrix with the rule ``project_environment`` uses (texel directions × exact cell
    solid angles) at 256×512: a midpoint rule in θ, error O((l Δθ)²). Measured max |G − I| = 4.0e-5."""
    tol = 1e-4
    d = latlong.texel_directions(256, 512).reshape(-1, 3)
    w = latlong.texel_solid_angles(256, 512).reshape(-1)
    y = sh.eval_basis_numpy(d, LMAX_TESTED)
    gram = (np.ascontiguousarray(y.T) * w) @ y
    assert np.abs(gram - np.eye(sh.n_coeffs(LMAX_TESTED))).max() < tol


def test_basis_equals_scipy_reference() -> None:
    d = _random_directions(500, seed=0)
    assert np.abs(sh.eval_basis_numpy(d, LMAX_TESTED) - real_sh_scipy(d, LMAX_TESTED)).max() < FLOAT64_TOL


def test_rh2001_basis_constants() -> None:
    """The polynomials printed in [1] (no Condon–Shortley phase), to their six decimals."""
    d = _random_directions(200, seed=2)
    x, y, z = d.T
    expected = np.stack([
        np.full_like(x, 0.282095),
        0.488603 * y, 0.488603 * z, 0.488603 * x,
        1.092548 * x * y, 1.092548 * y * z, 0.315392 * (3 * z * z - 1), 1.092548 * x * z,
        0.546274 * (x * x - y * y),
    ], axis=-1)
    # |polynomial| ≤ 2 for the constants' rounding of 5e-7 → 1e-6.
    assert np.abs(sh.eval_basis_numpy(d, 2) - expected).max() < 2 * SIX_DECIMALS_TOL


def test_index_helpers() -> None:
    assert [sh.sh_index(l, m) for l in range(3) for m in range(-l, l + 1)] == list(range(9))
    assert [sh.degree_of(k) for k in range(9)] == [0, 1, 1, 1, 2, 2, 2, 2, 2]
    assert sh.n_coeffs(2) == 9 and sh.n_coeffs(8) == 81


# --- the clamped cosine -----------------------------------------------------------------------------

def test_clamped_cosine_al_published_values() -> None:
    """A0 = π, A1 = 2π/3, A2 = π/4, A4 = −π/24, A6 = π/64, A8 = −π/128, odd l > 1: 0 ([2]; R&H
    2001 §2 as listed in ../shared/reference/README.md)."""
    published = {0: math.pi, 1: 2 * math.pi / 3, 2: math.pi / 4, 4: -math.pi / 24, 6: math.pi / 64,
                 8: -math.pi / 128}
    for l, value in published.items():
        assert abs(sh.clamped_cosine_al(l) - value) < FLOAT64_TOL, l
    for l in range(3, 12, 2):
        assert sh.clamped_cosine_al(l) == 0.0, l


@pytest.mark.parametrize("l", range(11))
def test_clamped_cosine_al_is_legendre_projection(l: int) -> None:
    """A_l = 2π ∫₋₁¹ P_l(x) max(x, 0) dx = 2π ∫₀¹ P_l(x) x dx: a polynomial of degree l + 1, exact
    with 20 Gauss–Legendre nodes on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(20)
    x, w = (x + 1) / 2, w / 2
    numeric = 2 * np.pi * np.sum(w * special.eval_legendre(l, x) * x)
    assert abs(sh.clamped_cosine_al(l) - numeric) < FLOAT64_TOL


def test_rh2001_constants_from_al_and_normalisation() -> None:
    """c1…c5 of [1, eq. 12] are A_l times basis constants (expanding eq. 8 for l ≤ 2):
    c1 = A2·k22 = A2·√(15/4π)/2, c2 = A1·√(3/4π)/2, c3 = 3·A2·√(5/16π), c4 = A0·√(1/4π),
    c5 = A2·√(5/16π).

    The printed values are not all correctly rounded: measured differences from the exact forms are
    c1 4e-7, c2 6.5e-7, c3 1.1e-6, c4 1e-7, c5 4e-8. c2 and c3 match A_l times R&H's *rounded* basis
    constants (A1·0.488603/2 = 0.5116639, 3·A2·0.315392 = 0.7431249). Budget: 3·A2·5e-7 (a rounded
    basis constant) + 5e-7 (the final rounding) = 1.7e-6 → tolerance 2e-6."""
    exact_tol = 2e-6
    a0, a1, a2 = (sh.clamped_cosine_al(l) for l in range(3))
    exact = {
        "C1": a2 * math.sqrt(15 / (4 * math.pi)) / 2,
        "C2": a1 * math.sqrt(3 / (4 * math.pi)) / 2,
        "C3": 3 * a2 * math.sqrt(5 / (16 * math.pi)),
        "C4": a0 * math.sqrt(1 / (4 * math.pi)),
        "C5": a2 * math.sqrt(5 / (16 * math.pi)),
    }
    for name in exact:
        assert abs(getattr(sh, name) - exact[name]) < exact_tol, name


def test_render_al_form_equals_quadratic_form() -> None:
    """Eq. 8 (A_l form) and eq. 12 (quadratic form) are the same function. Differences: the printed
    c1…c5 (≤ 1.2e-6 from exact, see above, times |polynomial| ≤ 2 and |L|) plus float32 evaluation
    (~1e-7·Σ|L|), so ≤ 2.5e-6·Σ|L|. Measured 2.7e-6 with Σ|L| = 8.5, i.e. 3.2e-7·Σ|L|."""
    rng = np.random.default_rng(4)
    coeffs = rng.normal(size=(9, 3))
    normals = latlong.fibonacci_sphere(5000)
    tol = 3e-6 * np.abs(coeffs).sum(axis=0)
    a = sh.render_irradiance(coeffs, normals)
    b = sh.render_irradiance_rh2001(coeffs, normals)
    assert (np.abs(a - b).max(axis=0) < tol).all()
    # and both equal the float64 numpy evaluation of Σ A_l L_lm Y_lm
    al = np.array([sh.clamped_cosine_al(sh.degree_of(k)) for k in range(9)])
    exact = (sh.eval_basis_numpy(normals, 2) * al) @ coeffs
    assert (np.abs(a - exact).max(axis=0) < tol).all()


# --- projection -------------------------------------------------------------------------------------

def test_bandlimited_round_trip() -> None:
    """project_environment(bandlimited) recovers BANDLIMITED_SH. The texel rule is second order
    in Δθ = π/(H−1): measured max |ΔL| = 3.2e-4, 7.9e-5, 1.9e-5 at H = 64, 128, 256 (ratio ≈ 4)."""
    tol_at_128 = 2e-4
    coeffs = sh.project_environment(procedural.bandlimited(128).radiance, 2)
    assert np.abs(coeffs - procedural.BANDLIMITED_SH).max() < tol_at_128
    # a higher-order projection of an order-2 function has (nearly) empty bands 3, 4
    c4 = sh.project_environment(procedural.bandlimited(128).radiance, 4)
    assert np.abs(c4[:9] - coeffs).max() < 1e-6  # same rule, same float32 path
    assert np.abs(c4[9:]).max() < tol_at_128


def test_project_samples_drjit_equals_numpy_einsum() -> None:
    """The drjit path (float32, block_sum) vs a float64 einsum on the same samples. Error budget:
    float32 inputs (2⁻²⁴ each) and a float32 sum of 10⁴ terms, ≲ √N·2⁻²⁴ ≈ 6e-6 of Σ|terms|; measured
    3e-7 of max |L_lm|. Tolerance 1e-5·Σ_k |w_k L_k Y_lm(ω_k)|."""
    rng = np.random.default_rng(9)
    n = 10_000
    d = _random_directions(n, seed=10)
    w = rng.random(n)
    rad = rng.random((n, 3))
    ours = sh.project_samples(d, w, rad, 4)
    y = sh.eval_basis_numpy(d, 4)
    ref = np.einsum("nk,n,nc->kc", y, w, rad)
    scale = np.einsum("nk,n,nc->kc", np.abs(y), w, rad)
    assert (np.abs(ours - ref) <= 1e-5 * scale).all()


# --- the directional worst case (R&H 2001) ----------------------------------------------------------

def _delta_light_errors(omega0: np.ndarray, flux: float, normals: np.ndarray) -> tuple[np.ndarray, ...]:
    # projecting a delta light of flux Φ: L_lm = ∫ Φ δ(ω − ω0) Y_lm(ω) dω = Φ Y_lm(ω0)
    coeffs = sh.project_samples(omega0[None, :], np.array([flux]), np.ones((1, 3)), 2)
    exact = flux * np.maximum(normals @ omega0, 0.0)[:, None]
    return (np.abs(sh.render_irradiance(coeffs, normals) - exact),
            np.abs(sh.render_irradiance_rh2001(coeffs, normals) - exact), coeffs)


def test_delta_light_coefficients() -> None:
    omega0 = np.array([0.3, 0.8, -0.5]) / np.linalg.norm([0.3, 0.8, -0.5])
    _, _, coeffs = _delta_light_errors(omega0, 2.5, latlong.fibonacci_sphere(11))
    expected = 2.5 * sh.eval_basis_numpy(omega0, 2)
    assert np.abs(coeffs - expected[:, None]).max() < 1e-6  # float32 products of O(1) numbers


def test_directional_worst_case_is_the_bound() -> None:
    """For a delta light the SH9 clamped-cosine is K̃(x) = 3/32 + x/2 + 15x²/32 (x = n·ω0), so
    |E′ − E| = Φ|K̃(x) − max(x, 0)|: max 3/32·Φ at the terminator x = 0 and mean
    ½∫₋₁¹|K̃ − max(x,0)|dx·Φ = 0.0306737·Φ over uniform normals — R&H's 9.375 % / 3.07 % bounds,
    attained. The normals: a spherical Fibonacci set plus a ring on the terminator."""
    flux = 2.5
    n = 20001
    omega0 = np.array([0.3, 0.8, -0.5]) / np.linalg.norm([0.3, 0.8, -0.5])
    u = np.cross(omega0, [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(omega0, u)
    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    ring = np.cos(t)[:, None] * u + np.sin(t)[:, None] * v
    normals = np.concatenate([latlong.fibonacci_sphere(n), ring])
    # max: float32 rendering of O(Φ) terms, measured |max/Φ − 3/32| = 7e-8.
    max_tol = 1e-6
    # mean: a quasi-uniform n-point rule on a Lipschitz, piecewise-smooth function; its error shrinks at
    # least like 1/n (measured 1.2e-7 at n = 20001, 6.5e-8 at 100001). Tolerance 1/n = 5e-5.
    mean_tol = 1.0 / n
    err_al, err_rh, _ = _delta_light_errors(omega0, flux, normals)
    for err in (err_al, err_rh):
        assert abs(err.max() / flux - 3 / 32) < max_tol
        assert abs(err[:n].mean(axis=0).max() / flux - _exact_worst_case_mean()) < mean_tol


def _exact_worst_case_mean() -> float:
    """½∫₋₁¹|K̃(x) − max(x, 0)|dx in closed form. |K̃ − max(x,0)| is even in x (K̃(−x) = K̃(x) − x);
    on [0, 1] g = 3/32 − x/2 + 15x²/32 has roots x± = (16 ± √76)/30 and antiderivative
    G = 3x/32 − x²/4 + 5x³/32 with G(0) = G(1) = 0, so the mean is 2G(x₋) − 2G(x₊) = 0.03067373…"""
    def g(x: float) -> float:
        return 3 * x / 32 - x * x / 4 + 5 * x**3 / 32
    lo, hi = (16 - math.sqrt(76)) / 30, (16 + math.sqrt(76)) / 30
    return 2 * g(lo) - 2 * g(hi)


def test_directional_worst_case_mean_function() -> None:
    """metrics.directional_worst_case_mean() (trapezoid, 200001 points) equals the closed form; the
    trapezoid's error at the kinks is O(h²) ≈ 1e-10. R&H round it to 3.07 %."""
    exact = _exact_worst_case_mean()
    assert abs(exact - 0.0306737333) < 1e-10
    assert abs(irradiance_error.directional_worst_case_mean() - exact) < 1e-9
    assert round(exact, 4) == irradiance_error.WORST_CASE_MEAN
    assert irradiance_error.WORST_CASE_MAX == 3 / 32


@pytest.mark.parametrize("width", [1024, 96, 40, 37])  # 32, 32, 8 and 1 phases
@pytest.mark.parametrize("lmax", [0, 2, 4])
def test_polyphase_row_sums_equal_direct_products(width: int, lmax: int) -> None:
    """fourier_row_sums (polyphase: rows read as (W/k, 3k) matrices, then rotated by the shift theorem)
    equals Σ_j L_ij T_q(φ_j) computed directly in float64, to float32 rounding (relative 1e-5 of the
    largest row sum), for widths with 32, 8 and 1 phases."""
    rng = np.random.default_rng(width + lmax)
    rad = rng.uniform(0.0, 2.0, (9, width, 3)).astype(np.float32)
    direct = np.einsum("qw,iwc->iqc", sh.fourier_columns(width, lmax).T, rad.astype(np.float64))
    ours = sh.fourier_row_sums(rad, lmax)
    assert ours.shape == direct.shape
    assert np.abs(ours - direct).max() <= 1e-5 * np.abs(direct).max()
