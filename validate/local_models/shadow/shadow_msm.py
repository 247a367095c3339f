"""Moment shadow maps (MSM): the sharp bound on the filtered depth test from four moments [1].

The map stores b = (d, d², d³, d⁴) of the normalised linear depth d, prefiltered with the 5×5 Gauss
and read bilinearly (:func:`~validate.local_models.shadow.shadow_map.filter_footprint`). Hamburger 4MSM
[1, Algorithm 2], for a receiver at depth z_f:

1. b′ = (1 − α) b + α (½, ½, ½, ½) (the moments of a mixture with a Bernoulli(½) on {0, 1}, which
   makes the Hankel matrix positive definite);
2. solve [[1, b′₁, b′₂], [b′₁, b′₂, b′₃], [b′₂, b′₃, b′₄]] c = (1, z_f, z_f²) (Cholesky in [1]);
3. z₂ ≤ z₃, the roots of c₃ z² + c₂ z + c₁ = 0;
4. G = 0 if z_f ≤ z₂; G = (z_f z₃ − b′₁ (z_f + z₃) + b′₂) / ((z₃ − z₂)(z_f − z₂)) if z_f ≤ z₃;
   G = 1 − (z₂ z₃ − b′₁ (z₂ + z₃) + b′₂) / ((z_f − z₂)(z_f − z₃)) otherwise;
5. V′ = 1 − G.

G is the smallest shadow intensity P(D < z_f) of any distribution with the moments b′ [1, §3], so
V′ ≥ P′(D ≥ z_f) ≥ P(D ≥ z_f) − α/2 for the filtered depth test P: MSM errs towards light, and
less than VSM (two moments) where several occluders overlap a filter.

``ALPHA = 3·10⁻⁵``: the moment bias of [1]'s Algorithm 2 for moments stored in 32-bit floats.

References
[1] C. Peters, R. Klein, "Moment Shadow Mapping", I3D 2015, Algorithm 2 (Hamburger 4MSM), §3.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...scenes.shadow_scenes import DiscLight
from ..families import shadow
from ..precision import to_dr, to_np
from .shadow_map import ShadowMap, filter_footprint, footprint_dr

ALPHA = 3e-5


def hamburger_4msm_dr(b1: Any, b2: Any, b3: Any, b4: Any, z_f: Any, alpha: float = ALPHA) -> Any:
    """Shadow intensity G from the moments b1…b4 and fragment depths z_f (drjit arrays) [1, Algorithm 2]; the
    3×3 Hankel system is solved by its LDLᵀ (Cholesky) factorisation, as in [1]."""
    import drjit as dr

    b1, b2, b3, b4 = ((1.0 - alpha) * b + alpha * 0.5 for b in (b1, b2, b3, b4))
    d2 = b2 - b1 * b1  # H = L D Lᵀ: L = [[1, 0, 0], [b1, 1, 0], [b2, l32, 1]], D = diag(1, d2, d3)
    l32 = (b3 - b1 * b2) / d2
    d3 = b4 - b2 * b2 - l32 * l32 * d2
    y2 = z_f - b1  # L y = (1, z_f, z_f²)
    y3 = z_f * z_f - b2 - l32 * y2
    c3 = y3 / d3  # Lᵀ c = D⁻¹ y
    c2 = y2 / d2 - l32 * c3
    c1 = 1.0 - b1 * c2 - b2 * c3
    disc = dr.sqrt(dr.maximum(c2 * c2 - 4 * c3 * c1, 0.0))
    r1, r2 = (-c2 - disc) / (2 * c3), (-c2 + disc) / (2 * c3)
    z2, z3 = dr.minimum(r1, r2), dr.maximum(r1, r2)
    mid = (z_f * z3 - b1 * (z_f + z3) + b2) / ((z3 - z2) * (z_f - z2))
    far = 1 - (z2 * z3 - b1 * (z2 + z3) + b2) / ((z_f - z2) * (z_f - z3))
    g = dr.select(z_f <= z2, 0.0, dr.select(z_f <= z3, mid, far))
    g = dr.select(dr.isnan(g), 0.0, g)
    return dr.clip(g, 0.0, 1.0)


def hamburger_4msm(b: np.ndarray, z_f: np.ndarray, alpha: float = ALPHA) -> np.ndarray:
    """G (N,) from moments b (N, 4) and fragment depths z_f (N,): :func:`hamburger_4msm_dr` with numpy in/out,
    in the active dtype of :mod:`..precision`."""
    b = np.asarray(b, dtype=np.float64).reshape(-1, 4)
    return to_np(hamburger_4msm_dr(*(to_dr(b[:, k]) for k in range(4)), to_dr(z_f), alpha), (len(b),))


@shadow.register("msm", "moment shadow map: Hamburger 4MSM from (d, d², d³, d⁴), 5×5 Gauss + bilinear",
                 source="Peters & Klein 2015, Algorithm 2", upper_bound=True, memory_bytes_per_texel=16)
def shadow_msm(shadow_map: ShadowMap, light: DiscLight, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    fp = footprint_dr(filter_footprint(shadow_map, points))
    return to_np(1.0 - hamburger_4msm_dr(*fp.moments(4), fp.receiver), (fp.n,))
