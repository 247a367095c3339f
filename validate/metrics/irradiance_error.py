"""Irradiance error metrics (definitions repeated in README § Metrics).

For a reference E(n) and an approximation E′(n) at N quasi-uniform normals, with the total incident
flux Φ = ∫ L dω (per channel; Φ_Y = ∫ Y(L) dω on luminance, Y = 0.2126 R + 0.7152 G + 0.0722 B):

* ``flux_luminance``  e(n) = |Y(E′) − Y(E)| / Φ_Y.  The normalisation under which R&H's claims
  hold: SH9 error ≤ 3/32 = 9.375 % Φ at every normal and ≤ 3.07 % Φ on average, with equality for
  a directional light ([1]; JOSA 18(10) 2001). This is the metric that reproduces "< 1 % / < 5 %".
* ``flux_rgb``        e_c(n) = |E′_c − E_c| / Φ_c per channel; mean/max/rms are those of the worst
  channel (the bound holds per channel).
* ``relative``        e(n) = |Y(E′) − Y(E)| / Y(E), over normals with Y(E) ≥ 10⁻³ max Y(E).
* ``peak``            e(n) = |Y(E′) − Y(E)| / max_n Y(E).

Each metric reports ``mean`` (over normals), ``max`` and ``rms`` = √(mean e²), plus the
uncertainty of mean and max propagated from the reference's per-normal uncertainty δ(n):
| |E′−E_true| − |E′−E| | ≤ δ, so mean and max move by at most mean(δ)/norm and max(δ)/norm.

:func:`per_normal_error` gives e(n) itself, one value per normal (the worst-case search maximises it):
``flux_rgb`` there is max_c e_c(n), and ``relative`` is 0 below the floor.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ..scenes.latlong import luminance

METRIC_NAMES = ("flux_luminance", "flux_rgb", "relative", "peak")
RELATIVE_FLOOR = 1e-3  # relative error is reported where Y(E) ≥ 1e-3 · max Y(E)

# R&H 2001 directional-light worst case for SH9 (order 2) irradiance, relative to Φ.
WORST_CASE_MAX = 3.0 / 32.0
WORST_CASE_MEAN = 0.0307  # ½∫_{-1}^{1} |3/32 + x/2 + 15x²/32 − max(0, x)| dx, = 0.030674…


@dataclass
class ErrorStats:
    mean: float
    max: float
    rms: float
    mean_uncertainty: float
    max_uncertainty: float

    def to_json(self) -> dict:
        return asdict(self)


def _stats(err: np.ndarray, unc: np.ndarray) -> ErrorStats:
    return ErrorStats(float(err.mean()), float(err.max()), float(np.sqrt((err**2).mean())),
                      float(unc.mean()), float(unc.max()))


def irradiance_errors(reference: np.ndarray, approx: np.ndarray, flux: np.ndarray,
                      uncertainty: np.ndarray | None = None) -> dict[str, ErrorStats]:
    """All metrics for E (N,3) vs E′ (N,3), total flux Φ (3,), reference uncertainty δ (N,3)."""
    if uncertainty is None:
        uncertainty = np.zeros_like(reference)
    diff = np.abs(approx - reference)
    ey, ey_ref, dy = luminance(approx), luminance(reference), luminance(uncertainty)
    phi_y = float(luminance(flux))
    dly = np.abs(ey - ey_ref)
    out = {"flux_luminance": _stats(dly / phi_y, dy / phi_y)}
    per_c = [_stats(diff[:, c] / flux[c], uncertainty[:, c] / flux[c]) for c in range(3) if flux[c] > 0]
    out["flux_rgb"] = ErrorStats(max(s.mean for s in per_c), max(s.max for s in per_c), max(s.rms for s in per_c),
                                 max(s.mean_uncertainty for s in per_c), max(s.max_uncertainty for s in per_c))
    peak = float(ey_ref.max())
    mask = ey_ref >= RELATIVE_FLOOR * peak
    out["relative"] = _stats(dly[mask] / ey_ref[mask], dy[mask] / ey_ref[mask])
    out["peak"] = _stats(dly / peak, dy / peak)
    return out


PER_NORMAL_METRICS = ("flux_luminance", "flux_rgb", "relative")


def per_normal_error(approx: np.ndarray, reference: np.ndarray, flux: np.ndarray, metric: str,
                     peak: float | None = None) -> np.ndarray:
    """e(n) (N,) of ``metric`` (one of :data:`PER_NORMAL_METRICS`) for E′ = approx, E = reference (N, 3), flux
    Φ (3,): ``flux_luminance`` |Y(E′) − Y(E)| / Φ_Y; ``flux_rgb`` max_c |E′_c − E_c| / Φ_c; ``relative``
    |Y(E′) − Y(E)| / Y(E) where Y(E) ≥ :data:`RELATIVE_FLOOR` · ``peak`` (default max Y(E) over these normals;
    a search passes the maximum over a fixed dense set so that adding normals does not move the floor), 0
    elsewhere."""
    if metric == "flux_luminance":
        return np.abs(luminance(approx) - luminance(reference)) / float(luminance(flux))
    if metric == "flux_rgb":
        return np.max(np.abs(approx - reference) / np.maximum(flux, 1e-300)[None, :], axis=1)
    y = luminance(reference)
    floor = RELATIVE_FLOOR * (float(y.max()) if peak is None else peak)
    return np.where(y >= floor, np.abs(luminance(approx) - y) / np.maximum(y, 1e-300), 0.0)


def directional_worst_case_mean(samples: int = 200001) -> float:
    """½ ∫_{-1}^{1} |K̃(x) − max(0, x)| dx with K̃ = 3/32 + x/2 + 15x²/32 (the SH9 clamped cosine)."""
    x = np.linspace(-1, 1, samples)
    k = 3 / 32 + x / 2 + 15 * x * x / 32
    return float(np.trapezoid(np.abs(k - np.maximum(x, 0)), x) / 2)
