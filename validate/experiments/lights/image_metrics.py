"""Error measures of the ``lights`` experiment: image errors of a shaded G-buffer against a render,
and the Student-t/Šidák agreement test of a prediction with a Monte Carlo render.

Image errors, over the N valid pixels, reference radiance r ± σ (per pixel, from P passes),
approximation a, luminance Y (Rec. 709 weights), L_norm = mean Y(r) over pixels with Y(r) > 0:

* ``mean``  = mean_p |Y(a) − Y(r)| / L_norm,  uncertainty mean_p Y(σ) / L_norm
  (| |a − r_true| − |a − r| | ≤ |r − r_true|, whose scale is σ);
* ``max``   = max_p |Y(a) − Y(r)| / L_norm,   uncertainty max_p Y(σ) / L_norm, over the pixels where
  both images agree on whether the pixel is lit at all (Y > 0 in both or in neither);
* ``mismatch`` = the fraction of pixels where they do not: one image exactly black, the other not. For
  a delta light that is a shadow ray answered differently (Mitsuba offsets its shadow-ray origins by
  its own error bound, the shadow tester here by 10⁻⁴ m along the normal), on the shadow terminator;
  reported beside ``max`` (the analogue of the shadows experiment's one-texel edge band);
* ``bias``  = Σ_p (Y(a) − Y(r)) / Σ_p Y(r),   uncertainty √(Σ_p Y(σ)²) / Σ_p Y(r) (standard error).

Agreement test (:func:`agreement`), luminance, over the N pixels with s > 0:

* bias: the image total. Pass k gives T_k = Σ_p Y(x_pk) (passes are independent, so the T_k are, whatever
  the correlation between pixels within a pass); t = (mean_k T_k − Σ_p Y(q_p)) / √(s_T²/P + s_Q²), s_Q
  the prediction's own standard error of its total (0 for a closed form), Student t with P − 1 dof,
  converted to a normal z ("pooled z"); consistent when |z| < 4 (two-sided false-alarm rate 6·10⁻⁵).
  A sum over thousands of pixels is close to normal whatever the skew of one pixel's samples. (The
  mean of per-pixel z is not used: with skewed pass values — area lights — per-pixel t is biased,
  measured −0.03 per pixel at 16 passes, which a 4/√N bound on the mean flags.)
* outliers: per pixel t = (m − q) / √(s_m² + s_q²) with P − 1 dof, converted to a standard-normal z
  (:func:`validate.stats.t_to_z`); consistent when max |z| is below the Šidák-corrected
  critical value at family-wise α = 0.01 [Šidák 1967].
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ...scenes.latlong import luminance
from ...stats import mean_and_stderr, sidak_critical, t_to_z
from ..techniques import Measured

ALPHA = 0.01  # family-wise level of the per-pixel agreement tests
BIAS_SIGMAS = 4.0  # |pooled z| < 4: false-alarm rate 6·10⁻⁵
POWER_SCALE = 1.01  # the standard perturbation of a technique's metrics: its irradiance × 1.01
POWER_TEXT = "the technique's irradiance × 1.01 (a 1 % intensity error)"


@dataclass(frozen=True)
class ImageErrors:
    mean: float
    mean_uncertainty: float
    max: float
    max_uncertainty: float
    mismatch: float
    bias: float
    bias_uncertainty: float
    pixels: int
    normaliser: float

    def to_json(self) -> dict[str, Any]:
        return {k: (float(v) if np.isfinite(v) else None) for k, v in asdict(self).items()}


def image_errors(reference: np.ndarray, uncertainty: np.ndarray, approx: np.ndarray) -> ImageErrors:
    """The three image errors of the module docstring over N pixels ((N, 3) arrays)."""
    yr, ya, ys = luminance(reference), luminance(approx), luminance(uncertainty)
    lit = yr > 0
    norm = float(yr[lit].mean()) if lit.any() else 1.0
    diff = np.abs(ya - yr) / norm
    agree = (ya > 0) == lit
    total = float(yr.sum()) or 1.0
    dmax = float(diff[agree].max()) if agree.any() else float("nan")
    return ImageErrors(float(diff.mean()), float(ys.mean() / norm), dmax, float(ys.max() / norm),
                       float((~agree).mean()), float((ya - yr).sum() / total), float(np.sqrt((ys**2).sum()) / total),
                       int(yr.size), norm)


def measured(ref: np.ndarray, unc: np.ndarray, approx: np.ndarray) -> dict[str, Measured]:
    """mean/max/bias as :class:`Measured`, each with its value under the standard perturbation."""
    e, p = image_errors(ref, unc, approx), image_errors(ref, unc, approx * POWER_SCALE)
    out = {k: Measured(getattr(e, k), getattr(e, f"{k}_uncertainty"), getattr(p, k), POWER_TEXT, unit="%",
                       stat="" if k == "bias" else k, better="zero" if k == "bias" else "lower")
           for k in ("mean", "max", "bias")}
    out["mismatch"] = Measured(e.mismatch, 0.0, unit="%")
    return out


def metric_json(m: Measured) -> dict[str, Any]:
    return m.to_json()


@dataclass(frozen=True)
class Agreement:
    pooled_z: float
    bias_bound: float
    max_abs_z: float
    critical_z: float
    pixels: int
    relative_bias: float  # Σ (m − q) / Σ q
    z: np.ndarray  # (N,) per tested pixel (NaN where untested)

    @property
    def consistent(self) -> bool:
        return abs(self.pooled_z) < self.bias_bound and self.max_abs_z < self.critical_z

    def to_json(self) -> dict[str, Any]:
        return {"pooled_z": self.pooled_z, "bias_bound": self.bias_bound, "max_abs_z": self.max_abs_z,
                "critical_z": self.critical_z, "pixels": self.pixels, "relative_bias": self.relative_bias,
                "consistent": self.consistent}


def agreement(pass_values: np.ndarray, predicted: np.ndarray, pred_stderr: np.ndarray | float = 0.0,
              pred_total_se: float = 0.0) -> Agreement:
    """Luminance test of ``predicted`` (N, 3) against P independent render passes (P, N, 3) (module
    docstring); ``pred_stderr`` (N, 3) and ``pred_total_se`` are the prediction's own standard errors."""
    x = luminance(np.asarray(pass_values, dtype=np.float64))  # (P, N)
    passes = x.shape[0]
    m, s = mean_and_stderr(x, axis=0)
    q = luminance(np.asarray(predicted, dtype=np.float64))
    sq = luminance(np.asarray(pred_stderr, dtype=np.float64)) if np.ndim(pred_stderr) else np.full_like(m, 0.0)
    sigma = np.sqrt(s**2 + sq**2)
    ok = np.isfinite(q)
    tested = ok & (sigma > 0)
    z = np.full(m.shape, np.nan)
    z[tested] = t_to_z((m[tested] - q[tested]) / sigma[tested], passes - 1)
    totals = x[:, ok].sum(axis=1)
    t_mean, t_se = mean_and_stderr(totals, axis=0)
    se = float(np.sqrt(t_se**2 + pred_total_se**2))
    diff = float(t_mean - q[ok].sum())
    pooled = float(t_to_z(np.array([diff / se if se > 0 else np.sign(diff) * np.inf]), passes - 1)[0])
    n = int(tested.sum())
    return Agreement(pooled, BIAS_SIGMAS, float(np.abs(z[tested]).max()) if n else 0.0,
                     sidak_critical(max(n, 1), ALPHA), n, diff / float(q[ok].sum()), z)


def total_stderr(pass_values: np.ndarray) -> float:
    """Standard error of the luminance image total from P passes (P, N, 3)."""
    totals = luminance(np.asarray(pass_values, dtype=np.float64)).sum(axis=1)
    return float(mean_and_stderr(totals, axis=0)[1])
