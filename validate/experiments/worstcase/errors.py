"""Per-normal error of one technique on one map, and the refinement of the worst normal.

The metrics are :func:`validate.metrics.irradiance_error.per_normal_error` (``flux_luminance``, ``flux_rgb``,
``relative``); for ``relative`` the maximum Y(E) is taken over a fixed dense normal set, :data:`DENSE_NORMALS`,
so that adding normals does not move the floor. A metric name is ``<metric>.<max|mean>``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ...errors import ValidateError
from ...local_models import irradiance
from ...metrics.irradiance_error import per_normal_error
from ...scenes.latlong import fibonacci_sphere, luminance
from .lighting import flux_numpy, truth_numpy

METRICS = ("flux_luminance.max", "flux_rgb.max", "relative.max", "flux_luminance.mean", "flux_rgb.mean")
DENSE_NORMALS = 4096
# pattern search on the sphere: radii from 0.05 rad halving to 0.05/2¹⁴ ≈ 3·10⁻⁶ rad; the metrics are
# Lipschitz in n (|dE/dn| ≤ Φ for the truth, ≤ a few Φ for an order-2 SH technique), so the last radius
# leaves < 10⁻⁵ of the maximum unresolved.
REFINE_START, REFINE_STEPS, MOVES_PER_RADIUS = 0.05, 15, 3

Technique = Callable[[np.ndarray, np.ndarray], np.ndarray]


def check_metric(metric: str) -> tuple[str, str]:
    base, _, stat = metric.partition(".")
    if metric not in METRICS:
        raise ValidateError(f"worst case: metric {metric!r}: expected one of {', '.join(METRICS)}")
    return base, stat


def registered(name: str, scale: float = 1.0) -> Technique:
    """The registered technique through the family contract (× ``scale``: the power perturbation)."""
    tech = irradiance[name]

    def fn(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
        return scale * irradiance.call(tech, radiance, normals)
    return fn


def errors_at(fn: Technique, radiance: np.ndarray, normals: np.ndarray, base: str,
              peak: float | None = None) -> np.ndarray:
    return per_normal_error(fn(radiance, normals), truth_numpy(radiance, normals), flux_numpy(radiance), base, peak)


def tangent_frame(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t = np.cross(n, a)
    t /= np.linalg.norm(t)
    return t, np.cross(n, t)


def worst_normal(fn: Technique, radiance: np.ndarray, metric: str) -> tuple[float, np.ndarray]:
    """(value, normal) of the metric's worst normal: the dense set, then (``max`` metrics) a pattern search
    of 8 neighbours at radii :data:`REFINE_START` · 2⁻ᵏ around the best (monotone: never below the dense max)."""
    base, stat = check_metric(metric)
    dense = fibonacci_sphere(DENSE_NORMALS)
    truth = truth_numpy(radiance, dense)
    peak = float(luminance(truth).max())
    e = per_normal_error(fn(radiance, dense), truth, flux_numpy(radiance), base, peak)
    if stat == "mean":
        return float(e.mean()), dense[int(np.argmax(e))]
    best, n = float(e.max()), dense[int(np.argmax(e))]
    ang = np.arange(8) * (np.pi / 4)
    for k in range(REFINE_STEPS):
        r = REFINE_START * 0.5 ** k
        for _ in range(MOVES_PER_RADIUS):
            t, b = tangent_frame(n)
            cand = n[None, :] + r * (np.cos(ang)[:, None] * t + np.sin(ang)[:, None] * b)
            cand /= np.linalg.norm(cand, axis=1, keepdims=True)
            ec = errors_at(fn, radiance, cand, base, peak)
            if ec.max() <= best:
                break
            best, n = float(ec.max()), cand[int(np.argmax(ec))]
    return best, n
