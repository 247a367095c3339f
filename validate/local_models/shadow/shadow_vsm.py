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

from typing import Any

import numpy as np

from ...scenes.shadow_scenes import DiscLight
from ..families import shadow
from ..precision import to_dr, to_np
from .shadow_map import ShadowMap, filter_footprint, footprint_dr

MIN_VARIANCE = 2.0**-20  # ≈ 1e-6: fp32 E[d²] − E[d]² of d ≤ 1 cancels to ~2⁻²⁴; 16× headroom


def vsm_visibility_dr(b1: Any, b2: Any, t: Any) -> Any:
    """Chebyshev's upper bound [1, eq. 5] from the first two moments and the receiver depth t (drjit arrays)."""
    import drjit as dr

    var = dr.maximum(b2 - b1 * b1, MIN_VARIANCE)
    p = var / (var + (t - b1) * (t - b1))
    return dr.select(t <= b1, 1.0, dr.clip(p, 0.0, 1.0))


def vsm_visibility(b1: np.ndarray, b2: np.ndarray, t: np.ndarray) -> np.ndarray:
    """:func:`vsm_visibility_dr` with numpy in/out, in the active dtype of :mod:`..precision`."""
    t = np.asarray(t, dtype=np.float64)
    return to_np(vsm_visibility_dr(to_dr(b1), to_dr(b2), to_dr(t)), t.shape)


@shadow.register("vsm", "variance shadow map: Chebyshev bound from (d, d²), 5×5 Gauss + bilinear",
                 source="Donnelly & Lauritzen 2006, eq. 5", upper_bound=True, memory_bytes_per_texel=8)
def shadow_vsm(shadow_map: ShadowMap, light: DiscLight, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    fp = footprint_dr(filter_footprint(shadow_map, points))
    b1, b2 = fp.moments(2)
    return to_np(vsm_visibility_dr(b1, b2, fp.receiver), (fp.n,))
