"""``blender_eevee``: Blender 5.0's EEVEE rasteriser, headless on Mesa llvmpipe through EGL.

The same scene files and importer as :mod:`.blender_cycles`; ``taa_render_samples`` samples per frame (EEVEE
accumulates jittered rasterisations), film filter 0.01 px. Precision: EEVEE's film accumulates in half floats —
measured: every value of its float32 EXR is a binary16 number (0.55078125 where the truth is 0.551166) — so a reader
adds the half-float rounding (relative 2⁻¹¹, uniform: σ = ulp/√12) to the uncertainty. Cost on the 2-core machine:
the first frame of a process compiles EEVEE's shaders on llvmpipe (measured 18 s), later frames seconds each; so
EEVEE renders only where the settings ask for it (``blender`` experiment: ``eevee_scenes``).
Blender's manual bounds nothing per pixel for EEVEE ("less precise than Cycles"): its results are findings.
"""

from __future__ import annotations

from .blender import BlenderEngine

ENGINE = BlenderEngine(
    name="blender_eevee", product="Blender EEVEE", engine="BLENDER_EEVEE", precision="half",
    supports=("furnace", "directional", "point", "spot"),
    defects={"precision": "half-float film (measured: every output value is a binary16 number)"})

__all__ = ["ENGINE"]
