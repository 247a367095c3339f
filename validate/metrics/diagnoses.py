"""What a failed per-pixel judgement most likely means: a global scale, a raster shift.

Global scale. The least-squares factor k of e ≈ k·m over the judged pixels, each value weighted by 1/σ²
(σ the judgement's per-value uncertainty, :func:`validate.metrics.pixel_z.judge`):

    k = Σ e m/σ² / Σ m²/σ²,   u(k) = √(1/Σ m²/σ²) · max(1, √(χ²/(N − 1)))

— the weighted mean's standard error, inflated by the fit's reduced χ² when the residuals scatter more than σ
says (they do when the engine is wrong in more than its scale). :func:`named_factor` names k when it matches one
of :data:`NAMED_FACTORS` within max(3u, ``NAME_TOLERANCE``·c): a missing or extra π (radiance vs irradiance,
the Lambert 1/π), 4π (intensity vs flux of an isotropic point light), 683 lm/W (photometric vs radiometric units).

Raster shift. :func:`shifted` resamples an image by a sub-pixel offset (bilinear, edges clamped); a judge that
tries ±½ px in x and y finds an engine whose pixel centres sit on the pixel corners (D3D9's half-pixel offset,
an uncorrected TAA jitter).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ValidateError

NAMED_FACTORS = {"π": math.pi, "1/π": 1 / math.pi, "4π": 4 * math.pi, "1/(4π)": 1 / (4 * math.pi),
                 "2π": 2 * math.pi, "1/(2π)": 1 / (2 * math.pi), "683": 683.0, "1/683": 1 / 683.0,
                 "2": 2.0, "1/2": 0.5}
# a factor that is a named constant to 0.1 % is that constant, however small u: engines store half floats
# (relative step 2⁻¹¹ ≈ 0.05 %) and budgets of ~0.25 % leave k this loose even without noise
NAME_TOLERANCE = 1e-3
SHIFTS = ((0.0, 0.5), (0.0, -0.5), (0.5, 0.0), (-0.5, 0.0), (0.5, 0.5), (0.5, -0.5), (-0.5, 0.5), (-0.5, -0.5))


def global_scale(engine: np.ndarray, mean: np.ndarray, sigma: np.ndarray, mask: np.ndarray) -> tuple[float, float]:
    """(k, u(k)) of e ≈ k·m on ``mask`` (module docstring); arrays (R, R, 3), σ > 0 where m ≠ 0."""
    e, m, s = engine[mask].ravel(), mean[mask].ravel(), sigma[mask].ravel()
    s = np.where(s > 0, s, max(float(np.abs(m).max()), 1e-30) * 1e-6)  # a noise-free truth: tiny equal weights
    w = 1.0 / s**2
    smm = float((w * m * m).sum())
    if smm <= 0:
        raise ValidateError("global scale: the truth is zero on every judged pixel")
    k = float((w * e * m).sum() / smm)
    chi2 = float((w * (e - k * m) ** 2).sum()) / max(e.size - 1, 1)
    return k, math.sqrt(1.0 / smm) * max(1.0, math.sqrt(chi2))


def named_factor(k: float, u: float) -> str | None:
    """The name of :data:`NAMED_FACTORS` that ``k`` ± ``u`` matches (the closest, relative), or None."""
    best = None
    for name, c in NAMED_FACTORS.items():
        d = abs(k - c)
        if d <= max(3.0 * u, NAME_TOLERANCE * c) and (best is None or d / c < best[1]):
            best = (name, d / c)
    return None if best is None else best[0]


def shifted(image: np.ndarray, dy: float, dx: float) -> np.ndarray:
    """``image`` (R, C, …) resampled at (i − dy, j − dx) (bilinear, clamped at the edges): if the engine's pixel
    (i, j) shows the truth at (i + dy, j + dx), the result shows it at (i, j)."""
    r, c = image.shape[:2]
    y = np.clip(np.arange(r) - dy, 0, r - 1)
    x = np.clip(np.arange(c) - dx, 0, c - 1)
    y0, x0 = np.floor(y).astype(int), np.floor(x).astype(int)
    y1, x1 = np.minimum(y0 + 1, r - 1), np.minimum(x0 + 1, c - 1)
    fy, fx = (y - y0)[:, None], (x - x0)[None, :]
    if image.ndim == 3:
        fy, fx = fy[..., None], fx[..., None]
    a = image[y0][:, x0] * (1 - fx) + image[y0][:, x1] * fx
    b = image[y1][:, x0] * (1 - fx) + image[y1][:, x1] * fx
    return a * (1 - fy) + b * fy
