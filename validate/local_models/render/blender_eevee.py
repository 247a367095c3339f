"""``blender_eevee``: Blender 5.0's EEVEE rasteriser, headless on Mesa llvmpipe through EGL.

The same scene files and importer as :mod:`.blender_cycles`; ``taa_render_samples`` samples per frame (EEVEE
accumulates jittered rasterisations), film filter 0.01 px. Precision: EEVEE's film accumulates in half floats —
measured: every value of its float32 EXR is a binary16 number (0.55078125 where the truth is 0.551166) — so a reader
adds the half-float rounding (relative 2⁻¹¹, uniform: σ = ulp/√12) to the uncertainty. Cost on the 2-core machine:
the first frame of a process compiles EEVEE's shaders on llvmpipe (25 s at 16 samples with Mesa's shader cache
cold; 1.8 s at 1 sample with it warm), later frames seconds each; so EEVEE renders only where the settings ask for
it (``blender`` experiment: ``eevee_scenes``, two scenes at 1 sample in every run).
Blender's manual bounds nothing per pixel for EEVEE ("less precise than Cycles"): its results are findings.
Beyond the .glb scenes the ``blender`` experiment renders through bpy a Lambertian sphere lit only by a probe (the
world light probe: L1 spherical harmonics plus the sun extracted above ``World.sun_threshold``) and a sphere light
with an occluder (virtual shadow maps, ``Light.use_shadow_jitter`` off and on, ``shadow_filter_radius``,
``shadow_jitter_overblur``), white GGX spheres over roughness (its world and sphere-probe reflections) and a
baked irradiance volume (``lightprobe_cache_bake`` works headless), under ``VALIDATE_EEVEE=1``.
"""

from __future__ import annotations

from .blender import BlenderEngine

ENGINE = BlenderEngine(
    name="blender_eevee", product="Blender EEVEE", engine="BLENDER_EEVEE", precision="half",
    supports=("furnace", "directional", "point", "spot"),
    defects={"precision": "half-float film (measured: every output value is a binary16 number)",
             "world lighting": "the world probe's diffuse lighting is L1 SH: 3.4 % / 8.6 % of Φ (mean / max) on "
                               "grace_probe, beyond R&H's 1 % / 5 % for SH9 on all 30 shared probes; its sun "
                               "extraction threshold is absolute, so the error depends on the probe's exposure "
                               "(blender experiment)",
             "light threshold": "the default light_threshold 0.01 fades point, spot and area lights by distance: "
                                "the lit plane 0.974 (a 0.15 m sphere light) and 0.631 (a disc) of the path tracers, "
                                "point_sphere 0.998; whole at 10⁻⁴ (blender experiment, soft shadows)",
             "glossy reflections": "a white GGX sphere under grace_probe: +13 % energy and 87 % mean per-pixel "
                                   "error at roughness 0.1, 39 % / 28 % at 0.3 / 0.6 (blender experiment, probes)"})

__all__ = ["ENGINE"]
