"""Settings of the ``blender`` experiment: which scenes Blender renders, with how many samples and passes.

Costs measured on the 2-core machine (Blender 5.0.1, 64² px): the child process starts and imports bpy in 0.5 s;
a glTF import and scene set-up 0.05–0.2 s; a Cycles frame 0.03–0.06 s at 8–16 spp (sun, point, spot) and 0.1–0.14 s
at 64 spp (the furnace); EEVEE's first frame in a process 18 s (its shaders compiled on llvmpipe). A first FULL at 16
and 64 spp took 23 s cold with another job on the machine (80 Cycles frames: 13.8 s), over the experiment's ~15 s
share of the report budget, so FULL renders 8 spp (punctual) and 16 spp (furnace) × 8 passes; nothing warm
(cached).

EEVEE renders the sun-lit and the point-lit spheres in every run (``eevee_scenes``; the furnace too under
``VALIDATE_EEVEE=1``) at 1 TAA sample. Measured on the idle machine, cold reference cache, Mesa's shader cache warm:
1 and 16 samples gave the same energy to 10⁻⁵ (lambert_directional 1.00015 / 1.00014 of the truth, point_sphere
0.99783 / 0.99783) and 99.91 / 99.91 % and 97.9 / 98.8 % of pixels accepted. The pixel filter is the pixel-centre
ray, so samples only dither shadows, which these scenes do not show. Frames took 1.8–2.3 s at 1 sample and 3.3–11.8 s
at 16. With Mesa's shader cache cold (``MESA_SHADER_CACHE_DISABLE=true``), the first EEVEE frame of a process compiles
its shaders on llvmpipe: 25 s at 16 samples, against 11.8 s warm.

The bpy-built world-lit spheres (:mod:`.world`) run only under ``VALIDATE_EEVEE=1`` too: measured cold on the loaded
2-core machine, their share was the world texture (Mitsuba's envmap evaluated at 2048 × 1024 texels) 5 s, the
sphere and texture set-up in Blender 5–7 s per scene, Cycles' world frames 4–5 s each at 32 spp (8 per probe), the
Mitsuba sphere (256 spp × 8) 2–5 s, and EEVEE's frames 6–38 s each at 4 samples plus its shader compilation on
llvmpipe (18–72 s in a process whose Mesa shader cache is cold): one probe with Cycles and EEVEE's defaults is
≈ 60 s, three times the experiment's share of the cold report. The default run therefore adds nothing.
EEVEE's ``world_eevee_samples``: 1 / 4 / 16 TAA samples gave R&H's mean 3.425 / 3.432 / 3.433 % and max 8.768 /
8.607 / 8.665 % of Φ on grace_probe (docs/experiments/blender.md): 4.
The probe scenes (:mod:`.probes`, ``VALIDATE_EEVEE=1`` only): measured cold on the loaded 2-core machine, the glossy
spheres' Cycles frames 1.6–3.0 s each (8 × 32 spp per roughness), EEVEE's 2–33 s each, the irradiance volume's bake
8 s, the Mitsuba truths (the glTF BSDF, 8 × 256 spp per roughness; the volume scene 8 × 128 spp) 16 s together;
``--quick`` with everything opt-in: 300 s cold (docs/experiments/blender.md).
"""

from __future__ import annotations

import os
from dataclasses import dataclass

EEVEE_SCENES = ("lambert_directional", "point_sphere")  # every run
EEVEE_EXTRA = ("furnace_metal_r0.5",)  # VALIDATE_EEVEE=1


@dataclass(frozen=True)
class Settings:
    scene_set: str = "full"  # the exported set (validate.scenes.manifest.scene_set) and the renders truth's samples
    resolution: int = 64
    kinds: tuple[str, ...] = ("furnace", "directional", "point", "spot")
    scenes: tuple[str, ...] = ()  # only these scenes of the set (empty: every scene of ``kinds``)
    passes: int = 8  # independent Cycles frames (seeds) per scene → per-pixel standard error with passes − 1 dof
    spp: int = 8  # Cycles samples per frame, punctual lights (next-event estimation: the noise is the 0.01 px filter)
    furnace_spp: int = 16  # Cycles samples per frame in the furnace (environment sampling: Monte Carlo noise)
    seed: int = 0
    conversion_spp: int = 4  # the importer's SPEC and RAW modes: one frame each of the conversion scenes
    eevee_scenes: tuple[str, ...] = ()
    eevee_samples: int = 1  # EEVEE's taa_render_samples per frame: 1 and 16 measured equal (module docstring)
    eevee_passes: int = 1  # EEVEE renders deterministically: one frame; its uncertainty is its half-float rounding
    # bpy-built world-lit spheres (experiments/blender/world.py): probes by name, one view each
    world_probes: tuple[str, ...] = ()
    world_view: tuple[float, float] = (15.0, 0.0)  # Mitsuba's sensor (reference.pathtrace): elevation, azimuth
    world_cycles: bool = True
    world_spp: int = 32  # Cycles samples per frame, ``passes`` frames
    world_truth_spp: int = 256  # Mitsuba's sphere (sh9's cross-check settings: 256 spp × 8 passes)
    world_eevee_samples: int = 4  # taa_render_samples: 1 → 4 → 16 moved R&H's mean by < 0.02 % of Φ (docs)
    world_variants: tuple[str, ...] = ()  # EEVEE's world settings (world.VARIANTS); empty: no EEVEE
    world_survey: tuple[str, ...] = ()  # EEVEE alone (these variants) on every other probe of the run: the survey
    soft_shadows: bool = False  # shadows.py: the sphere light and occluder, Cycles and EEVEE (jitter off / on)
    shadow_spp: int = 16  # Cycles samples per frame (``passes`` frames); EEVEE: taa_render_samples
    shadow_sweep: tuple[str, ...] = ()  # shadows.SWEEP: EEVEE's filter radius / overblur beyond the jitter rows
    shadow_disc: bool = True  # with soft_shadows: the disc light too (Cycles; EEVEE jitter off and on)
    # bpy-built probe scenes (experiments/blender/probes.py); empty probe: not rendered
    glossy_probe: str = ""
    glossy_roughness: tuple[float, ...] = (0.1, 0.3, 0.6)
    glossy_variants: tuple[str, ...] = ("world",)  # EEVEE: probes.GLOSSY_VARIANTS
    glossy_passes: int = 8  # Cycles frames (seeds): two halves of 4 for the bias test's cross-fitted z
    glossy_spp: int = 32
    glossy_truth_spp: int = 256  # Mitsuba (the glTF BSDF at metallic 1), ``passes`` passes
    glossy_eevee_samples: int = 4
    volume_probe: str = ""
    volume_variants: tuple[str, ...] = ("world", "volume")  # EEVEE: probes.VOLUME_VARIANTS
    volume_cycles: bool = True  # Cycles as a second truth of the volume scene (bounces as Mitsuba's max_depth)
    volume_spp: int = 32  # Cycles samples per frame, ``passes`` frames
    volume_truth_spp: int = 128
    volume_eevee_samples: int = 4


_ON = os.environ.get("VALIDATE_EEVEE") == "1"
_EXTENDED = os.environ.get("VALIDATE_EXTENDED") == "1"  # the full run's heavy extras (python -m validate --help)
_EEVEE = EEVEE_SCENES + EEVEE_EXTRA if _ON else EEVEE_SCENES
WORLD_PROBES = ("grace_probe", "rnl_probe")  # the paper's probes (R&H 2001: Grace Cathedral, Eucalyptus Grove)
WORLD_VARIANTS = ("default", "no_sun", "no_clamp", "no_sun_no_clamp")
QUICK = Settings(scene_set="quick", passes=8, spp=8, furnace_spp=16, eevee_scenes=_EEVEE,
                 scenes=("furnace_dielectric_r0.5", "furnace_metal_r0.5", "lambert_directional", "point_plane",
                         "point_sphere", "spot_plane"),
                 world_probes=WORLD_PROBES[:1] if _ON else (), world_variants=("default",) if _ON else (),
                 soft_shadows=_ON, shadow_sweep=("filter_0", "filter_3", "threshold_low") if _ON else (),
                 glossy_probe=WORLD_PROBES[0] if _ON else "", volume_probe=WORLD_PROBES[0] if _ON else "")
FULL = Settings(eevee_scenes=_EEVEE, world_probes=WORLD_PROBES if _ON else (),
                world_variants=WORLD_VARIANTS if _ON else (), soft_shadows=_ON,
                world_survey=("default", "no_sun") if _ON and _EXTENDED else (),
                shadow_sweep=("filter_0", "filter_3", "overblur_0", "overblur_40", "threshold_low") if _ON else (),
                glossy_probe=WORLD_PROBES[0] if _ON else "",
                glossy_variants=("world", "sphere_probe", "sphere_probe_far"),
                volume_probe=WORLD_PROBES[0] if _ON else "")
