"""Timing for ``python -m validate bench``: best-of-N wall times, and two calls timed alternately.

The ratio of two alternately timed calls is what every side-by-side row of the bench reports (a projection
beside its plain reduction, a GLSL technique beside its Python transcription, a scipy fit beside its drjit-AD
twin): a load that comes and goes on the machine touches both alike, so the ratio holds where the absolute
times do not."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_time(fn: Callable[[], object], repeats: int = 3) -> float:
    """Best wall time of ``fn`` in seconds over ``repeats`` runs after one warm-up (JIT compilation, caches)."""
    fn()  # warm-up (JIT compilation, caches)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def best_pair(f: Callable[[], object], g: Callable[[], object], repeats: int = 7) -> tuple[float, float]:
    """Best times of f and g, run alternately (f, g, f, g, …) after one warm-up each, so that a load that
    comes and goes on the machine touches both alike: the ratio is the figure, not the absolute times."""
    f(), g()
    tf, tg = [], []
    for _ in range(repeats):
        for fn, times in ((f, tf), (g, tg)):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
    return min(tf), min(tg)
