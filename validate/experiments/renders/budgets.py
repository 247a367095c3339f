"""Per-pixel budgets of ``renders`` that its parts share (the main scenes and :mod:`.cdf`): here, below both, so
neither imports the other."""

from __future__ import annotations

from ...local_models.render.hosted import HALF_FLOAT_RTOL, SWIFTSHADER_TRIG_ATOL

# Furnace budget per pixel (radiance units, truth 1): three's PMREM / Babylon's prefiltered cube store half
# floats (2⁻¹¹ relative per texel) and both engines add a diffuse and a specular lookup → 2·2⁻¹¹; SwiftShader
# trig 2e-4 absolute (cube-face directions) → b = 2·2⁻¹¹ + 2e-4 ≈ 1.2e-3.
FURNACE_BUDGET = 2 * HALF_FLOAT_RTOL + SWIFTSHADER_TRIG_ATOL
# (b) probe on metal spheres: the furnace budget per unit radiance (2 half-float lookups + SwiftShader trig), relative
PROBE_BUDGET_REL = FURNACE_BUDGET
# Directional budget, a measured margin: the engines shade a 512×256 tessellated sphere; three's largest
# |engine − Mitsuba| over the 2336 interior pixels of the 64² image was 1.76e-3 = 0.18 % of the peak ρE/π =
# 0.955 (rows 9–46, scattered, not at the outline); b = 0.25 % of the peak radiance ρE/π. Scene kinds judged with
# it: kinds.peak_budget.
DIRECT_BUDGET_OF_PEAK = 2.5e-3
