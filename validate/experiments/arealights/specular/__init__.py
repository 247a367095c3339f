"""The specular part of ``arealights``: every ``specular_arealight`` technique (LTC, Karis's representative point for
spheres and tubes, plug-ins) against Mitsuba's GGX ``roughconductor`` under rectangle, disc, sphere and tube emitters.

Scenes: a receiver at the origin, normal +y; the viewer at θ_v from the normal (azimuth 0); the light's centre
at unit distance in direction (θ_l, Δφ) (Δφ = 180°: the mirror side), its size given by the half-angle σ it
subtends (sphere R = sin σ; disc of radius tan σ and square of side 2 tan σ, both facing the receiver; a tube (capsule)
of radius TUBE_RADIUS = sin 2° and length ℓ = 2 tan σ, its axis perpendicular to the direction of its centre, either
across the plane of incidence or along it — both are measured). GGX α ∈ settings, F = 1 (η = 0, k = 1 in Mitsuba;
f0 = 1 for the techniques), L_e = 1.

Reference: :func:`validate.reference.area_specular_render.reference` (Mitsuba's BSDF.eval integrated over the
emitter, Gauss–Legendre n nodes; ± |L(n) − L(n/2)|), validated first against Mitsuba's rendered radiance
(:func:`~validate.reference.area_specular_render.render`: the same plane, BSDF and area emitter, ``direct``
integrator) by a Šidák-corrected z test that must also reject a 2 % bias.

Metrics (per technique; the luminance channel, F = 1 makes all channels equal):
* ``rel_err.<shape>`` = Σ |L − L_ref| / Σ L_ref over every configuration, α and σ of the shape; also per α
  (``rel_err.<shape>.a<α>``) and per σ (``rel_err.<shape>.s<σ>``); ± Σ u_ref / Σ L_ref;
* ``bound_ratio.<shape>`` (LTC only) = max over configurations of (|L − L_ref| − u_ref) / B with
  B = L_e ∫_{S²} |E·D_ltc − f cos| dω, the misfit of the LTC actually used (table interpolated at (μ_v, α))
  integrated over the whole sphere: by the triangle inequality |∫_light (E·D − f cos)| ≤ B for every light, so
  the ratio is ≤ 1 wherever the polygon integral is exact (theorem; a disc is a 64-gon of equal area).

Tubes (Karis 2013 "Tube lights"): ``representative_point_tube`` (energy (α/α′_line)(α/α′_sphere)²) against its
unnormalised counterpart, and against two variants measured per configuration — the line factor left out
(``no_line``: the sphere's factor only) and the line factor squared (``line_squared``: the segment treated as widening
the lobe in both dimensions) — judged by the same Σ|ΔL|/ΣL.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, sections, techniques

KEY = "specular"  # the parent's measurements m["specular"], results.json experiments.arealights.specular

__all__ = ["KEY", "compute", "claims", "findings", "sections", "data", "techniques"]
