"""The share of a scene's light that global illumination carries, and the share an engine's image misses.

A scene with two truths of the same pixels — the full light transport F (every bounce) and the direct-only D (the
camera ray's surface lit by the lights and the environment, with shadows: what an engine without global
illumination computes) — has the global-illumination share over a set of pixels M

    g = 1 − Σ_M D / Σ_M F                                                    (sums over the pixels and channels)

the fraction of the radiance reaching the camera that bounced more than once. The same ratio of an engine's image
E against F is the share the engine misses, m = 1 − Σ_M E / Σ_M F (negative: it adds light).

Uncertainty. The truths are P passes each, pass i of both traced with the same seed; the value is the ratio of the
pass means and its standard error the spread of the per-pass ratios g_i = 1 − Σ D_i / Σ F_i (E for D_i: an image
is one fixed set of numbers), u = sd(g_i)/√P, with the image's own per-value readback error r added in quadrature
as √(Σ r²)/Σ F. Not Σ stderr² over the pixels: within one pass Mitsuba's samples of different pixels are
positively correlated — measured on ``room_opening`` at 24², 64 spp × 8 passes, four seeds: the per-pass totals
scatter with sd 2.9–3.9 where the per-pixel variances sum to 2.3–2.5, and four truths' totals differ by twice
their Σ stderr² error — so a sum's error from the pixels' would be too small by up to 2×; the pass-to-pass spread
holds the correlation, and the pairing of D and F cancels their shared first bounce.

Two pixel sets: the judged pixels, and those the direct light does not reach (:func:`unlit_mask`: the direct truth
at most :data:`UNLIT_OF_PEAK` of its peak), where g is 1 by construction and an engine's m says how much of the
bounced light it lacks there.
"""

from __future__ import annotations

import numpy as np

from ..errors import ValidateError
from ..stats import Measured

UNLIT_OF_PEAK = 1e-3  # a pixel whose direct truth is ≤ 0.1 % of the direct peak counts as unlit (the sun's shadow)


def missing_share(x_passes: np.ndarray, full_passes: np.ndarray, mask: np.ndarray,
                  x_readback: np.ndarray | float = 0.0) -> Measured:
    """1 − Σ x / Σ full over ``mask`` (module docstring) ± its standard error. ``full_passes``: (P, *S, 3), S the
    pixels' shape ((H, W), or (N,) for a list of pixels), ``mask`` of shape S; ``x_passes``: (P, *S, 3) passes
    paired with ``full_passes``' (a truth of the same seed), or (*S, 3): one fixed image with its per-value
    ``x_readback`` error."""
    if not mask.any():
        raise ValidateError("missing share: no pixel to sum over")
    p = full_passes.shape[0]
    f_i = full_passes[:, mask].sum(axis=(1, 2))
    x_i = (x_passes[:, mask].sum(axis=(1, 2)) if x_passes.ndim == full_passes.ndim
           else np.full(p, float(x_passes[mask].sum())))
    f = float(f_i.mean())
    if not f > 0:
        raise ValidateError("missing share: the full truth is dark over the pixels")
    r = np.broadcast_to(np.asarray(x_readback, np.float64), (*mask.shape, 3))
    u = float(np.sqrt(np.var(1.0 - x_i / f_i, ddof=1) / p + np.sum(r[mask] ** 2) / f**2))
    return Measured(1.0 - float(x_i.mean()) / f, u, unit="%", stat="mean",
                    params={"n_pixels": int(mask.sum()), "passes": int(p)})


def unlit_mask(direct: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """The pixels of ``mask`` whose direct truth (summed over the channels) is at most :data:`UNLIT_OF_PEAK` of its
    peak there."""
    d = np.nan_to_num(direct, nan=0.0).sum(axis=-1)
    peak = float(d[mask].max()) if mask.any() else 0.0
    return mask & (d <= UNLIT_OF_PEAK * peak)
