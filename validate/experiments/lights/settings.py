"""``lights`` settings: everything that differs between ``--quick`` and the full run (:data:`QUICK`, :data:`FULL`)."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

NAME = "lights"


@dataclass(frozen=True)
class Settings:
    """Render sizes and Monte Carlo effort per scene kind, the n×n grid sweep and the stand-in sweep."""

    width: int
    height: int
    delta_spp: int  # point, spot, directional renders
    delta_passes: int
    area_spp: int  # rectangle, disk, sphere, lamp renders
    area_passes: int
    sum_spp: int  # the four-light render (linearity)
    sum_passes: int
    ground_spp: int  # the bare-ground rectangle (closed form)
    ground_passes: int
    technique_grid: int  # n of the area techniques' n×n grid
    grid_ns: tuple[int, ...]  # the grid convergence sweep
    grid_reference: int  # n of the self-convergence reference grid
    visibility_side: int  # stratified shadow rays per side for the visible fraction
    range: float  # windowed falloffs' range (m)
    seed: int
    ratios: tuple[float, ...]  # stand-in sweep: distance / light size
    distances: tuple[float, ...]  # attenuation curves (m)
    polar_deg: tuple[float, ...]  # stand-in receivers: polar angles from the light's normal, in one plane
    tilt_deg: tuple[float, ...]  # and normals tilted in that plane from the direction to the light, both ways
    # The stand-in crossing's tolerance in d/size (Brent's xtol): the stand-ins evaluate in float32, whose rounding
    # (~3·10⁻⁷ of E) moves the root by ~1·10⁻⁴ (the error's slope there is ~3·10⁻³ per unit d/size; measured:
    # Brent on the closed forms and a bisection on the float64 quadrature differ by up to 1.1·10⁻⁴), so 10⁻³.
    standin_xtol: float


QUICK = Settings(width=64, height=48, delta_spp=1, delta_passes=2, area_spp=16, area_passes=8, sum_spp=64, sum_passes=8,
                 ground_spp=64, ground_passes=8, technique_grid=8, grid_ns=(1, 2, 3, 4, 6, 8, 12, 16),
                 grid_reference=24, visibility_side=12, range=10.0, seed=1234,
                 ratios=tuple(np.geomspace(0.75, 40.0, 24).tolist()),
                 distances=tuple(np.geomspace(0.25, 20.0, 40).tolist()), polar_deg=(0.0, 30.0, 60.0),
                 tilt_deg=(-60.0, -30.0, 0.0, 30.0, 60.0), standin_xtol=1e-3)
FULL = replace(QUICK, width=160, height=120, area_spp=64, area_passes=16, sum_spp=256, sum_passes=16, ground_spp=256,
               ground_passes=16, grid_ns=(1, 2, 3, 4, 5, 6, 8, 10, 12, 16), grid_reference=32, visibility_side=16,
               ratios=tuple(np.geomspace(0.75, 40.0, 48).tolist()),
               distances=tuple(np.geomspace(0.25, 20.0, 80).tolist()), polar_deg=(0.0, 15.0, 30.0, 45.0, 60.0),
               tilt_deg=(-60.0, -45.0, -30.0, -15.0, 0.0, 15.0, 30.0, 45.0, 60.0))
