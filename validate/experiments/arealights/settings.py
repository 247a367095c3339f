"""``arealights`` settings: everything that differs between ``--quick`` and the full run, and the fixed
effort both share (meter film, projection nodes, the α-range grid, the two Mitsuba decisions)."""

from __future__ import annotations

from dataclasses import dataclass, field

from .specular.settings import SpecularSettings

NAME = "arealights"
SCALE_ERROR = 0.02  # the reference-bias power check of the meter test


@dataclass(frozen=True)
class MeterRun:
    """One Mitsuba irradiance-meter decision: normals at ``thetas_deg``, ``passes`` × ``spp`` samples per pixel.

    The default (2.1 M samples per normal at 7 normals): at α = 25° the bound z*·s is ≤ 0.45 % of Φ against a
    0.66 % margin; at 19.5° the zero-hit bound at θ = 180° is 0.006 % of Φ against a 0.047 % margin."""

    thetas_deg: tuple[float, ...] = tuple(range(0, 181, 30))
    passes: int = 16
    spp: int = 128


@dataclass(frozen=True)
class Settings:
    """Quick and full are two instances (:data:`QUICK`, :data:`FULL`); ``specular`` is reported with its
    measurements (``experiments.arealights.specular.settings``), the rest as ``settings``."""

    alphas_deg: tuple[float, ...]  # sphere/disc half-angles of the α sweep
    theta_step_deg: float  # receiver-normal tilt step of every closed-form comparison
    elevation_step_deg: float  # light elevation step of the SH-vs-elevation sweep
    distance_ratios: int  # d/r samples of the point-light sweep (geometric, 1.1…100)
    meter_thetas_deg: tuple[float, ...]  # normals of the reference checks (irradiance meter)
    meter_passes: int
    meter_spp: int
    specular: SpecularSettings
    meter_film: int = 32
    projection_nodes: int = 48  # numerical cap projection (doubled for its uncertainty)
    scale_error: float = SCALE_ERROR
    range_step_deg: float = 0.5  # the fine α grid of the 5 % range (closed form)
    range_deg: tuple[float, float] = (1.0, 60.0)
    decide: MeterRun = field(default_factory=MeterRun)


QUICK = Settings(alphas_deg=(1, 2, 5, 10, 15, 20, 25, 30, 45, 60), theta_step_deg=0.25, elevation_step_deg=5.0,
                 distance_ratios=24, meter_thetas_deg=(0, 30, 60, 75, 90, 105, 120, 180), meter_passes=16,
                 meter_spp=32, specular=SpecularSettings(alphas=(0.1, 0.3, 0.6), sigmas_deg=(5.0, 15.0, 30.0),
                                                         nodes=64, render_pixels=64, render_spp=64))
FULL = Settings(alphas_deg=(1, 2, 3, 4, 5, 6, 7.5, 10, 12.5, 15, 17.5, 20, 22.5, 25, 27.5, 30, 35, 40, 45, 50, 55, 60),
                theta_step_deg=0.05, elevation_step_deg=1.0, distance_ratios=80,
                meter_thetas_deg=(0, 15, 30, 45, 55, 60, 65, 70, 75, 80, 85, 90, 95, 100, 105, 110, 115, 120, 125,
                                  135, 150, 180), meter_passes=16, meter_spp=32,
                specular=SpecularSettings(alphas=(0.05, 0.1, 0.2, 0.3, 0.45, 0.6, 0.8),
                                          sigmas_deg=(2.5, 5.0, 10.0, 15.0, 20.0, 30.0), nodes=160, render_pixels=128,
                                          render_spp=128))
