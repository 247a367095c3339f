"""Per-pixel budgets of ``renders`` that its parts share (the main scenes and :mod:`.cdf`): here, below both, so
neither imports the other."""

from __future__ import annotations

from ...local_models import render as engines

# Furnace budget per pixel (radiance units, truth 1): three's PMREM / Babylon's prefiltered cube store half
# floats (2⁻¹¹ relative per texel) and both engines add a diffuse and a specular lookup → 2·2⁻¹¹; SwiftShader
# trig 2e-4 absolute (cube-face directions) → b = 2·2⁻¹¹ + 2e-4 ≈ 1.2e-3.
FURNACE_BUDGET = 2 * engines.HALF_FLOAT_RTOL + engines.SWIFTSHADER_TRIG_ATOL
# (b) probe on metal spheres: the furnace budget per unit radiance (2 half-float lookups + SwiftShader trig), relative
PROBE_BUDGET_REL = FURNACE_BUDGET
