"""Ask Mitsuba for radiance: ``emitter.eval`` at arbitrary world directions.

A direction d points from the scene *towards* the environment; Mitsuba's ``eval`` takes the
incident direction ``si.wi = −d`` (measured in ``tests/reference/test_latlong.py``).
"""

from __future__ import annotations

import numpy as np

from ..backend import init

CHUNK = 1 << 21


def eval_emitter(emitter, directions: np.ndarray) -> np.ndarray:
    """Radiance (N, 3) of a Mitsuba emitter for world directions (N, 3) (float32 in, float64 out)."""
    import drjit as dr  # function-level: drjit + mitsuba cost ~0.7 s to import; numpy-only callers skip it
    import mitsuba as mi

    backend = init()
    d = np.ascontiguousarray(directions.reshape(-1, 3), dtype=np.float32)
    out = np.empty((d.shape[0], 3), dtype=np.float64)
    if backend.is_vectorized:
        for s in range(0, d.shape[0], CHUNK):
            chunk = d[s:s + CHUNK]
            si = dr.zeros(mi.SurfaceInteraction3f, chunk.shape[0])
            si.wi = mi.Vector3f(-chunk[:, 0], -chunk[:, 1], -chunk[:, 2])
            out[s:s + CHUNK] = np.array(emitter.eval(si)).reshape(3, -1).T
    else:  # scalar_rgb: one direction at a time (slow, correct)
        for k, v in enumerate(d):
            si = dr.zeros(mi.SurfaceInteraction3f)
            si.wi = mi.Vector3f(-float(v[0]), -float(v[1]), -float(v[2]))
            out[k] = np.array(emitter.eval(si), dtype=np.float64).ravel()[:3]
    return out.reshape(directions.shape[:-1] + (3,))
