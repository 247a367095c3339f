"""``engines`` settings: everything that differs between ``--quick`` and the full run."""

from __future__ import annotations

from dataclasses import dataclass

from ...local_models.irradiance.engines import worker

NAME = "engines"



@dataclass(frozen=True)
class Settings:
    """How hard the experiment tries (quick and full are two instances, :data:`QUICK`, :data:`FULL`)."""

    normals: int  # spherical-Fibonacci normals for every metric
    cells: int  # reference quadrature cells
    face_size: int  # faces the registered techniques receive (worker.FACE_SIZE)
    sweep_sizes: tuple[int, ...]  # face sizes of the resolution sweep (same normals: the reference is cached)
    # engines.babylon_sh.own_faces.clamp_lowers_error on the full probe set only: in quick the one environment whose
    # own faces exceed 4096 (sunsky_30deg) exceeds it on the suite's faces too, where the clamp also lowers the error
    # (measured: own +62.8 %, suite +0.17 ± 0.025 %), so the power check (the suite's faces) cannot fail there; on
    # the full set it is −15.3 % (rooitou_park_1k). Quick still reports both face sources in the table.
    clamp_claim: bool = True


QUICK = Settings(2500, 64, worker.FACE_SIZE, (32, 64, 128), clamp_claim=False)
FULL = Settings(10000, 64, worker.FACE_SIZE, (16, 32, 64, 128, 256))
