"""Mitsuba's point emitter asked directly: the irradiance it delivers at given receivers.

``emitter.sample_direction(it, ·)`` of Mitsuba 3's ``point`` plugin (src/emitters/point.cpp) returns the
direction to the light ``ds.d`` and the weight I/d² (intensity over squared distance, no sampling
noise: a delta emitter). The unshadowed irradiance on a receiver of normal n is then

    E = I/d² · max(0, n·ds.d)   [PBRT 4th ed. §12.1, E = I cos θ / r²],

evaluated in Mitsuba's float32 (relative rounding ≲ 10⁻⁶). Deterministic: uncertainty = float32 rounding.
"""

from __future__ import annotations

import numpy as np

from ..backend import init


def point_irradiance(position: np.ndarray, intensity: float, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(N,) E = I max(0, n·ω)/d² from Mitsuba's point emitter at ``position`` (module docstring)."""
    import drjit as dr
    import mitsuba as mi

    backend = init()
    emitter = mi.load_dict({"type": "point", "position": [float(x) for x in position],
                            "intensity": {"type": "rgb", "value": float(intensity)}})
    p = np.ascontiguousarray(np.asarray(points, dtype=np.float32).reshape(-1, 3))
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    if backend.is_vectorized:
        it = dr.zeros(mi.Interaction3f, len(p))
        it.p = mi.Point3f(p[:, 0], p[:, 1], p[:, 2])
        ds, w = emitter.sample_direction(it, mi.Point2f(0.5, 0.5), False)
        d = np.array(ds.d).reshape(3, -1).T
        weight = np.array(w).reshape(3, -1)[0]
    else:  # scalar variant: one receiver at a time
        d, weight = np.empty((len(p), 3)), np.empty(len(p))
        for i, q in enumerate(p):
            it = mi.Interaction3f()
            it.p = mi.Point3f(*map(float, q))
            ds, w = emitter.sample_direction(it, mi.Point2f(0.5, 0.5), False)
            d[i], weight[i] = np.array(ds.d), float(w[0])
    return weight.astype(np.float64) * np.maximum(0.0, np.sum(n * d, axis=1))


__all__ = ["point_irradiance"]
