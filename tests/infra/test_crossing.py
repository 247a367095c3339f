"""validate.metrics.crossing: the last crossing of a level, located by Brent's method on the exact function.

Oracles are closed-form roots: f(x) = 1/x² crosses 0.01 at x = 10 exactly; with a bump above the level at
x ≈ 20 added (a max of two functions: continuous, not smooth), the last crossing is that of the bump's right
flank, 20 + 1.5·√(ln 10) (Gaussian 0.1·exp(−((x − 20)/1.5)²) = 0.01)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from validate.metrics import crossing

XTOL = 1e-6


def test_root_not_grid_node():
    f = lambda x: 1.0 / x**2  # noqa: E731
    x = np.geomspace(1.0, 40.0, 12)
    c = crossing.last_crossing(f, x, f(x), 0.01, XTOL)
    assert abs(c.root - 10.0) <= XTOL
    assert abs(c.grid_node - 10.0) > 100 * XTOL  # power: the grid-node answer misses the tolerance
    assert c.max_beyond <= 0.01 and c.bracket[0] <= c.root <= c.bracket[1]
    assert c.slope == pytest.approx(-2.0 / 10.0**3, rel=0.05)
    assert abs(crossing.bisect_last(f, float(x[5]), float(x[7]), 0.01, XTOL, 16) - 10.0) <= XTOL


def test_last_of_several_crossings_with_a_kink():
    f = lambda x: max(1.0 / x**2, 0.1 * math.exp(-(((x - 20.0) / 1.5) ** 2)))  # noqa: E731
    x = np.geomspace(1.0, 40.0, 24)
    fx = np.array([f(t) for t in x])
    c = crossing.last_crossing(f, x, fx, 0.01, XTOL)
    want = 20.0 + 1.5 * math.sqrt(math.log(10.0))
    assert abs(c.root - want) <= XTOL
    assert abs(c.root - 10.0) > 1.0  # power: the first crossing would be 10


def test_no_crossing_inside_the_sweep():
    x = np.linspace(1.0, 2.0, 5)
    below = crossing.last_crossing(lambda t: 0.0, x, np.zeros(5), 0.01, XTOL)
    assert below.root is None and below.below_grid and below.grid_node == 1.0
    above = crossing.last_crossing(lambda t: 1.0, x, np.ones(5), 0.01, XTOL)
    assert above.root is None and not above.below_grid and above.grid_node is None
