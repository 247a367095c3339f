"""``sh9`` settings: everything that differs between ``--quick`` and the full run."""

from __future__ import annotations

from dataclasses import dataclass

NAME = "sh9"


@dataclass(frozen=True)
class Settings:
    """How hard the experiment tries (quick and full are two instances, :data:`QUICK`, :data:`FULL`)."""

    normals: int  # spherical-Fibonacci normals for every metric
    cells: int  # reference quadrature cells (validate.reference.irradiance)
    grid: tuple[int, int]  # lat-long grid of normals for the heat map
    sphere_px: int  # sphere images
    pathtrace: tuple[str, ...]  # environments of the path-traced cross-check (those present)
    pathtrace_px: int = 48
    spp: int = 256
    passes: int = 8
    max_order: int = 8


# quick: one cross-check, the environment with a closed form and the sharpest light (two_tone,
# disc_on_sky and a real probe are also tested in tests/reference/test_pathtrace.py)
QUICK = Settings(2500, 64, (24, 48), 48, ("near_directional",))
FULL = Settings(10000, 64, (48, 96), 96, ("two_tone", "disc_on_sky", "near_directional", "sunsky_30deg", "grace_probe"))
