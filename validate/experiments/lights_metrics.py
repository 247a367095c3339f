"""Error measures of the ``lights`` experiment: image errors of a shaded G-buffer against a render,
and the Student-t/Šidák agreement test of a prediction with a Monte Carlo render.

Image errors, over the N valid pixels, reference radiance r ± σ (per pixel, from P passes),
approximation a, luminance Y (Rec. 709 weights), L_norm = mean Y(r) over pixels with Y(r) > 0:

* ``mean``  = mean_p |Y(a) − Y(r)| / L_norm,  uncertainty mean_p Y(σ) / L_norm
  (| |a − r_true| − |a − r| | ≤ |r − r_true|, whose scale is σ);
* ``max``   = max_p |Y(a) − Y(r)| / L_norm,   uncertainty max_p Y(σ) / L_norm;
* ``bias``  = Σ_p (Y(a) − Y(r)) / Σ_p Y(r),   uncertainty √(Σ_p Y(σ)²) / Σ_p Y(r) (standard error).

Agreement test (:func:`agreement`): per pixel t = (m − q) / √(s_m² + s_q²) with P − 1 dof, converted
to a standard-normal z (:func:`validate.metrics.stats.t_to_z`); the prediction is consistent when
|mean z| ≤ 4/√N (a 4σ bias bound) and max |z| is below the Šidák-corrected critical value at
family-wise α = 0.01 [Šidák 1967]. Pixels with s = 0 (no sample reached a light) are left out.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..metrics.stats import mean_z_bound, sidak_critical, t_to_z
from ..scenes.latlong import luminance
from .techniques import Measured

ALPHA = 0.01  # family-wise level of the per-pixel agreement tests
BIAS_SIGMAS = 4.0  # |mean z| ≤ 4/√N: false-alarm rate 6·10⁻⁵
POWER_SCALE = 1.01  # the standard perturbation of a technique's metrics: its irradiance × 1.01
POWER_TEXT = "the technique's irradiance × 1.01 (a 1 % intensity error)"


@dataclass(frozen=True)
class ImageErrors:
    mean: float
    mean_uncertainty: float
    max: float
    max_uncertainty: float
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
    total = float(yr.sum()) or 1.0
    return ImageErrors(float(diff.mean()), float(ys.mean() / norm), float(diff.max()), float(ys.max() / norm),
                       float((ya - yr).sum() / total), float(np.sqrt((ys**2).sum()) / total), int(yr.size), norm)


def measured(ref: np.ndarray, unc: np.ndarray, approx: np.ndarray) -> dict[str, Measured]:
    """mean/max/bias as :class:`Measured`, each with its value under the standard perturbation."""
    e, p = image_errors(ref, unc, approx), image_errors(ref, unc, approx * POWER_SCALE)
    return {k: Measured(getattr(e, k), getattr(e, f"{k}_uncertainty"), getattr(p, k), POWER_TEXT)
            for k in ("mean", "max", "bias")}


def metric_json(m: Measured) -> dict[str, Any]:
    return {"value": m.value, "uncertainty": m.uncertainty, "perturbed": m.perturbed, "perturbation": m.perturbation}


@dataclass(frozen=True)
class Agreement:
    mean_z: float
    bias_bound: float
    max_abs_z: float
    critical_z: float
    pixels: int
    z: np.ndarray  # (N,) per tested pixel (NaN where untested)

    @property
    def consistent(self) -> bool:
        return abs(self.mean_z) <= self.bias_bound and self.max_abs_z < self.critical_z

    def to_json(self) -> dict[str, Any]:
        return {"mean_z": self.mean_z, "bias_bound": self.bias_bound, "max_abs_z": self.max_abs_z,
                "critical_z": self.critical_z, "pixels": self.pixels, "consistent": self.consistent}


def agreement(mean: np.ndarray, stderr: np.ndarray, predicted: np.ndarray, pred_stderr: np.ndarray | float,
              passes: int) -> Agreement:
    """Luminance t → z test of ``predicted`` against the render ``mean`` ± ``stderr`` (module docstring)."""
    m, s, q = luminance(mean), luminance(stderr), luminance(predicted)
    sq = luminance(pred_stderr) if np.ndim(pred_stderr) else np.full_like(m, float(pred_stderr))
    sigma = np.sqrt(s**2 + sq**2)
    ok = (sigma > 0) & np.isfinite(q)
    z = np.full(m.shape, np.nan)
    z[ok] = t_to_z((m[ok] - q[ok]) / sigma[ok], passes - 1)
    n = int(ok.sum())
    return Agreement(float(z[ok].mean()), mean_z_bound(max(n, 1), BIAS_SIGMAS), float(np.abs(z[ok]).max()),
                     sidak_critical(max(n, 1), ALPHA), n, z)
