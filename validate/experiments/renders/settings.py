"""Settings of the ``renders`` experiment: image size, reference samples, engines."""

from __future__ import annotations

import os
from dataclasses import dataclass

# ``VALIDATE_EXTENDED=1``: the full run's Khronos Sample Viewer and loader parts (g) as wide as they go — the viewer on
# the hemisphere light with its IBL sampler at cube 64², LUT 128² (~75 s of SwiftShader: the furnace 36 s, the
# hemisphere 39 s, measured), Babylon.js through its loader (its page and first prefilter ~80 s) and every exported
# scene, the authored glTF scenes with truths traced from the files (the room alone ~90 s cold at the full set's
# samples). Without it a full run gives both parts the quick run's scenes and sizes (their references are the full
# run's, from the cache), which keeps a cold ``make report`` within its budget.
EXTENDED = os.environ.get("VALIDATE_EXTENDED") == "1"


@dataclass(frozen=True)
class Settings:
    resolution: int = 64  # 64² pixels: a Mitsuba reference costs seconds on 2 cores
    spp: int = 32  # samples per pixel per pass (pixel-centre rays)
    passes: int = 8  # independent passes → per-pixel standard error with 7 dof
    seed: int = 0
    # registered engines (validate.local_models.render.registry), in this order; Filament renders the punctual-light
    # kinds only (its engine's ``lacks`` gives the reason for the others). A registered engine FULL does not name
    # renders in every run as well (kinds.run_engines)
    engines: tuple[str, ...] = ("three", "babylon", "filament")
    furnace_roughness: tuple[float, ...] = (0.25, 0.5, 1.0)
    sun_lux: float = 3.0
    env_spp: int = 1024  # hemisphere (an environment, Monte Carlo noise): relative standard error ≈ 0.5 % per pixel
    # (b) the probe (ict_uffizi_256x128.hdr of --probes, resampled to 128 × 64) on white metal spheres over roughness,
    # and a Lambertian sphere; probe_spp per pass (Monte Carlo noise from the environment)
    probe_roughness: tuple[float, ...] = (0.1, 0.2, 0.25, 0.3, 0.5, 0.75, 1.0)
    probe_resolution: int = 64
    probe_spp: int = 256
    rect_resolution: int = 64  # (d) rectangular area light on the plane and the sphere
    # (b) glTF materials under the probe (probe_resolution, probe_spp): metalness × roughness against (i) glTF as
    # specified and (ii) the multiscatter microsurface (white metal; at metalness 0.5 the linear mix of glTF)
    material_metallic: tuple[float, ...] = (0.0, 0.5, 1.0)
    material_roughness: tuple[float, ...] = (0.25, 0.5, 1.0)
    bsdf_check_samples: int = 200_000  # χ² histogram samples and albedo samples per case of the glTF BSDF checks
    # (e) shadows (validate.scenes.render_shadow_scenes): resolution, reference samples per pass, and which engines'
    # shadow types (each engine's ``shadow_types``) — () renders none
    shadow_resolution: int = 64
    shadow_spp: int = 64
    shadow_engines: tuple[str, ...] = ("three", "babylon", "filament")
    # (b) Babylon's CDF irradiance (validate.scenes.render_cdf_scenes, Babylon PR 16247): Babylon's cube sizes, the
    # image size; Babylon only, so full runs only (quick has no Babylon: its first call here — page, shaders, first
    # CDF cube — took 42–45 s on the shared 2 cores, measured)
    cdf_sizes: tuple[int, ...] = (64, 128, 256)
    cdf_resolution: int = 32
    # the Khronos glTF Sample Viewer (part .khronos): the exported scenes it renders and its IBL sampler's sizes
    # (khronos_viewer.IBL_QUICK: cube 16², LUT 64², for constant environments only; "suite": cube 64², LUT 128²)
    khronos_scenes: tuple[str, ...] = ("furnace_dielectric_r0.25", "furnace_dielectric_r0.5", "furnace_dielectric_r1",
                                       "furnace_metal_r0.25", "furnace_metal_r0.5", "furnace_metal_r1",
                                       "lambert_directional", "point_plane", "point_sphere", "spot_plane",
                                       "hemisphere_sphere")
    khronos_ibl: str = "suite"


# quick: three.js and Filament (Babylon's page load and first prefilter cost ~80 s on 2 cores; Filament's page and
# its four punctual scenes ~17 s at 64², measured); full: all three engines. Quick's shadows stay three.js only:
# Filament's two shadow scenes at 32² add 6.3 s of page time (4.9 s the first, its shadow-receiver shaders
# compiled; 1.4 s the second; measured on the shared 2 cores) and at 32² its directional penumbra is under a pixel
# wide (W = 0)
QUICK = Settings(spp=16, passes=8, engines=("three", "filament"), env_spp=256, probe_roughness=(0.25, 0.5),
                 probe_resolution=32, probe_spp=128, rect_resolution=32, material_roughness=(0.5,),
                 bsdf_check_samples=100_000, shadow_resolution=32, shadow_spp=16, shadow_engines=("three",),
                 cdf_sizes=(), khronos_scenes=Settings.khronos_scenes[:-1], khronos_ibl="quick")
FULL = Settings(spp=128, passes=8) if EXTENDED else Settings(
    spp=128, passes=8, khronos_scenes=Settings.khronos_scenes[:-1], khronos_ibl="quick")
