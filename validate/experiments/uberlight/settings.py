"""``uberlight`` settings: everything that differs between ``--quick`` and the full run
(:data:`QUICK`, :data:`FULL`)."""

from __future__ import annotations

from dataclasses import dataclass, replace

NAME = "uberlight"


@dataclass(frozen=True)
class Settings:
    """Render sizes, projector texture, barn-door luminaires and the sweeps of Fig. 12.3."""

    width: int  # projector renders (pixels)
    height: int
    texture: int  # projector mask texture side
    fov_deg: float
    barndoor_width: int  # barn-door renders (pixels)
    barndoor_height: int
    barndoor_spp: int
    barndoor_passes: int
    depth: float  # barn door: disc-to-aperture depth (m)
    aperture: tuple[float, float]  # barn door: aperture half-extents (m)
    barndoors: tuple[tuple[float, float], ...]  # (disc radius (m), aperture roundness (0: rectangle))
    roundness_sweep: tuple[float, ...]
    edge_sweep: tuple[float, ...]
    seed: int
    d0_over_r: tuple[float, ...]  # Fore June falloff: d₀ in units of the disc radius


QUICK = Settings(width=64, height=48, texture=1024, fov_deg=70.0, barndoor_width=64, barndoor_height=48,
                 barndoor_spp=64, barndoor_passes=8, depth=0.3, aperture=(0.12, 0.09),
                 barndoors=((0.025, 0.0), (0.06, 0.0), (0.025, 0.6)), roundness_sweep=(0.2, 1.0, 4.0),
                 edge_sweep=(0.0, 0.3), seed=1234, d0_over_r=(1.05, 1.5, 2.0, 3.0, 5.0))
FULL = replace(QUICK, width=128, height=96, texture=2048, barndoor_width=128, barndoor_height=96, barndoor_spp=64,
               barndoor_passes=16,
               barndoors=((0.015, 0.0), (0.025, 0.0), (0.04, 0.0), (0.06, 0.0), (0.025, 0.6), (0.025, 1.0),
                          (0.04, 0.6)),
               roundness_sweep=(0.2, 0.5, 1.0, 2.0, 4.0), edge_sweep=(0.0, 0.1, 0.2, 0.3))
