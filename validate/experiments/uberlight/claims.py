"""``uberlight`` claims: every technique's declared thresholds (the projector claim twinned with its 1° roll
power check) and each barn-door size's fitted soft edge within its computed error budget."""

from __future__ import annotations

from ...local_models import uberlight as family
from ..base import Claim
from ..techniques import technique_claims
from .compute import Measurements
from .settings import NAME


def claims(m: Measurements) -> list[Claim]:
    out: list[Claim] = []
    for tech in family:
        meas = {k: v for k, v in m.measured[tech.name].items() if not k.endswith(".roll")}
        for c in technique_claims(NAME, tech, meas, unit=""):
            out.append(c)
            if c.metric == "projector.max_rel":
                roll = m.measured[tech.name]["projector.max_rel.roll"]
                twin = Claim(c.id + ".roll", c.description + " (power: 1° roll)", c.metric, c.threshold, c.measured,
                             c.uncertainty, source=c.source)
                out.append(twin.with_power(roll.perturbation, roll.perturbed))
    disc = m.data["barndoor"]["smoothstep_vs_disc"]
    for row in m.data["barndoor"]["sizes"]:
        b = row["budget"]
        hole = f"aperture roundness {row['aperture_roundness']:g}" if row["aperture_roundness"] else "rectangular hole"
        c = Claim(f"{NAME}.barndoor.{row['key']}.edge", f"fitted soft edge within the error budget of the "
                  f"barn-door penumbra (disc r = {row['radius']:g} m, depth {row['depth']:g} m, {hole})", "edge_rms",
                  b["total"], row["edge_rms"], row["edge_rms_uncertainty"],
                  source=f"error budget, each term computed: smoothstep vs the straight-edge disc penumbra "
                         f"(segment area), best span {2 * disc['span_over_diameter']:.3f} r, "
                         f"RMS {b['disc_shape']:.4f}; "
                         f"penumbra width ∝ 1 − h/Z varies ±{b['depth_spread']:.3f} over the band → {b['depth']:.4f}; "
                         f"Lambertian cos α missing from the überlight (half its spread over the band) "
                         f"{b['cos']:.4f}; "
                         f"total {b['total']:.4f}")
        out.append(c.with_power("fitted edge widths × 1.5", row["edge_rms_wide"]))
    return out
