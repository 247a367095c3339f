"""Image error metrics for rendered comparisons: relative error maps with Monte Carlo uncertainty, and
NVIDIA FLIP next to them.

For a reference image R (per-pixel Monte Carlo mean, standard error σ) and an approximation A, on the
pixels of a mask (the object), with luminance Y = 0.2126 R + 0.7152 G + 0.0722 B:

* ``relative``  e(p) = |Y(A) − Y(R)| / Y(R), reported where Y(R) ≥ :data:`RELATIVE_FLOOR` · max Y(R);
  per-pixel uncertainty u(p) = σ_Y/Y(R), σ_Y the standard error of Y(R) (given, or Y(σ) computed from
  the per-channel errors — an upper bound, the channels share their paths). Since
  | |A − R| − |A − R_true| | ≤ |R − R_true|, whose mean is ≈ σ√(2/π) ≤ σ, the *mean* of e moves by at
  most mean(u) (1σ, conservative) when R is replaced by the truth: ``mean ± mean_uncertainty``. The
  mean also *includes* the noise (≈ 0.8 mean(u) where the approximation is exact), so it is meaningful
  only where mean(u) ≪ the errors of interest. The max over pixels is dominated by noise unless u ≪ e;
  it is reported with u at that pixel, for orientation only.
* ``signed``    (Y(A) − Y(R)) / Y(R) per pixel (the map). The *bias* is the luminance-weighted mean
  Σ (Y(A) − Y(R)) / Σ Y(R) — not the plain mean of the ratios, which Monte Carlo noise in the
  denominator biases upwards by ≈ mean(u²) (Jensen) — with standard error √(Σ σ_Y²) / Σ Y(R) (pixels
  are independent).
* ``flip``      NVIDIA FLIP [1] in HDR mode, :func:`validate.metrics.flip.flip_hdr` with the mask and
  ``negatives="clamp"`` (the package's defaults, returned as ``parameters``). Pixels outside the mask are
  black in both images, so they contribute no error; the mean is taken over the mask. FLIP is perceptual (0 = identical,
  1 = maximal) and has no Monte Carlo uncertainty attached: it is shown next to the relative error,
  not used in claims.

References
  [1] P. Andersson, J. Nilsson, T. Akenine-Möller, M. Oskarsson, K. Åström, M. D. Fairchild,
      "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM CGIT 3(2), 2020; and
      "Visualizing Errors in Rendered High Dynamic Range Images", Eurographics 2021 (HDR-FLIP).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ..errors import ValidateError
from ..scenes.latlong import luminance

RELATIVE_FLOOR = 1e-3  # relative error is reported where Y(R) ≥ 1e-3 · max Y(R)


@dataclass
class ImageErrorStats:
    """Relative-error statistics over the compared pixels (fractions, not percent)."""

    mean: float
    mean_uncertainty: float
    max: float
    max_uncertainty: float
    p95: float
    bias: float
    bias_uncertainty: float
    pixels: int

    def to_json(self) -> dict:
        return asdict(self)


@dataclass
class RelativeError:
    """Per-pixel maps (H, W) — NaN where not compared — and their statistics; the luminances behind them."""

    error: np.ndarray
    signed: np.ndarray
    uncertainty: np.ndarray
    stats: ImageErrorStats
    y_ref: np.ndarray
    y_app: np.ndarray
    y_se: np.ndarray


def _check(reference: np.ndarray, approx: np.ndarray, mask: np.ndarray) -> None:
    if reference.shape != approx.shape or reference.ndim != 3 or reference.shape[-1] != 3:
        raise ValidateError(f"image error: reference {reference.shape} and approximation {approx.shape} must "
                            "both be (H, W, 3)")
    if mask.shape != reference.shape[:2]:
        raise ValidateError(f"image error: mask {mask.shape} does not match image {reference.shape[:2]}")


def relative_error(reference: np.ndarray, stderr: np.ndarray, approx: np.ndarray, mask: np.ndarray,
                   floor: float = RELATIVE_FLOOR) -> RelativeError:
    """Relative luminance error map of ``approx`` against a Monte Carlo ``reference`` (module doc);
    ``stderr`` is the standard error of Y(R) (H, W) or per channel (H, W, 3)."""
    _check(reference, approx, mask)
    y_ref, y_app = luminance(reference), luminance(approx)
    y_se = np.abs(stderr) if np.ndim(stderr) == 2 else luminance(np.abs(stderr))
    m = mask & np.isfinite(y_ref) & np.isfinite(y_app)
    if not m.any():
        raise ValidateError("image error: no pixel to compare (empty mask)")
    peak = float(np.max(y_ref[m]))
    m &= y_ref >= floor * peak
    if not m.any():
        raise ValidateError("image error: no pixel above the relative-error floor")
    err = np.full(mask.shape, np.nan)
    sig = np.full(mask.shape, np.nan)
    unc = np.full(mask.shape, np.nan)
    sig[m] = (y_app[m] - y_ref[m]) / y_ref[m]
    err[m] = np.abs(sig[m])
    unc[m] = y_se[m] / y_ref[m]
    return RelativeError(err, sig, unc, _stats(err, unc, y_ref, y_app, y_se, m), y_ref, y_app, y_se)


def _stats(err: np.ndarray, unc: np.ndarray, y_ref: np.ndarray, y_app: np.ndarray, y_se: np.ndarray,
           m: np.ndarray) -> ImageErrorStats:
    if not m.any():
        nan = float("nan")
        return ImageErrorStats(nan, nan, nan, nan, nan, nan, nan, 0)
    e, u = err[m], unc[m]
    total = float(np.sum(y_ref[m]))
    return ImageErrorStats(float(e.mean()), float(u.mean()), float(e.max()), float(u[np.argmax(e)]),
                           float(np.percentile(e, 95)), float(np.sum(y_app[m] - y_ref[m]) / total),
                           float(np.sqrt(np.sum(y_se[m] ** 2)) / total), int(e.size))


def summarize(rel: RelativeError, select: np.ndarray) -> ImageErrorStats:
    """Statistics of an existing error map over a sub-region ``select`` (H, W) (e.g. a view-angle band)."""
    return _stats(rel.error, rel.uncertainty, rel.y_ref, rel.y_app, rel.y_se, select & np.isfinite(rel.error))

