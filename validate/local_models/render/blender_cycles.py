"""``blender_cycles``: Blender 5.0's Cycles path tracer on the CPU, a second truth beside Mitsuba.

Cycles renders the exported ``.glb`` scenes through Blender's own glTF importer (lights converted in mode
``COMPAT``: :mod:`.blender`), with the worker's settings (``blender_worker.py``): a box pixel filter of 0.01 px (the
pixel-centre ray the suite's truth traces), no adaptive sampling, no denoiser, light threshold 0, no clamping.
Frames are float32: Cycles accumulates in float, so the output adds no rounding to the uncertainty; the Monte Carlo
noise is measured from independent seeds, as the suite's Mitsuba passes.

Supports, as Mitsuba describes them: Lambertian surfaces under a sun, a point and a spot light (the spot with
Blender's own cone: :func:`blender_spot`), the white furnace (any material: Principled BSDF). Differs by design:
Principled's metal is multiple-scattering GGX (Blender 4.0 release notes, "Principled BSDF": energy-conserving
multiscatter GGX) where glTF's is single-scattering, so the furnace's metal spheres are an energy ratio, not a match.
"""

from __future__ import annotations

from .blender import BlenderEngine

ENGINE = BlenderEngine(
    name="blender_cycles", product="Blender Cycles", engine="CYCLES", precision="float",
    supports=("furnace", "directional", "point", "spot"),
    defects={"spot cone": "the importer maps KHR's quadratic cone falloff to Blender's smoothstep blend "
                          "(spot_blend = 1 − inner/outer): a different profile between the cones, by design",
             "metal": "Principled's multiple-scattering GGX is not glTF's single-scattering metal (by design)"})

__all__ = ["ENGINE"]
