"""Variance shadow maps (VSM): Chebyshev's bound on the filtered depth test from two moments [1].

The map stores (d, d²) of the normalised linear depth d, prefiltered with the 5×5 Gauss and read
bilinearly (:func:`~validate.local_models.shadow.shadow_map.filter_footprint`), giving μ = E[d] and
σ² = E[d²] − μ² over the filter's weights. For a receiver at depth t [1, eq. 5]:

    V′ = 1                         if t ≤ μ,
    V′ = p_max = σ² / (σ² + (t − μ)²)   otherwise (σ² clamped below at ``MIN_VARIANCE``).

By the one-sided Chebyshev (Cantelli) inequality p_max ≥ P(D ≥ t), the filtered depth test: VSM can
only err towards light. Where two occluders at different depths overlap a receiver's filter, σ² is
large and p_max ≫ P(D ≥ t): the "light bleeding" of [1] §3.2 (no bleeding reduction is applied here).

References
[1] W. Donnelly, A. Lauritzen, "Variance Shadow Maps", I3D 2006, eq. 5 and §3.2.
[2] T. Annen et al., "Exponential Shadow Maps", GI 2008, Fig. 1 (5×5 Gauss filtering of VSMs).
"""

from __future__ import annotations

import numpy as np

from ...scenes.shadow_scenes import DiscLight
from ..families import shadow
from .shadow_map import ShadowMap, filter_footprint

MIN_VARIANCE = 2.0**-20  # ≈ 1e-6: fp32 E[d²] − E[d]² of d ≤ 1 cancels to ~2⁻²⁴; 16× headroom


def vsm_visibility(b1: np.ndarray, b2: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Chebyshev's upper bound [1, eq. 5] from the first two moments and the receiver depth t."""
    var = np.maximum(b2 - b1 * b1, MIN_VARIANCE)
    p = var / (var + (t - b1) ** 2)
    return np.where(t <= b1, 1.0, np.clip(p, 0.0, 1.0))


@shadow.register("vsm", "variance shadow map: Chebyshev bound from (d, d²), 5×5 Gauss + bilinear",
                 source="Donnelly & Lauritzen 2006, eq. 5", upper_bound=True, memory_bytes_per_texel=8)
def shadow_vsm(shadow_map: ShadowMap, light: DiscLight, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    fp = filter_footprint(shadow_map, points)
    b = fp.moments(2)
    return vsm_visibility(b[:, 0], b[:, 1], fp.receiver)
