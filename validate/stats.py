"""Significance tests shared by the Monte Carlo comparisons: pass statistics, Student t → z, Šidák.

Every Mitsuba reference here is P independent passes of a Monte Carlo estimator; a prediction q is
judged against the pass mean m with its standard error s. The pieces, in the order they are used:

* ``mean_and_stderr``: m = (1/P) Σ_k x_k, s = sd(x) / √P with the sample standard deviation
  (divisor P − 1), so s has P − 1 degrees of freedom.
* ``t_to_z``: under H₀ (pass values ≈ normal by the CLT) t = (m − q)/s follows Student's t with
  ν = P − 1 dof. It is mapped to the standard-normal quantile with the same tail probability,

      z = sign(t) · Φ⁻¹(1 − F_t(|t|; ν)),

  so z ~ N(0, 1) exactly under H₀ (probability integral transform [3]; the map is monotone and odd).
  Values from tests with different ν then share one null distribution and can be pooled (mean z,
  Σ z²). Both tails are evaluated as upper tails (``isf(sf(·))``), which keeps full relative
  precision far out; |t| = ∞ (a zero standard error with m ≠ q) gives |z| = ∞.
* ``sidak_alpha`` / ``sidak_critical``: to test M values at *family-wise* level α — the probability
  that at least one of M true hypotheses is rejected is at most α — each is tested at
  α₁ = 1 − (1 − α)^{1/M}, and a two-sided normal test rejects when |z| > z* = Φ⁻¹(1 − α₁/2).
  Šidák [1] proves (1 − α₁)^M is a lower bound of the joint acceptance probability for two-sided
  tests of jointly normal statistics with *any* correlation, so correlated channels are covered;
  with independent tests it is exact. α₁ ≥ α/M (Bonferroni), slightly less conservative.
* ``sidak_p_value``: the family-wise p-value of the smallest of M p-values, 1 − (1 − p_min)^M: the
  same correction read the other way (exact for M independent tests).
* ``mean_z_bound``: k/√N, a k-sigma bound on the mean of N independent N(0, 1) values. A systematic
  bias b (in units of σ) moves the mean by b whatever N, so it is caught once b > k/√N; the two-sided
  false-alarm rate is 2(1 − Φ(k)) (6.3·10⁻⁵ for k = 4).
* ``two_sided_t_critical``: t* = F_t⁻¹(1 − α/2; ν), the two-sided level-α bound for one Student-t
  statistic, |t| > t* with probability α under H₀ [2].

The significance level α is a false-alarm rate: the probability that the test fails although the
prediction is correct (the Monte Carlo noise alone exceeds the bound). It is fixed before looking at
the data and passed in by the caller; nothing here has a default level.

References
  [1] Z. Šidák, "Rectangular confidence regions for the means of multivariate normal
      distributions", JASA 62 (1967) 626–633.
  [2] "Student" (W. S. Gosset), "The probable error of a mean", Biometrika 6 (1908) 1–25.
  [3] G. Casella, R. L. Berger, *Statistical Inference*, 2nd ed., Thm. 2.1.10 (probability
      integral transformation).
"""

from __future__ import annotations

import numpy as np

from .errors import ValidateError


def _check_alpha(alpha: float, who: str) -> None:
    if not 0.0 < alpha < 1.0:
        raise ValidateError(f"{who}: alpha={alpha} must be in (0, 1)")


def _check_count(m: int, who: str) -> None:
    if m < 1:
        raise ValidateError(f"{who}: number of tests {m} must be ≥ 1")


def mean_and_stderr(samples: np.ndarray, axis: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(m, s) over ``axis`` of P pass values: m = mean, s = sd(ddof = 1)/√P (P − 1 dof); P ≥ 2."""
    x = np.asarray(samples)
    passes = x.shape[axis]
    if passes < 2:
        raise ValidateError(f"mean_and_stderr: {passes} pass(es) along axis {axis}; need ≥ 2 for an error")
    return x.mean(axis=axis), x.std(axis=axis, ddof=1) / np.sqrt(passes)


def t_to_z(t: np.ndarray, dof: int) -> np.ndarray:
    """z = sign(t) Φ⁻¹(1 − F_t(|t|; ν)): the N(0, 1) quantile with Student t's tail probability (ν = dof)."""
    from scipy.stats import norm
    from scipy.stats import t as student

    if dof < 1:
        raise ValidateError(f"t_to_z: dof={dof} must be ≥ 1")
    t = np.asarray(t, dtype=np.float64)
    return np.sign(t) * norm.isf(student.sf(np.abs(t), dof))


def sidak_alpha(alpha: float, m: int) -> float:
    """α₁ = 1 − (1 − α)^{1/m}: per-test level that keeps the family-wise level of m tests at α [1]."""
    _check_alpha(alpha, "sidak_alpha")
    _check_count(m, "sidak_alpha")
    return 1.0 - (1.0 - alpha) ** (1.0 / m)


def sidak_critical(m: int, alpha: float) -> float:
    """z* = Φ⁻¹(1 − α₁/2), α₁ = 1 − (1 − α)^{1/m}: two-sided |z| bound at family-wise level α, m tests [1]."""
    from scipy.stats import norm

    return float(norm.isf(sidak_alpha(alpha, m) / 2.0))


def sidak_p_value(p_min: float, m: int) -> float:
    """1 − (1 − p_min)^m: family-wise p-value of the smallest of m p-values [1]."""
    _check_count(m, "sidak_p_value")
    if not 0.0 <= p_min <= 1.0:
        raise ValidateError(f"sidak_p_value: p_min={p_min} must be in [0, 1]")
    return 1.0 - (1.0 - p_min) ** m


def mean_z_bound(n: int, sigmas: float) -> float:
    """k/√n: the k-sigma bound on the mean of n independent standard-normal z values (bias check)."""
    _check_count(n, "mean_z_bound")
    return float(sigmas / np.sqrt(n))


def two_sided_t_critical(alpha: float, dof: int) -> float:
    """t* = F_t⁻¹(1 − α/2; ν): |t| > t* with probability α for one Student-t statistic with ν dof [2]."""
    from scipy.stats import t as student

    _check_alpha(alpha, "two_sided_t_critical")
    if dof < 1:
        raise ValidateError(f"two_sided_t_critical: dof={dof} must be ≥ 1")
    return float(student.ppf(1 - alpha / 2, dof))
