"""Per-pixel judgement of an engine image against a Monte Carlo reference: z, Šidák, relative error.

For pixel p and channel c, with the reference mean m ± s (P − 1 dof, :mod:`validate.reference.render_reference`)
and the engine value e,

    σ = √(s² + (b/z*)²),   t = (e − m)/σ,   z = sign(t) Φ⁻¹(1 − F_t(|t|; ν))   (Student → normal),

ν = (P − 1)·(σ²/s²)² the Welch–Satterthwaite degrees of freedom [3] (the budget is exact, ∞ dof),

where b ≥ 0 is the engine's declared precision budget (half floats, SwiftShader trig, tessellation:
written next to each use) — a difference of b alone sits exactly on the critical value — and
z* = Φ⁻¹(1 − α₁/2), α₁ = 1 − (1 − α)^{1/M} the Šidák-corrected level over the M = 3N tested values [1].
A pixel is *accepted* when all three |z| ≤ z*. Mitsuba's own render tests accept an image when at least
99.75 % of its pixels pass at α = 0.01 [2].

Masks: the silhouette is not lighting (the engine rasterises a tessellated, unfiltered outline), so
only pixels whose centre ray hits the sphere, that lie ``edge_px`` pixels or more inside the outline
and that the engine covers fully (alpha = 1) are judged (:func:`interior_mask`). Relative errors divide
by m only where m ≥ ``floor``·max(m) (the masked denominator), so a dark terminator does not dominate.

Outputs carry their parameters (α, z*, budget, masks' sizes) and uncertainties: the mean relative error
± its standard error from the reference noise (√Σ(s/m)²/N, pixels independent), the max ± the
reference's relative standard error at the argmax pixel.

References
----------
[1] Z. Šidák, "Rectangular confidence regions for the means of multivariate normal distributions",
    JASA 62 (1967) 626–633.
[2] Mitsuba 3, ``src/python/python/test/test_renders.py`` (z-test per pixel, Šidák, ≥ 99.75 % pass).
[3] B. L. Welch, "The generalization of 'Student's' problem when several different population variances
    are involved", Biometrika 34 (1947) 28–35 (Welch–Satterthwaite degrees of freedom).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ValidateError
from ..stats import Measured, sidak_critical

ALPHA = 0.01
MIN_ACCEPTED = 0.9975  # Mitsuba's rule [2]
EDGE_PX = 2
REL_FLOOR = 0.05


@dataclass
class PixelJudgement:
    """Per-pixel z and relative error over the judged pixels, with the parameters used."""

    n_pixels: int
    fraction_accepted: float
    critical_z: float
    max_abs_z: float
    mean_rel: float  # mean |e − m|/m over the relative mask
    mean_rel_unc: float
    max_rel: float
    max_rel_unc: float
    mean_signed_rel: float  # mean (e − m)/m: the energy bias
    alpha: float
    budget: str
    z_image: np.ndarray  # (R, R) max |z| over channels, NaN outside the mask
    rel_image: np.ndarray  # (R, R) mean over channels of (e − m)/m, NaN outside the relative mask

    def measured(self) -> dict[str, Measured]:
        """The judgement's numbers as measured values: the fraction accepted (higher is better), max |z|, the
        mean and max relative error ± their uncertainty, the signed mean (its magnitude counts)."""
        return {"fraction_accepted": Measured(self.fraction_accepted, unit="%", better="higher"),
                "max_abs_z": Measured(self.max_abs_z, stat="max"),
                "mean_rel": Measured(self.mean_rel, self.mean_rel_unc, unit="%", stat="mean"),
                "max_rel": Measured(self.max_rel, self.max_rel_unc, unit="%", stat="max"),
                "mean_signed_rel": Measured(self.mean_signed_rel, unit="%", stat="mean", better="zero")}

    def to_json(self) -> dict[str, Any]:
        """The parameters (pixels judged, z*, α, budget) and :meth:`measured` as :class:`Measured` JSON."""
        return {"n_pixels": int(self.n_pixels), "critical_z": float(self.critical_z), "alpha": float(self.alpha),
                "budget": self.budget, **{k: v.to_json() for k, v in self.measured().items()}}


def interior_mask(hit: np.ndarray, coverage: np.ndarray, edge_px: int = EDGE_PX) -> np.ndarray:
    """Pixels ``edge_px`` or more inside the reference outline and fully covered by the engine."""
    from scipy import ndimage

    inner = ndimage.binary_erosion(hit, iterations=edge_px) if edge_px > 0 else hit
    return inner & (coverage >= 1.0 - 1e-6)


def welch_z(t: np.ndarray, s: np.ndarray, sigma: np.ndarray, dof: int) -> np.ndarray:
    """t → normal quantile with the Welch–Satterthwaite dof ν = dof·(σ²/s²)² (the budget term has ∞ dof) [3]."""
    from scipy.stats import norm
    from scipy.stats import t as student

    with np.errstate(divide="ignore", invalid="ignore"):
        nu = np.where(s > 0, dof * (sigma**2 / np.where(s > 0, s, 1.0) ** 2) ** 2, 1e9)
    nu = np.clip(nu, dof, 1e9)
    return np.sign(t) * norm.isf(student.sf(np.abs(t), nu))


def judge(engine: np.ndarray, mean: np.ndarray, stderr: np.ndarray, dof: int, mask: np.ndarray,
          budget: np.ndarray | float, budget_text: str, alpha: float = ALPHA) -> PixelJudgement:
    """Judge ``engine`` (R, R, 3) against ``mean`` ± ``stderr`` on ``mask`` (module docstring).

    ``budget``: b per pixel and channel (broadcast to (R, R, 3)), in radiance units.
    """
    n = int(mask.sum())
    if n == 0:
        raise ValidateError("pixel judgement: no pixel left inside the masks")
    e, m, s = engine[mask].astype(np.float64), mean[mask], stderr[mask]
    if not (np.all(np.isfinite(e)) and np.all(np.isfinite(m))):
        raise ValidateError("pixel judgement: NaN/Inf in the engine image or the reference on judged pixels")
    zc = sidak_critical(3 * n, alpha)
    b = np.broadcast_to(np.asarray(budget, np.float64), mean.shape)[mask]
    sigma = np.sqrt(s**2 + (b / zc) ** 2)
    diff = e - m
    t = np.divide(diff, sigma, out=np.where(diff == 0, 0.0, np.copysign(np.inf, diff)), where=sigma > 0)
    z = welch_z(t, s, sigma, dof)
    accepted = np.all(np.abs(z) <= zc, axis=-1)
    rel_ok = m.mean(axis=-1) >= REL_FLOOR * m.max()
    rel = diff[rel_ok] / m[rel_ok]
    urel = s[rel_ok] / m[rel_ok]
    k = int(np.argmax(np.abs(rel).max(axis=-1)))
    z_img = np.full(mask.shape, np.nan)
    z_img[mask] = np.abs(z).max(axis=-1)
    rel_img = np.full(mask.shape, np.nan)
    idx = np.argwhere(mask)[rel_ok]
    rel_img[idx[:, 0], idx[:, 1]] = rel.mean(axis=-1)
    return PixelJudgement(
        n_pixels=n, fraction_accepted=float(accepted.mean()), critical_z=float(zc), max_abs_z=float(np.abs(z).max()),
        mean_rel=float(np.abs(rel).mean()), mean_rel_unc=float(np.sqrt((urel**2).sum()) / urel.size),
        max_rel=float(np.abs(rel[k]).max()), max_rel_unc=float(urel[k].max()),
        mean_signed_rel=float(rel.mean()), alpha=alpha, budget=budget_text, z_image=z_img, rel_image=rel_img)
