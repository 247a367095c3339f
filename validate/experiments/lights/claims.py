"""``lights`` claims: every technique's declared thresholds, Lambert's rectangle formula against Mitsuba, the
grid's convergence order, and the linearity of the renders (each with a power check)."""

from __future__ import annotations

from ...local_models import light as family
from ..base import Claim
from ..techniques import technique_claims
from .compute import SLOPE_FROM_N, Measurements
from .settings import NAME

RATE_TOLERANCE = 0.25  # claim 3: |slope + 2| < 0.25 (order 2 vs the endpoint rule's order 1; see claims)


# -- claims ------------------------------------------------------------------------------------------------------
def claims(m: Measurements) -> list[Claim]:
    out: list[Claim] = []
    for tech in family:
        out += technique_claims(NAME, tech, m.measured.get(tech.name, {}), unit="")
    cf = m.data["closed_form"]
    out.append(Claim(
        f"{NAME}.rectangle.closed_form", "Lambert's polygon formula = Mitsuba rectangle emitter over the bare ground "
        "(|pooled z| of Σ(render − formula) over the pixels)", "abs_pooled_z", cf["test"]["bias_bound"],
        abs(cf["test"]["pooled_z"]), 0.0,
        source="Lambert 1760 / Arvo 1994 eq. 2 (exact for a polygon above the horizon); |z| < 4 for one N(0,1) "
               "statistic (CLT over the pixels; two-sided false alarm 6·10⁻⁵)")
        .with_power("the closed form's radiance × 1.02 (a 2 % bias)", abs(cf["power"]["pooled_z"])))
    g = m.data["grid"]
    out.append(Claim(
        f"{NAME}.grid.midpoint_rate", f"n×n grid (midpoint rule) converges as n⁻²: |slope + 2| over n ≥ {SLOPE_FROM_N} "
        "(max relative error vs the closed form, bare ground)", "abs_slope_minus_order", RATE_TOLERANCE,
        abs(g["midpoint_slope"] + 2.0), 0.0,
        source="composite midpoint rule error (h²/24)∫f'' + O(h⁴) for f ∈ C² (Davis & Rabinowitz 1984 §2.2–2.3): "
               "order 2; 0.25 lies between it and the endpoint rule's order 1 with a 3× margin")
        .with_power("the left-endpoint (cell corner) rule", abs(g["corner_slope"] + 2.0)))
    lin = m.data["linearity"]
    out.append(Claim(
        f"{NAME}.sum.mean", "render with point + spot + directional + rectangle = sum of the four single renders "
        "(|pooled z|)", "abs_pooled_z", lin["test"]["bias_bound"], abs(lin["test"]["pooled_z"]), 0.0,
        source="linearity of the rendering equation in the emitted radiance (Kajiya 1986 eq. 1); |z| < 4 for one "
               "N(0,1) statistic (false alarm 6·10⁻⁵)")
        .with_power("the sum of the single renders × 1.02 (a 2 % bias)", abs(lin["power_bias"]["pooled_z"])))
    out.append(Claim(
        f"{NAME}.sum.max", "the same, every pixel: max |z| below the Šidák critical value at α = 0.01", "max_abs_z",
        lin["test"]["critical_z"], lin["test"]["max_abs_z"], 0.0,
        source="Kajiya 1986 eq. 1 (linearity); Šidák 1967 family-wise level 0.01 over the N pixels")
        .with_power("single renders without the rectangle's shape (its shadow on the other lights missed, the bug "
                    "this check caught while it was written)", lin["power_unblocked"]["max_abs_z"]))
    return out
