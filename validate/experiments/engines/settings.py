"""``engines`` settings: everything that differs between ``--quick`` and the full run."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

from ...local_models.irradiance.engines import worker

NAME = "engines"



@dataclass(frozen=True)
class Settings:
    """How hard the experiment tries (quick and full are two instances, :data:`QUICK`, :data:`FULL`)."""

    normals: int  # spherical-Fibonacci normals for every metric
    cells: int  # reference quadrature cells
    face_size: int  # faces the registered techniques receive (worker.FACE_SIZE)
    sweep_sizes: tuple[int, ...]  # face sizes of the resolution sweep (same normals: the reference is cached)

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


QUICK = Settings(2500, 64, worker.FACE_SIZE, (32, 64, 128))
FULL = Settings(10000, 64, worker.FACE_SIZE, (16, 32, 64, 128, 256))
