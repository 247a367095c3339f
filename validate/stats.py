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
* ``cross_fitted_z`` / ``standardized_mean``: the bias test's z, numerator and standard error from disjoint
  halves of the passes so that its mean is 0 under H₀ even for skewed passes (where t's is not), and its mean
  over N pixels in units of its own spread, tested against k/√N.
* ``two_sided_t_critical``: t* = F_t⁻¹(1 − α/2; ν), the two-sided level-α bound for one Student-t
  statistic, |t| > t* with probability α under H₀ [2].
* :class:`Measured`: the one schema of a measured number in ``results.json`` (below).

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

import math
from collections.abc import Iterator, Mapping
from dataclasses import KW_ONLY, dataclass, field
from typing import Any

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


MIN_CROSS_FIT_PASSES = 4  # two halves of ≥ 2 passes: each half's spread needs 2


def _halves(x: np.ndarray, who: str) -> tuple[np.ndarray, np.ndarray]:
    if x.shape[0] < MIN_CROSS_FIT_PASSES:
        raise ValidateError(f"{who}: {x.shape[0]} pass(es); need ≥ {MIN_CROSS_FIT_PASSES} to split into halves")
    return x[0::2], x[1::2]


def cross_fitted_z(a: np.ndarray, b: np.ndarray, extra_sigma: np.ndarray | float = 0.0) -> np.ndarray:
    """Per-value z of mean(a) − mean(b) whose expectation is exactly 0 under H₀, however skewed the passes.

    ``a``: (P_a, …) independent passes of one estimator; ``b``: (P_b, …) independent passes of the other, or
    (1, …) a value known to ± ``extra_sigma`` (a quadrature). Passes are split by parity into halves h = 0, 1:

        z_h = (ā_h − b̄_h) / √(s²(a_{1−h}) / |a_h| + s²(b_{1−h}) / |b_h| + e²),     z = (z₀ + z₁) / 2,

    s² the sample variance (ddof 1) of the *other* half (0 for a one-pass ``b``). Numerator and denominator come
    from disjoint passes, so they are independent and E[z_h] = E[ā_h − b̄_h] · E[1/den] = 0 when both estimators
    are unbiased. The plain t = (m − q)/s is not centred when the passes are skewed: its mean and its standard
    error are then correlated (a right-skewed pass set that misses a rare bright path has both a low mean and a
    small spread), and the first Edgeworth term of Student's t gives E[t] ≈ −γ/(2√P) for pass skewness γ (P. Hall,
    *The Bootstrap and Edgeworth Expansion*, Springer 1992, §2.6). Measured here (docs/experiments/blender.md):
    Mitsuba at 8 × 32 spp against Mitsuba at 8 × 256 spp, a glossy sphere under Grace Cathedral, gives a mean t of
    −0.13, 1.9 × the 4/√N bound, where this z gives 0.02.
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    a_halves = _halves(a, "cross_fitted_z")
    b_halves = _halves(b, "cross_fitted_z") if b.shape[0] > 1 else (b, b)
    e2 = np.square(extra_sigma)
    z = np.zeros(np.broadcast_shapes(a.shape[1:], b.shape[1:]))
    for h in (0, 1):
        a_in, a_out, b_in, b_out = a_halves[h], a_halves[1 - h], b_halves[h], b_halves[1 - h]
        var_b = b_out.var(axis=0, ddof=1) / len(b_in) if b.shape[0] > 1 else 0.0
        den = np.sqrt(a_out.var(axis=0, ddof=1) / len(a_in) + var_b + e2)
        diff = a_in.mean(axis=0) - b_in.mean(axis=0)
        z += 0.5 * np.divide(diff, den, out=np.where(diff == 0, 0.0, np.copysign(np.inf, diff)), where=den > 0)
    return z


def standardized_mean(z: np.ndarray) -> np.ndarray:
    """mean / sd (ddof 1) of the N values along axis 0, per remaining index (channel).

    For N independent values of mean 0 and finite variance, √N × this is ≈ N(0, 1) (central limit theorem; the sd
    estimated from N ≈ 10³ values), so |·| ≤ k/√N (:func:`mean_z_bound`) is a k-sigma test of a zero mean that needs
    no unit variance (the z of :func:`cross_fitted_z` has a variance above 1: its standard errors come from half the
    passes). A non-finite z (a zero standard error with a difference) gives ∞.
    """
    z = np.asarray(z, dtype=np.float64)
    _check_count(z.shape[0] - 1, "standardized_mean")
    finite = np.all(np.isfinite(z), axis=0)
    zf = np.where(finite, z, 0.0)
    sd = zf.std(axis=0, ddof=1)
    mean = zf.mean(axis=0)
    out = np.divide(mean, sd, out=np.where(mean == 0, 0.0, np.inf), where=sd > 0)
    return np.where(finite, out, np.inf)


def two_sided_t_critical(alpha: float, dof: int) -> float:
    """t* = F_t⁻¹(1 − α/2; ν): |t| > t* with probability α for one Student-t statistic with ν dof [2]."""
    from scipy.stats import t as student

    _check_alpha(alpha, "two_sided_t_critical")
    if dof < 1:
        raise ValidateError(f"two_sided_t_critical: dof={dof} must be ≥ 1")
    return float(student.ppf(1 - alpha / 2, dof))


# ---------------------------------------------------------------------------------------------
# A measured value: the one JSON shape of every technique metric and judgement in results.json
# ---------------------------------------------------------------------------------------------

BETTER = ("lower", "higher", "zero")  # which way a measured value improves (Measured.better)


@dataclass(frozen=True)
class Measured:
    """A measured number: value ± uncertainty in a unit, what it summarises and which way is better.

    JSON (:meth:`to_json`), one shape for every technique metric and judgement in ``results.json``::

        {"value": 0.0123, "uncertainty": 0.0004, "unit": "%"}            # always these three
        {..., "stat": "max", "better": "zero", "params": {"n_pixels": 4096},
         "perturbed": 0.0185, "perturbation": "error × 1.5"}          # each only when set

    * ``value``: the number; one that could not be measured (NaN, ±∞) is written ``null`` (strict JSON).
    * ``uncertainty``: its 1σ; **none counts as 0** — the suite is deterministic (fixed seeds, cached
      references), so a value without one is exact as far as a re-run can tell (written ``0``).
    * ``unit``: ``"%"`` for a fraction shown as per cent (the claims' convention: the value stays a
      fraction), ``""`` for a dimensionless number, otherwise the unit's symbol (``"ms"``).
    * ``stat``: what the value summarises over its inputs (``"mean"``, ``"max"``, ``"rms"``, ``"p95"``);
      ``""``: a single number.
    * ``better``: ``"lower"`` (an error; the default, not written), ``"higher"`` (a score, a fraction
      accepted) or ``"zero"`` (a signed error: its magnitude counts) — how ``compare`` tells worse.
    * ``params``: the parameters that produced it (JSON-able), when the key does not say them.
    * ``perturbed`` / ``perturbation``: the same metric under the experiment's standard perturbation
      (the power check of a claim made on it); the first two fields are positional, the rest keywords.
    """

    value: float
    uncertainty: float = 0.0
    perturbed: float | None = None
    perturbation: str = ""
    _: KW_ONLY
    unit: str = ""
    stat: str = ""
    better: str = "lower"
    params: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.better not in BETTER:
            raise ValidateError(f"Measured: better={self.better!r} is not one of {', '.join(BETTER)}")

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"value": _finite(self.value),
                               "uncertainty": 0.0 if self.uncertainty is None else _finite(self.uncertainty),
                               "unit": self.unit}
        if self.stat:
            out["stat"] = self.stat
        if self.better != "lower":
            out["better"] = self.better
        if self.params:
            out["params"] = dict(self.params)
        if self.perturbed is not None:
            out["perturbed"], out["perturbation"] = _finite(self.perturbed), self.perturbation
        return out

    @classmethod
    def from_json(cls, d: Mapping[str, Any]) -> Measured:
        """The value of :meth:`to_json` (a null value → NaN; an absent or null uncertainty → 0)."""
        if not is_measured(d):
            raise ValidateError(f"not a measured value (needs 'value' and 'unit'): {dict(d)!r:.120}")
        return cls(_number(d["value"]), _number(d.get("uncertainty"), 0.0), _number(d.get("perturbed"), None),
                   str(d.get("perturbation") or ""), unit=str(d.get("unit") or ""), stat=str(d.get("stat") or ""),
                   better=str(d.get("better") or "lower"), params=dict(d.get("params") or {}))


def is_measured(d: Any) -> bool:
    """Whether ``d`` is a :meth:`Measured.to_json` dict: a mapping with ``value`` and ``unit``."""
    return isinstance(d, Mapping) and "value" in d and "unit" in d


def measured_json(tree: Any) -> Any:
    """``tree`` with every :class:`Measured` replaced by its JSON (mappings and lists walked, the rest kept)."""
    if isinstance(tree, Measured):
        return tree.to_json()
    if isinstance(tree, Mapping):
        return {k: measured_json(v) for k, v in tree.items()}
    if isinstance(tree, (list, tuple)):
        return [measured_json(v) for v in tree]
    return tree


def measured_leaves(tree: Any, prefix: str = "") -> Iterator[tuple[str, Mapping[str, Any]]]:
    """(path, JSON) of every measured value under ``tree``, paths joined with "/" (``env/flux_rgb/max``)."""
    if is_measured(tree):
        yield prefix, tree
    elif isinstance(tree, Mapping):
        for k, v in tree.items():
            yield from measured_leaves(v, f"{prefix}/{k}" if prefix else str(k))


def _finite(v: Any) -> float | None:
    """``v`` as a float, None when not finite (a JSON null)."""
    return float(v) if math.isfinite(float(v)) else None


def _number(v: Any, default: float | None = math.nan) -> Any:
    return default if v is None else float(v)
