"""Experiment ``brdfs``: the textbooks' shading models (Phong, Blinn–Phong, Cook–Torrance, Oren–Nayar, Minnaert,
Lambert) against physics.

Techniques: the ``brdf`` family (:mod:`validate.local_models.brdf.classic_brdfs`; contract: cosine-weighted BRDF
q = f_r(l, v)·max(0, n·l)). Every registered technique is measured on every material.

References
  * Mitsuba's BSDFs evaluated directly (:func:`validate.reference.brdf_render.eval_bsdf`):
    ``roughconductor`` Beckmann and GGX (coloured conductor, mirror F = 1, dielectric interface),
    ``diffuse``, and the suite's normalised modified Phong (:mod:`validate.reference.ibl_render`);
  * geometry, not a formula, for the rough diffuse models: a Lambertian V-groove microsurface path-traced
    with inter-reflections (:func:`validate.reference.brdf_render.vgroove_brdf`).

Metrics (:mod:`.compute`): ``rel_l1.<material>``, ``max_rel.<material>``, ``albedo_error.<material>``,
each ± uncertainty, with the power perturbation "output × 1.02".

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` → :func:`.claims.claims` →
:func:`.report.findings`, :func:`.report.sections`; :func:`..base.run` wires them. :mod:`.check` serves
``validate.testing.check_brdf``.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "Textbook shading models vs physics"
DESCRIPTION = "every brdf technique vs Mitsuba BSDFs and path-traced V-grooves"
ORDER = 70




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "summary", "techniques"]
