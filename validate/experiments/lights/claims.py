"""``lights`` claims: every technique's declared thresholds, Lambert's rectangle formula against Mitsuba, the
grid's convergence order, the linearity of the renders, and where a point light starts to stand in for an area
light (each with a power check)."""

from __future__ import annotations

from ...local_models import light as family
from ...scenes import light_scenes as ls
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
    return out + standin_claims(m)


def standin_claims(m: Measurements) -> list[Claim]:
    """Per area light: the reported 1 % crossing (Brent on the closed forms) agrees within its stated tolerance with
    the same crossing located independently (bisection on a float64 Gauss–Legendre reference); power: the first
    grid node past the crossing, the figure the finding reported before."""
    st, out = m.data["standin"], []
    for kind in ls.AREA_KINDS:
        r, ind, c = st[kind]["ratio_within_1pct"], st[kind]["independent"], st[kind]["crossing"]
        if r is None or ind["root"] is None:
            continue
        out.append(Claim(
            f"{NAME}.standin.{kind}.crossing", f"the d/size beyond which one point light stands in for the {kind} "
            "within 1 % (Brent on the closed form) = the same crossing bisected on an independent quadrature "
            "reference (|difference| in d/size)", "abs_ratio_difference", st["xtol"], abs(r - ind["root"]), 0.0,
            source=f"the figure's stated tolerance xtol = {st['xtol']:g} (Brent 1973 ch. 4: within xtol of a root); "
                   f"the bisection's half-width {ind['xtol'] / 2:g} and the references' disagreement at the root "
                   f"({ind['reference_disagreement']:.1e} of E, over the error's slope {c['slope']:.2g} per unit "
                   f"d/size: {ind['reference_disagreement'] / abs(c['slope']):.1e}) fit inside it")
            .with_power("the first grid node past the crossing (the figure reported before)", abs(c["grid_node"]
                                                                                              - ind["root"])))
    return out
