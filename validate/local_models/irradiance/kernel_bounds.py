"""The near-directional error bound shared by the irradiance techniques that depend on L00 and L1 only
(Geomerics L1 in :mod:`.windowed_sh`, hallucinated ZH3 in :mod:`.zh3`); the derivation is in
:mod:`.windowed_sh`'s docstring:

    |E′ − E| / Φ ≤ max_{ρ ∈ [cos α, 1]} max( sup_x [k_ρ(x) − max(ρx, 0)], sup_x [max(x + 2α, 0) − k_ρ(x)] )

for lighting inside a cone of half-angle α (Jensen's inequality below, the cone above). Registers nothing.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ...errors import ValidateError

# x grid for the near-directional bound: 200 001 points include 0 (the kink); |d/dx (k − max(x, 0))| ≤ 2.5 for
# both kernels (|k′| ≤ 1.5), so the grid misses the sup by at most 2.5 h, added to the bound.
BOUND_GRID = 200001
BOUND_LIPSCHITZ = 2.5
RHO_GRID = 9  # ρ ∈ [cos α, 1]; 1 − cos α ≈ 1.5·10⁻⁴ here, so the bound is flat over it


def near_directional_bound(kernel: Callable[[float, np.ndarray], np.ndarray], half_angle: float) -> float:
    """max over ρ ∈ [cos α, 1] of max(sup_x [k_ρ(x) − max(ρx, 0)], sup_x [max(x + 2α, 0) − k_ρ(x)]) (module
    docstring), on a grid of :data:`BOUND_GRID` x values plus the grid's worst miss. ``kernel(ρ, x)`` is the
    technique's output per unit flux at n·m̂ = x for lighting with mean-vector length ρ."""
    if not 0.0 <= half_angle < math.pi / 4:
        raise ValidateError(f"near-directional bound: half-angle {half_angle:g} rad must be in [0, π/4)")
    x = np.linspace(-1.0, 1.0, BOUND_GRID)
    worst = 0.0
    for rho in np.linspace(math.cos(half_angle), 1.0, RHO_GRID):
        k = kernel(float(rho), x)
        over = float(np.max(k - np.maximum(rho * x, 0.0)))
        under = float(np.max(np.maximum(x + 2 * half_angle, 0.0) - k))
        worst = max(worst, over, under)
    return worst + BOUND_LIPSCHITZ * 2.0 / (BOUND_GRID - 1)
