"""The glTF-IBL-Sampler part of ``ibl``, the claims: the thresholds ``khronos_ibl_lambertian`` declares (Ramamoorthi &
Hanrahan 2001: 1 % average, 5 % max of the flux), judged as the worst over the paper's probes, each with its
power check: the same metric with the cube read in the mirrored frame (normals x → −x), which must fail."""

from __future__ import annotations

from ....local_models import irradiance
from ...base import Claim
from ...techniques import Measured, technique_claims
from ..settings import NAME
from .compute import TECH, KhronosMeasurements


def probe_metrics(m: KhronosMeasurements) -> dict[str, Measured]:
    """flux_luminance.mean / .max of the technique, the worst (value + uncertainty) over the probes, each with the
    mirrored-normals value of the same probe as its perturbation."""
    out = {}
    for stat in ("mean", "max"):
        worst = max(m.probes, key=lambda p: m.probes[p][TECH][stat] + m.probes[p][TECH][f"{stat}_uncertainty"])
        row = m.probes[worst]
        out[f"flux_luminance.{stat}"] = Measured(row[TECH][stat], row[TECH][f"{stat}_uncertainty"],
                                                 row["mirrored"][stat], f"{worst}: the normals mirrored x → −x",
                                                 unit="%", stat=stat)
    return out


def khronos_claims(m: KhronosMeasurements) -> list[Claim]:
    if m.missing is not None or not m.probes:
        return []
    scope = f"worst over the paper's probes ({', '.join(m.probes)})"
    return technique_claims(NAME, irradiance[TECH], probe_metrics(m), scope=scope)
