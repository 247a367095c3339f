"""Exponential shadow maps (ESM): the depth test approximated by exp(c (d − t)) [1].

The map stores exp(c·d) of the normalised linear depth d, prefiltered with the 5×5 Gauss and read
bilinearly (:func:`~validate.local_models.shadow.shadow_map.filter_footprint`). For a receiver at depth t
[1, eq. 4–5]:

    V′ = clamp(e^(−c t) · E[e^(c d)], 0, 1) = clamp(E[e^(c (d − t))], 0, 1).

Since e^(c (d − t)) ≥ 1[d ≥ t] for every d (Markov's inequality on e^(cD)), V′ ≥ P(D ≥ t), the
filtered depth test: ESM errs towards light, by e^(−c (t − d)) for an occluder at d < t — the leak
near contact points that grows as t − d shrinks.

``C = 80``: e^(c d) for d ≤ 1 must fit in the fp32 moment texture, e^(88.7) = FLT_MAX; c = 80 keeps a
factor e^(8.7) ≈ 6000 of headroom and is the largest round value that does (the paper's discussion of c,
§3.3: larger c sharpens the test and reduces leaking, bounded by float range).

References
[1] T. Annen, T. Mertens, H.-P. Seidel, E. Flerackers, J. Kautz, "Exponential Shadow Maps", Graphics
    Interface 2008, eq. 4–5, §3.3; Fig. 1: 5×5 Gauss filtering.
"""

from __future__ import annotations

import numpy as np

from ...scenes.shadow_scenes import DiscLight
from ..families import shadow
from ..precision import to_np
from .shadow_map import ShadowMap, filter_footprint, footprint_dr

C = 80.0


@shadow.register("esm", "exponential shadow map: clamp(E[exp(c(d − t))]), c = 80, 5×5 Gauss + bilinear",
                 source="Annen et al. 2008, eq. 4–5", upper_bound=True, memory_bytes_per_texel=4)
def shadow_esm(shadow_map: ShadowMap, light: DiscLight, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    import drjit as dr

    fp = footprint_dr(filter_footprint(shadow_map, points))
    v = fp.filtered(dr.exp(C * (fp.depth - fp.receiver_per_tap)))
    return to_np(dr.clip(v, 0.0, 1.0), (fp.n,))
