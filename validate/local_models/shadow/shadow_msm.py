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

import numpy as np

from ...scenes.shadow_scenes import DiscLight
from ..families import shadow
from .shadow_map import ShadowMap, filter_footprint

ALPHA = 3e-5


def hamburger_4msm(b: np.ndarray, z_f: np.ndarray, alpha: float = ALPHA) -> np.ndarray:
    """Shadow intensity G (N,) from moments b (N, 4) and fragment depths z_f (N,) [1, Algorithm 2]."""
    b = (1.0 - alpha) * np.asarray(b, dtype=np.float64) + alpha * 0.5
    b1, b2, b3, b4 = b.T
    one = np.ones_like(b1)
    hankel = np.stack([np.stack([one, b1, b2], -1), np.stack([b1, b2, b3], -1), np.stack([b2, b3, b4], -1)], -2)
    c = np.linalg.solve(hankel, np.stack([one, z_f, z_f * z_f], -1)[..., None])[..., 0]
    c1, c2, c3 = c.T
    disc = np.sqrt(np.maximum(c2 * c2 - 4 * c3 * c1, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        r1, r2 = (-c2 - disc) / (2 * c3), (-c2 + disc) / (2 * c3)
        z2, z3 = np.minimum(r1, r2), np.maximum(r1, r2)
        mid = (z_f * z3 - b1 * (z_f + z3) + b2) / ((z3 - z2) * (z_f - z2))
        far = 1 - (z2 * z3 - b1 * (z2 + z3) + b2) / ((z_f - z2) * (z_f - z3))
    g = np.where(z_f <= z2, 0.0, np.where(z_f <= z3, mid, far))
    return np.clip(np.nan_to_num(g, nan=0.0), 0.0, 1.0)


@shadow.register("msm", "moment shadow map: Hamburger 4MSM from (d, d², d³, d⁴), 5×5 Gauss + bilinear",
                 source="Peters & Klein 2015, Algorithm 2", upper_bound=True, memory_bytes_per_texel=16)
def shadow_msm(shadow_map: ShadowMap, light: DiscLight, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    fp = filter_footprint(shadow_map, points)
    return 1.0 - hamburger_4msm(fp.moments(4), fp.receiver)
