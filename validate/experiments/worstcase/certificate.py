"""Worst-case certificates of techniques that are linear in the lighting, and the linearity test.

**Why one direction suffices.** Let a technique be linear in the lighting, E′ = T L, per channel and the
same in every channel, and let the truth be the texel quadrature E(n) = Σ_j L_j max(0, n·ω_j) ΔΩ_j. With
w_j = L_j ΔΩ_j / Φ (Φ = Σ_j L_j ΔΩ_j; w ≥ 0, Σ w_j = 1: the simplex) and d_j(n) the error of a unit-flux
light in texel j alone, the flux-normalised error is e(n) = |Σ_j w_j d_j(n)|. For every fixed n this is a
convex function of w, and so are max_n e(n) and mean_n e(n) (a max and a mean of convex functions); a
convex function on the simplex attains its maximum at a vertex, i.e. at one texel: the supremum over ALL
non-negative lighting of a map's resolution is max_j (max or mean)_n |d_j(n)|. The luminance metric is the
same with w_j = Y(L_j) ΔΩ_j / Φ_Y (Y is linear), so one grey texel covers ``flux_luminance`` and
``flux_rgb`` alike. For SH9 d_j(n) = K̃(n·ω_j) − max(0, n·ω_j) with K̃(x) = 3/32 + x/2 + 15x²/32 (R&H JOSA
2001 [1]): max 3/32 at the horizon, mean ½∫|K̃ − max(0, x)| dx = 0.030674 — both **relative to the total
flux Φ = ∫ L dω** (not to E, not to E/π, not to the peak irradiance): that normalisation is what makes 3/32
appear, and the only one under which a lighting-independent bound exists.

**Computing it.** A unit-flux grey delta in every texel of an H₀×2H₀ map (one technique call each), the
error over :data:`NORMALS` Fibonacci normals; the :data:`KEEP` worst texels are refined on maps of 2H, 4H, …
(the texels of the finer map within 1.5 coarse texels of each kept direction), and at every level the worst
normal is refined off the normal set (:func:`.errors.worst_normal`). The level values show the convergence;
the certificate is the last level's value, its uncertainty the last change between levels.

**Linearity test** (not assumed): f(aL₁ + bL₂) against a f(L₁) + b f(L₂) on random non-negative HDR maps
(texels log-uniform in [10⁻², 10⁵], the range of real probes with a sun), flux-normalised;
:data:`LINEARITY_TOLERANCE`.

References
  [1] R. Ramamoorthi, P. Hanrahan, "On the relationship between radiance and irradiance", JOSA A 18(10),
      2001; "An Efficient Representation for Irradiance Environment Maps", SIGGRAPH 2001.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...scenes.latlong import fibonacci_sphere, luminance
from .errors import Technique, check_metric, errors_at, worst_normal
from .lighting import FLUX_REFERENCE, flux_numpy, texel_geometry, truth_numpy

NORMALS = 500
KEEP = 3
# float32 projections of maps spanning 7 decades: the linear techniques differ from exact linearity by
# rounding, measured ≤ 2.2·10⁻⁷ Φ (sh9, sh9_hanning, sh9_lanczos, hemisphere) and 1.3·10⁻⁵ Φ (three_sh, float32
# cube faces); 10⁻⁴ Φ leaves 7×, and is 100× below the smallest defect of a nonlinear technique measured
# (zh3_stored 0.010; zh3_hallucinated 0.049, sh1_geomerics 0.039, babylon_sh 0.035, sh9_cmgen_auto 0.128).
LINEARITY_TOLERANCE = 1e-4
LINEARITY_PAIRS = 3
LINEARITY_HEIGHT = 16
LINEARITY_COEFFS = (0.7, 1.9)


def linearity_defect(fn: Technique, seed: int) -> float:
    """max over :data:`LINEARITY_PAIRS` random pairs, plus (a one-texel sun, a uniform sky), and 500 normals of
    |f(aL₁ + bL₂) − a f(L₁) − b f(L₂)| / Φ_Y(aL₁ + bL₂) (luminance-weighted)."""
    rng = np.random.default_rng([seed, 22])
    normals = fibonacci_sphere(500)
    a, b = LINEARITY_COEFFS
    worst = 0.0
    shape = (LINEARITY_HEIGHT, 2 * LINEARITY_HEIGHT, 3)
    sun = delta_map(LINEARITY_HEIGHT, LINEARITY_HEIGHT * LINEARITY_HEIGHT // 2 + 3) + 1e-3
    pairs = [tuple(10.0 ** rng.uniform(-2.0, 5.0, size=shape) for _ in range(2)) for _ in range(LINEARITY_PAIRS)]
    for l1, l2 in pairs + [(sun, np.ones(shape))]:  # + a sun and a uniform sky: ringing vs none
        mix = a * l1 + b * l2
        d = fn(mix.astype(np.float32), normals) - a * fn(l1.astype(np.float32), normals) \
            - b * fn(l2.astype(np.float32), normals)
        defect = float(np.max(np.abs(d) @ np.array([0.2126, 0.7152, 0.0722])))
        worst = max(worst, defect / float(luminance(flux_numpy(mix))))
    return worst


def delta_map(height: int, texel: int, flux: float = FLUX_REFERENCE) -> np.ndarray:
    """A grey map of flux ``flux`` entirely in one texel (row-major index) of an H×2H map."""
    _, dw = texel_geometry(height)
    m = np.zeros((height * 2 * height, 3), dtype=np.float32)
    m[texel] = flux / dw[texel]
    return m.reshape(height, 2 * height, 3)


@dataclass
class Certificate:
    technique: str
    metric: str
    value: float
    uncertainty: float
    direction: list[float]
    normal: list[float]
    levels: list[tuple[int, float]]  # (H, value) per refinement level
    calls: int
    texel: int  # the worst texel of the last level's H×2H map
    errors_over_normals: Any = field(default=None, repr=False)  # (normals, e) of the worst light, for the figure

    def to_json(self) -> dict[str, Any]:
        return {"technique": self.technique, "metric": self.metric, "value": self.value,
                "uncertainty": self.uncertainty, "direction": self.direction, "normal": self.normal,
                "levels": [list(x) for x in self.levels], "calls": self.calls}

    def at(self, height: int) -> float:
        """The certificate of maps of this resolution (the level of that H)."""
        return next(v for h, v in self.levels if h == height)


def _stat(e: np.ndarray, stat: str) -> float:
    return float(e.max() if stat == "max" else e.mean())


def delta_map3(height: int, texels: np.ndarray, flux: float = FLUX_REFERENCE) -> np.ndarray:
    """Up to three unit-flux deltas at once, texel ``texels[c]`` in channel c alone (a channel-separable
    technique answers each independently: tested by :func:`crosstalk`)."""
    _, dw = texel_geometry(height)
    m = np.zeros((height * 2 * height, 3), dtype=np.float32)
    for c, j in enumerate(texels):
        m[int(j), c] = flux / dw[int(j)]
    return m.reshape(height, 2 * height, 3)


TexelErrors = dict[tuple[int, tuple[int, ...]], np.ndarray]  # (H, texel group) → |d_j(n)| (NORMALS, 3)


def _texel_values(fn: Technique, height: int, texels: np.ndarray, metric: str,
                  memo: TexelErrors | None = None) -> np.ndarray:
    """(max or mean)_n |d_j(n)| for each texel, three texels per call (one per channel). ``memo`` keeps the
    per-normal errors of each call, so certificates of one technique for several metrics (max and mean) share
    the technique calls of the maps they have in common (the coarse sweep)."""
    _, stat = check_metric(metric)
    normals = fibonacci_sphere(NORMALS)
    memo = {} if memo is None else memo
    out = []
    for s in range(0, len(texels), 3):
        group = texels[s:s + 3]
        key = (height, tuple(int(j) for j in group))
        if key not in memo:
            m = delta_map3(height, group)
            memo[key] = np.abs(fn(m, normals) - truth_numpy(m, normals)) / FLUX_REFERENCE
        e = memo[key]
        out += [_stat(e[:, c], stat) for c in range(len(group))]
    return np.array(out)


def crosstalk(fn: Technique, height: int = LINEARITY_HEIGHT) -> float:
    """max_n,c |f(δ_c)_c′ − [c = c′] f(δ_grey)_c| / Φ over channels c: a single-channel delta must light its
    own channel only, exactly as the grey delta does (channel separability, identical channels)."""
    normals = fibonacci_sphere(200)
    j = height * height + height // 2  # a texel below the equator
    grey = fn(delta_map(height, j), normals)
    worst = 0.0
    for c in range(3):
        m = np.zeros((height, 2 * height, 3), dtype=np.float32)
        m[..., c] = delta_map(height, j)[..., c]
        expect = np.zeros_like(grey)
        expect[:, c] = grey[:, c]
        worst = max(worst, float(np.max(np.abs(fn(m, normals) - expect))) / FLUX_REFERENCE)
    return worst


def _neighbours(height: int, directions: np.ndarray, radius: float) -> np.ndarray:
    d, _ = texel_geometry(height)
    near = (d @ directions.T).max(axis=1) >= np.cos(radius)
    return np.flatnonzero(near)


def certificate(fn: Technique, name: str, metric: str, coarse: int, levels: int,
                memo: TexelErrors | None = None) -> Certificate:
    """sup over non-negative lighting of ``metric`` for a linear technique (module docstring). ``memo``: shared
    by the certificates of the same ``fn`` (:func:`_texel_values`); ``calls`` counts the texels evaluated
    whether or not the memo answered."""
    texels = np.arange(coarse * 2 * coarse)
    h, calls, path = coarse, 0, []
    best_dir, best_n, keep = None, None, None
    for level in range(levels):
        if level > 0:
            h *= 2
            texels = _neighbours(h, keep, 1.5 * np.pi / (h // 2 - 1))
        vals = _texel_values(fn, h, texels, metric, memo)
        calls += len(texels)
        order = np.argsort(vals)[::-1][:KEEP]
        d, _ = texel_geometry(h)
        keep = d[texels[order]]
        value, normal = worst_normal(fn, delta_map(h, int(texels[order[0]])), metric)
        path.append((h, value))
        best_dir, best_n = keep[0], normal
    unc = abs(path[-1][1] - path[-2][1]) if len(path) > 1 else 0.0
    base, _ = check_metric(metric)
    dense = fibonacci_sphere(2000)
    worst_light = delta_map(h, int(texels[order[0]]))
    e = errors_at(fn, worst_light, dense, base)
    return Certificate(name, metric, path[-1][1], unc, [float(x) for x in best_dir], [float(x) for x in best_n],
                       path, calls, int(texels[order[0]]), (dense, e))
