"""``ibl`` settings: everything that differs between ``--quick`` and the full run (:data:`QUICK`, :data:`FULL`)."""

from __future__ import annotations

import os
from dataclasses import dataclass

# ``VALIDATE_EXTENDED=1``: the glTF-IBL-Sampler's whole sweep in a full run (sampleCount 64…16384, faces 16²…128²
# and the tool's default, lodBias −2…1, 4096 normals: ~160 s on lavapipe, the default face alone 64 s a probe);
# without it a full run sweeps as quick does (one point besides the technique's), within the cold report's budget
EXTENDED = os.environ.get("VALIDATE_EXTENDED") == "1"

NAME = "ibl"



@dataclass(frozen=True)
class Settings:
    """How hard the experiment tries. Quick and full differ only in these numbers."""

    quick: bool
    sweep_envs: tuple[str, ...]  # environments of the diffuse-map sweep (the first is rendered)
    env_scale: int  # procedural environments at 1/env_scale of their full resolution
    faces: tuple[int, ...]  # cube-map faces of the sweep (must hold 8 and 32)
    heights: tuple[int, ...]  # lat-long heights of the sweep
    test_normals: int  # quasi-uniform normals of the sweep
    claim_normals: int  # randomly rotated normals of the claim
    size: int  # rendered image side (pixels)
    spp: int
    passes: int
    ni_size: int  # image side of the normal-incidence crop renders (only θ_v ≤ 5° pixels are traced)
    ni_spp: int
    exponents: tuple[float, ...]  # Phong exponents rendered (must hold BLEND_EXPONENT)
    alphas: tuple[float, ...]  # GGX α rendered
    sh_face: int  # face of the SH-vs-convolution comparison
    ao_samples: int
    interreflection_depth: int
    chi2_exponents: tuple[float, ...]  # χ² test of the Phong sampling
    chi2_cos_views: tuple[float, ...]
    chi2_samples: int
    furnace_cos_views: tuple[float, ...]  # white furnace through the path integrator
    furnace_spp: int  # paths per view per ray (64 rays per view)
    dfg_cells: tuple[tuple[int, int], ...]  # (μ index, α index) DFG-table cell centres of the constant-env claim
    heatmaps_per_section: int | None  # quick: fewer heat maps (matplotlib is the slow part)
    flip: bool  # HDR-FLIP beside every comparison (0.1–0.4 s per image whatever its size: full runs only)
    # the glTF-IBL-Sampler part (.khronos): normals per paper probe, and its sweep, one knob at a time around the
    # technique's options (1024 samples, faces 64², lodBias 0; each point one run of the tool, ~1–3 s on lavapipe;
    # quick: one point besides the technique's, lodBias −1)
    khronos_normals: int = 1024
    khronos_samples: tuple[int, ...] = (1024,)
    khronos_faces: tuple[int, ...] = (64,)  # 0: the tool's own default (the panorama's width / 4)
    khronos_lod_biases: tuple[float, ...] = (-1.0, 0.0)


QUICK = Settings(True, ("disc_on_sky", "two_tone"), 2, (4, 8, 16, 32, 64), (4, 8, 16, 32, 64), 512, 512,
                      32, 64, 4, 64, 4096, (10.0, 100.0), (0.3,), 16, 64, 4,
                      (1.0, 10.0, 100.0), (1.0, 0.5), 1_000_000, (1.0, 0.7, 0.3), 1 << 12,
                      ((31, 3), (22, 9), (9, 19)), 1, False)
FULL = Settings(False, ("disc_on_sky", "two_tone", "sunsky_30deg", "near_directional"), 1,
                     (4, 8, 16, 32, 64, 128, 256), (4, 8, 16, 32, 64, 128, 256), 4096, 2048,
                     96, 512, 8, 128, 8192, (1.0, 10.0, 100.0, 1000.0), (0.1, 0.3, 0.6), 32, 1024, 8,
                     (1.0, 10.0, 100.0), (1.0, 0.7, 0.3), 2_000_000, (1.0, 0.85, 0.7, 0.5, 0.3), 1 << 14,
                     ((31, 3), (22, 3), (9, 3), (31, 9), (22, 9), (9, 9), (31, 19), (22, 19), (9, 19)), None, True,
                     **(dict(khronos_normals=4096, khronos_samples=(64, 256, 1024, 4096, 16384),
                             khronos_faces=(16, 32, 64, 128, 0), khronos_lod_biases=(-2.0, -1.0, -0.5, 0.0, 0.5, 1.0))
                        if EXTENDED else {}))

