"""``shadows`` settings: everything that differs between ``--quick`` and the full run (:data:`QUICK`, :data:`FULL`)."""

from __future__ import annotations

from dataclasses import dataclass

from ...scenes import shadow_scenes as ss

NAME = "shadows"



@dataclass(frozen=True)
class Settings:
    """Quick and full runs differ only in these numbers."""

    width: int
    height: int
    spp: int
    passes: int
    visibility_side: int
    radii: tuple[float, ...]
    resolutions: tuple[int, ...]
    default_resolution: int  # the comparison tables and images
    bias_resolution: int
    kernel_resolution: int  # PCF kernel sweep and PCSS against the best fixed kernel
    kernel_radii: tuple[float, ...]
    bias_scales: tuple[float, ...]
    kernels: tuple[int, ...]
    rate_grid: int  # ground receivers per side for the hard map's convergence rate
    flip_radii: tuple[float, ...]  # radii whose images get HDR-FLIP (≈ 0.7 s per image pair)


QUICK = Settings(96, 72, 64, 8, 12, (ss.NEAR_POINT_RADIUS, 0.25, 1.0), (256, 1024, 4096), 1024, 1024, 256, (1.0,),
                 (0.0, 0.125, 0.25, 0.5, 1.0, 2.0, 8.0, 32.0), (1, 3, 5, 9, 13, 17, 25, 33), 256, (1.0,))
FULL = Settings(160, 120, 64, 16, 16, tuple(ss.LIGHT_RADII), (256, 512, 1024, 2048, 4096), 2048, 1024, 512,
                (0.25, 1.0), (0.0, 0.0625, 0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0),
                (1, 2, 3, 5, 7, 9, 13, 17, 25, 33, 49), 512, tuple(ss.LIGHT_RADII))
