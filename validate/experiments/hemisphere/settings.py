"""``hemisphere`` settings: everything that differs between ``--quick`` and the full run."""

from __future__ import annotations

from dataclasses import dataclass

from ...scenes import area_lights

NAME = "hemisphere"


@dataclass(frozen=True)
class Settings:
    """Tilt grid, reference quadrature and irradiance-meter effort (quick and full: :data:`QUICK`, :data:`FULL`)."""

    beta_step_deg: float  # tilt step of the quadrature comparison (two-tone and sunsky)
    azimuths: int  # azimuths per tilt on the skies
    cells: int  # reference quadrature cells (validate.reference.irradiance)
    meter_betas_deg: tuple[float, ...]  # tilts measured by Mitsuba's irradiance meter
    meter_passes: int  # independent meter passes (Student t over passes)
    meter_spp: int  # samples per pixel per pass
    meter_film: int = area_lights.FILM_SIZE  # meter film side (pixels)


QUICK = Settings(beta_step_deg=10.0, azimuths=8, cells=64, meter_betas_deg=(0, 30, 45, 60, 90, 120, 135, 150, 180),
                 meter_passes=8, meter_spp=16)
FULL = Settings(beta_step_deg=2.5, azimuths=24, cells=128, meter_betas_deg=(*range(0, 181, 15), 45, 135),
                meter_passes=16, meter_spp=32)
