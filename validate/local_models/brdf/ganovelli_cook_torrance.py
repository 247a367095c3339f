"""Cook–Torrance as printed in Ganovelli et al. §6.10.1, eqs. 6.60–6.66 [1] (no listing: the as-printed technique).

The seed's text lost fraction bars, minus signs and exponents in extraction. As extracted:

    6.60  Lr=LpDGF(NL)(NV)        "where F, D, and G at the numerator are its three fundamental components"
    6.61  D=1m2cos4αexptanαm       6.62  G1=2(NH)(NV)(VH)     6.63  G2=(NH)(NL)(VH)
    6.64  G=min{1,G1,G2}           6.66  F=ρ(1ρ)(1NL)5

Readings argued here:

* 6.60: the text says D, G, F are "at the numerator", so the lost bar makes a fraction
  Lr = Lp D G F / ((N·L)(N·V)) — the product reading Lp D G F (N·L)(N·V) contradicts that sentence.
  The printed formula has no factor N·L for the incident light's projected area; Cook & Torrance [2]
  multiply their R_s by E_i = I_i (N·L) dω_i. Both are implemented: ``literal`` (no N·L, as printed)
  and ``with_nl`` (× N·L, the reading that treats Lp as the light's radiance times its cosine).
* 6.61: D = exp(−(tan α/m)²)/(m² cos⁴α) — Beckmann without 1/π, Cook & Torrance's own form [2, eq. 7].
* 6.62/6.63: G1 = 2(N·H)(N·V)/(V·H) and, as printed, G2 = (N·H)(N·L)/(V·H) *without* the 2 of 6.62
  (Blinn's and Cook & Torrance's shadowing term has it [2, eq. 5]). ``g2_factor`` 1 (printed) or 2.
* 6.66: F = ρ + (1 − ρ)(1 − N·L)⁵, Schlick's form with the printed argument N·L (Schlick [3] uses the
  angle to the microfacet normal, V·H), ρ = F₀ = ((η − 1)² + k²)/((η + 1)² + k²).

Units: Lp is the light's "amount" as in Ganovelli's Lambert term L = L_incident k_D (N·L) (eq. 6.5), i.e.
E⊥/π for a light of perpendicular irradiance E⊥ ("π folded into the light",
:mod:`validate.local_models.brdf.classic_brdfs`). The brdf family's output L_o/E⊥ is then S/π with S the
printed expression divided by Lp.

What the existing ``classic_brdfs.cook_torrance_printed`` differs in: it puts the 2 of 6.62 into G2 as
well and multiplies 6.60 by N·L — the reading (``with_nl``, ``g2_factor`` 2), neither of which the seed
prints. Its "4.04× Mitsuba's energy" is that reading; the seed's readings give other factors (the
``listings`` experiment's table).

References
  [1] F. Ganovelli, M. Corsini, S. Pattanaik, M. Di Benedetto, *Introduction to Computer Graphics: A
      Practical Learning Approach*, CRC 2014, §6.10.1 eq. 6.60–6.66.
  [2] R. L. Cook, K. E. Torrance, "A reflectance model for computer graphics", ACM TOG 1(1), 1982.
  [3] C. Schlick, "An inexpensive BRDF model for physically-based rendering", CGF 13(3), 1994.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..brdf.common import (
    RGB,
    GeometryDr,
    beckmann_d_dr,
    fresnel_f0_rgb,
    fresnel_schlick_dr,
    opaque_rgb,
    param,
    rgb_param,
)
from ..families import brdf

READINGS: dict[str, tuple[bool, float]] = {  # name -> (multiply by N·L, factor in G2)
    "literal": (False, 1.0), "literal_g2x2": (False, 2.0), "with_nl": (True, 1.0), "with_nl_g2x2": (True, 2.0)}


def ganovelli_specular(params: Mapping[str, Any], g: GeometryDr, with_nl: bool = False,
                       g2_factor: float = 1.0) -> RGB:
    """S/π = F(N·L) D G / (π (N·L)(N·V)) [× N·L] with the printed D, G1, G2 (module docstring), on drjit arrays
    (:class:`~validate.local_models.brdf.common.GeometryDr`, the family's dtype)."""
    import drjit as dr

    who = "cook_torrance_ganovelli"
    m = float(param(params, "alpha", who))
    f = fresnel_schlick_dr(g.cl, fresnel_f0_rgb(param(params, "eta", who), param(params, "k", who)))
    d = beckmann_d_dr(g.ch, m, normalised=False)
    vh = dr.maximum(g.vh, 1e-12)
    gg = dr.minimum(1.0, dr.minimum(2.0 * g.ch * g.cv / vh, g2_factor * g.ch * g.cl / vh))
    s = d * gg / dr.maximum(g.cl * g.cv, 1e-12)
    return f * ((s * g.cl if with_nl else s) / np.pi)


def reading(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray,
            name: str) -> np.ndarray:
    """One reading of :data:`READINGS` plus the Lambert term ρ/π (N·L); zero below either horizon."""
    g = GeometryDr(normals, lights, views)
    with_nl, g2 = READINGS[name]
    diffuse = opaque_rgb(rgb_param(params, "albedo", "cook_torrance_ganovelli") / np.pi) * g.cl
    return g.finish(diffuse + ganovelli_specular(params, g, with_nl, g2))


@brdf.register("cook_torrance_ganovelli", "Cook–Torrance exactly as extracted from Ganovelli eq. 6.60–6.66: "
               "D G F/((n·l)(n·v)), no n·l factor, G2 without the 2, Schlick F(n·l), D without π",
               seed="003 Ganovelli §6.10.1, eq. 6.60–6.66")
def cook_torrance_ganovelli(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                            views: np.ndarray) -> np.ndarray:
    """The ``literal`` reading (module docstring)."""
    return reading(params, normals, lights, views, "literal")


@brdf.register("cook_torrance_ganovelli_nl", "Ganovelli eq. 6.60 read with the incident cosine: D G F/((n·l)(n·v)) "
               "× n·l, G2 as printed (no 2)", seed="003 Ganovelli §6.10.1, eq. 6.60–6.66")
def cook_torrance_ganovelli_nl(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                               views: np.ndarray) -> np.ndarray:
    """The ``with_nl`` reading (module docstring)."""
    return reading(params, normals, lights, views, "with_nl")


__all__ = ["READINGS", "cook_torrance_ganovelli", "cook_torrance_ganovelli_nl", "ganovelli_specular", "reading"]
