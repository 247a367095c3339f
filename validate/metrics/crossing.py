"""Where a swept figure crosses a level for the last time: bracketed on the sweep's grid, refined by a root finder.

A finding such as "within 1 % beyond d/size = r" reports the root r of g(x) = f(x) − level, not the first grid
node past it. ``f`` is the sweep's own exact evaluation (the same reference and model as at the grid nodes, never
interpolated grid values). The bracket is the last sign change on the grid (f > level at node i, f ≤ level at
i + 1 and at every later node, which is reported as ``max_beyond``), cut into ``subdivisions`` sub-intervals
that are evaluated exactly, and the last sign change among them is refined by Brent's method
(Brent 1973, *Algorithms for Minimization without Derivatives*, ch. 4; ``scipy.optimize.brentq``): for a
continuous g with g(a)·g(b) < 0 it returns x₀ within ``xtol`` (+ 4·10⁻¹⁶|x₀|) of a root in [a, b]. Smoothness
is not needed: a maximum over receivers is continuous but has kinks where the worst receiver changes, where
Brent's interpolation steps are rejected and it falls back to bisection. What the grid and the sub-grid cannot
exclude is a further excursion above the level narrower than the sub-grid spacing beyond the reported root.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

DEFAULT_SUBDIVISIONS = 16


@dataclass(frozen=True)
class Crossing:
    """The last crossing of ``level`` by f on the swept range.

    ``root`` is None when f ≤ level at every node (``below_grid``: the crossing, if any, lies before the first
    node) or when f > level at the last node (no crossing inside the sweep). ``grid_node`` is the first node past
    the crossing (what a grid-node answer would report)."""

    root: float | None
    xtol: float
    level: float
    bracket: tuple[float, float] | None
    grid_node: float | None
    max_beyond: float  # max of f over the grid nodes past the root (≤ level by construction)
    slope: float | None  # the secant df/dx over the final bracket (turns an error in f into one in x)
    evaluations: int  # exact evaluations of f beyond the grid's
    below_grid: bool

    def to_json(self) -> dict[str, Any]:
        d = asdict(self)
        d["bracket"] = list(self.bracket) if self.bracket is not None else None
        return d


def last_crossing(f: Callable[[float], float], x: Sequence[float], fx: Sequence[float], level: float, xtol: float,
                  subdivisions: int = DEFAULT_SUBDIVISIONS) -> Crossing:
    """The root of f − level after which f stays ≤ level on the grid ``x`` (increasing) with values ``fx`` = f(x)
    (module docstring). A NaN value counts as above the level."""
    from scipy.optimize import brentq

    x, fx = np.asarray(x, dtype=np.float64), np.asarray(fx, dtype=np.float64)
    above = np.nonzero(~(fx <= level))[0]
    if above.size == 0:
        return Crossing(None, xtol, level, None, float(x[0]), float(np.max(fx)), None, 0, True)
    i = int(above[-1])
    if i + 1 >= x.size:
        return Crossing(None, xtol, level, None, None, float("nan"), None, 0, False)
    sub = np.linspace(x[i], x[i + 1], subdivisions + 1)
    fsub = np.concatenate([[fx[i]], [f(float(s)) for s in sub[1:-1]], [fx[i + 1]]])
    j = int(np.nonzero(~(fsub <= level))[0][-1])
    calls = [0]

    def g(t: float) -> float:
        calls[0] += 1
        return f(t) - level

    root = float(brentq(g, sub[j], sub[j + 1], xtol=xtol))
    return Crossing(root, xtol, level, (float(sub[j]), float(sub[j + 1])), float(x[i + 1]),
                    float(np.max(fx[i + 1:])), float((fsub[j + 1] - fsub[j]) / (sub[j + 1] - sub[j])),
                    subdivisions - 1 + calls[0], False)


def bisect_last(f: Callable[[float], float], lo: float, hi: float, level: float, xtol: float, scan: int) -> float:
    """An independent locator of the same crossing: scan ``scan`` + 1 equal nodes of [lo, hi], take the last one
    above the level, and bisect (plain interval halving, no interpolation) until the bracket is ≤ ``xtol`` wide;
    returns its midpoint (within xtol/2 of a root)."""
    nodes = np.linspace(lo, hi, scan + 1)
    vals = np.array([f(float(t)) for t in nodes])
    above = np.nonzero(~(vals <= level))[0]
    if above.size == 0 or above[-1] + 1 >= nodes.size:
        return float("nan")
    a, b = float(nodes[above[-1]]), float(nodes[above[-1] + 1])
    while b - a > xtol:
        m = 0.5 * (a + b)
        if f(m) <= level:
            b = m
        else:
            a = m
    return 0.5 * (a + b)
