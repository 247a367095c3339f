"""The shared significance helpers (:mod:`validate.stats`) against closed forms and simulation.

Oracles: Student's t with 1 and 2 dof has a closed-form cdf (Cauchy: ½ + atan(t)/π; ν = 2:
½ + t / (2√(2 + t²))), so t → z is checked without scipy's t distribution; Šidák's level is checked
against its defining identity (m independent two-sided tests reject together with probability α)
and against a simulation; calibration draws many seeded t statistics from normal passes and checks
that their z values are N(0, 1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import norm

from validate import stats
from validate.errors import ValidateError

FLOAT64_TOL = 1e-12  # closed forms evaluated in float64
# t → z vs the closed-form cdfs over |t| ≤ 20: scipy's t tail and the oracle's atan/sqrt differ by a few
# ulps, amplified by dz/dp = 1/φ(z) ≤ 10³ in the far tail (measured max 3e-14); 1e-9 is generous.
QUANTILE_TOL = 1e-9
# Calibration sample: N seeded t statistics with P = 4 passes (3 dof, the heaviest tails in use).
CALIBRATION_N, CALIBRATION_PASSES = 200_000, 4
# Statistical tolerances in standard errors of the estimate: 5σ two-sided is a 6·10⁻⁷ false alarm
# per check with a random seed; the seed is fixed, so the outcome is deterministic.
SIGMAS = 5.0


def cauchy_z(t: np.ndarray) -> np.ndarray:
    """z = Φ⁻¹(F(t)) with the Cauchy (ν = 1) cdf F(t) = ½ + atan(t)/π, upper tail 1 − F = atan2(1, t)/π."""
    return np.sign(t) * norm.isf(np.arctan2(1.0, np.abs(t)) / np.pi)


def t2_z(t: np.ndarray) -> np.ndarray:
    """z for ν = 2: upper tail 1 − F(|t|) = ½ (1 − |t|/√(2 + t²))."""
    a = np.abs(t)
    return np.sign(t) * norm.isf(0.5 * (1.0 - a / np.sqrt(2.0 + a * a)))


T_GRID = np.concatenate([-np.geomspace(20.0, 1e-3, 60), [0.0], np.geomspace(1e-3, 20.0, 60)])


@pytest.mark.parametrize("dof, oracle", [(1, cauchy_z), (2, t2_z)])
def test_t_to_z_equals_closed_form_quantile_map(dof: int, oracle) -> None:
    assert np.max(np.abs(stats.t_to_z(T_GRID, dof) - oracle(T_GRID))) < QUANTILE_TOL


def test_t_to_z_is_odd_monotone_and_tends_to_identity() -> None:
    for dof in (1, 3, 7, 30):
        z = stats.t_to_z(T_GRID, dof)
        assert np.array_equal(stats.t_to_z(-T_GRID, dof), -z)
        assert np.all(np.diff(z) > 0)
        assert np.all(np.abs(z) <= np.abs(T_GRID))  # t has heavier tails: |z| ≤ |t|
    # Large ν: z = t − (t³ + t)/(4ν) + O(ν⁻²) (Cornish–Fisher); at ν = 10⁴ the O(ν⁻²) part is
    # < 0.1 % of the first correction for |t| ≤ 3 (measured 0.05 %).
    nu, t = 10_000, np.array([0.5, 1.0, 2.0, 3.0])
    first = -(t**3 + t) / (4 * nu)
    assert np.max(np.abs((stats.t_to_z(t, nu) - t) / first - 1.0)) < 1e-3
    # far tail stays finite and ordered (upper-tail evaluation, no 1 − F cancellation)
    assert stats.t_to_z(np.array([1e6]), 3)[0] > stats.t_to_z(np.array([1e5]), 3)[0] > 7.9  # tail ∝ t⁻³
    assert stats.t_to_z(np.array([np.inf]), 3)[0] == np.inf


def test_t_to_z_calibration() -> None:
    """z of simulated t statistics (normal passes, P − 1 dof) is N(0, 1): mean, variance, tail rates."""
    rng = np.random.default_rng(20240)
    x = rng.normal(size=(CALIBRATION_N, CALIBRATION_PASSES))
    mean, se = stats.mean_and_stderr(x, axis=1)
    t = mean / se
    z = stats.t_to_z(t, CALIBRATION_PASSES - 1)
    n = CALIBRATION_N
    assert abs(z.mean()) < SIGMAS / math.sqrt(n)
    assert abs(z.var() - 1.0) < SIGMAS * math.sqrt(2.0 / n)  # var of the sample variance of N(0,1): 2/n
    for level in (0.05, 0.01, 0.001):
        rate = float(np.mean(np.abs(z) > norm.isf(level / 2)))
        assert abs(rate - level) < SIGMAS * math.sqrt(level * (1 - level) / n)
    # the raw t is *not* N(0, 1) with 3 dof: its 1 % two-sided rate at 2.576 is ≈ 8 %
    assert np.mean(np.abs(t) > norm.isf(0.005)) > 0.05


def test_sidak_known_values_and_identity() -> None:
    # m = 1 is the plain two-sided test: the usual 1.96
    assert stats.sidak_critical(1, 0.05) == pytest.approx(1.959963984540054, abs=FLOAT64_TOL)
    # Šidák-corrected two-sided 5 % values for m = 2 and 10 (tables: 2.236, 2.800; Bonferroni 2.241, 2.807)
    assert stats.sidak_critical(2, 0.05) == pytest.approx(2.2364766445577917, abs=1e-10)
    assert stats.sidak_critical(10, 0.05) == pytest.approx(2.799625219301094, abs=1e-10)
    for m in (1, 3, 144, 6912):
        for alpha in (0.01, 0.05, 0.3):
            a1 = stats.sidak_alpha(alpha, m)
            assert alpha / m <= a1 <= alpha * (1 + FLOAT64_TOL)  # ≥ Bonferroni's α/m, never above α
            # defining identity: m independent two-sided tests at z* all accept with probability 1 − α
            tail = 2.0 * norm.sf(stats.sidak_critical(m, alpha))
            assert 1.0 - (1.0 - tail) ** m == pytest.approx(alpha, rel=1e-9)
            assert stats.sidak_p_value(a1, m) == pytest.approx(alpha, rel=1e-12)  # the inverse map
    assert stats.sidak_p_value(0.2, 1) == pytest.approx(0.2, abs=FLOAT64_TOL)


def test_sidak_family_wise_rate_simulated() -> None:
    """Families of m = 50 independent N(0, 1) values exceed z* with probability α = 0.05."""
    rng = np.random.default_rng(7)
    families, m, alpha = 40_000, 50, 0.05
    z = rng.normal(size=(families, m))
    rate = float(np.mean(np.abs(z).max(axis=1) > stats.sidak_critical(m, alpha)))
    assert abs(rate - alpha) < SIGMAS * math.sqrt(alpha * (1 - alpha) / families)


def test_two_sided_t_critical_and_bounds() -> None:
    # ν = 1 (Cauchy): t* = tan(π(1 − α)/2) = cot(πα/2), exact
    for alpha in (0.2, 0.05, 1e-3):
        cauchy = 1.0 / math.tan(math.pi * alpha / 2)
        assert stats.two_sided_t_critical(alpha, 1) == pytest.approx(cauchy, rel=FLOAT64_TOL)
    assert stats.two_sided_t_critical(0.05, 10) == pytest.approx(2.228, abs=5e-4)  # textbook table value
    assert stats.mean_z_bound(1600, 4.0) == pytest.approx(0.1, abs=FLOAT64_TOL)
    x = np.array([[1.0, 2.0, 4.0, 9.0]])
    mean, se = stats.mean_and_stderr(x, axis=1)
    assert mean[0] == 4.0 and se[0] == pytest.approx(math.sqrt(((9 + 4 + 0 + 25) / 3) / 4), abs=FLOAT64_TOL)


@pytest.mark.parametrize("call, culprit", [
    (lambda: stats.t_to_z(np.array([1.0]), 0), "dof"),
    (lambda: stats.sidak_alpha(0.0, 3), "alpha"),
    (lambda: stats.sidak_critical(3, 1.0), "alpha"),
    (lambda: stats.sidak_critical(0, 0.01), "tests"),
    (lambda: stats.sidak_p_value(1.5, 3), "p_min"),
    (lambda: stats.mean_z_bound(0, 4.0), "tests"),
    (lambda: stats.two_sided_t_critical(0.05, 0), "dof"),
    (lambda: stats.mean_and_stderr(np.ones((3, 1)), axis=1), "pass"),
    (lambda: stats.cross_fitted_z(np.ones((3, 1)), np.ones((1, 1))), "pass"),
    (lambda: stats.cross_fitted_z(np.ones((4, 1)), np.ones((2, 1))), "pass"),
])
def test_bad_input(call, culprit: str) -> None:
    with pytest.raises(ValidateError, match=culprit):
        call()


def test_cross_fitted_z_is_centred_for_skewed_passes_where_t_is_not() -> None:
    """Passes of 32 log-normal samples (σ = 1.5: a rare bright path) against passes of 256, both unbiased: the mean
    of the plain t's z over 3000 pixels sits far outside 4/√N (E[t] ≈ −γ/(2√P)), the cross-fitted z's is inside it,
    and a 5 % bias in one renderer is caught by the cross-fitted test."""
    rng = np.random.default_rng(1)
    n = 3000

    def passes(spp: int) -> np.ndarray:
        return rng.lognormal(0.0, 1.5, size=(8, spp, n, 1)).mean(axis=1)

    a, b = passes(32), passes(256)
    limit = stats.mean_z_bound(n, 4.0)
    t = (a.mean(0) - b.mean(0)) / np.sqrt(a.var(0, ddof=1) / 8 + b.var(0, ddof=1) / 8)
    assert abs(stats.t_to_z(t, 7).mean()) > 2 * limit
    assert abs(stats.standardized_mean(stats.cross_fitted_z(a, b))[0]) < limit
    assert abs(stats.standardized_mean(stats.cross_fitted_z(1.05 * a, b))[0]) > limit


def test_cross_fitted_z_against_a_known_value() -> None:
    """A one-pass ``b`` is a value known to ± extra_sigma: equal passes give z = 0, a zero spread with a difference ∞
    (and ∞ as the standardized mean), and the halves' spreads set the scale."""
    a = np.array([[1.0], [1.0], [1.0], [1.0]])
    assert stats.cross_fitted_z(a, np.array([[1.0]]))[0] == 0.0
    assert stats.cross_fitted_z(a, np.array([[0.5]]))[0] == np.inf
    assert stats.standardized_mean(np.array([[1.0], [np.inf]]))[0] == np.inf
    a = np.array([[0.0], [2.0], [2.0], [4.0]])  # halves (0, 2) and (2, 4): means 1 and 3, each spread s² = 2
    z = stats.cross_fitted_z(a, np.array([[2.0]]), 0.0)
    assert z[0] == pytest.approx(0.5 * (-1.0 + 1.0), abs=FLOAT64_TOL)
    z = stats.cross_fitted_z(a, np.array([[1.0]]), 0.0)
    assert z[0] == pytest.approx(0.5 * (0.0 / 1.0 + 2.0 / 1.0), abs=FLOAT64_TOL)
