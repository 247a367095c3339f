"""Experiment ``listings``: every lighting listing of the seeds run as printed, the printed equations, Mitsuba.

The seeds' listings (index: ``docs/listings.md``, :mod:`validate.local_models.listings.catalog`) run on
Mesa llvmpipe through :mod:`validate.gl.listing_harness`, each beside its float64 Python transcription;
printed equations without a listing run as "as printed" Python techniques beside their corrections;
Mitsuba references: ``roughconductor`` BSDF evaluations, the point emitter, the textured projector of the
``uberlight`` experiment, a Lambertian disc's exact on-axis irradiance. Without a GL runtime the GLSL
rows are skipped (the findings say why) and the Python transcriptions stand in.
"""

from __future__ import annotations

from dataclasses import asdict

from ..base import Claim, Context, ExperimentResult, Section, register_experiment
from .claims import claims
from .compute import Measurements, compute
from .report import findings, sections
from .settings import FULL, QUICK, Settings

NAME = "listings"
TITLE = "The textbooks' lighting listings, run as printed"
DESCRIPTION = ("Every lighting listing of the five seed texts on llvmpipe beside its Python transcription and "
               "Mitsuba; printed equations against their corrections")
ORDER = 95


@register_experiment(NAME, TITLE, DESCRIPTION, order=ORDER)
def run(ctx: Context) -> ExperimentResult:
    s = QUICK if ctx.quick else FULL
    m = compute(ctx, s)
    res = ExperimentResult(NAME, TITLE, DESCRIPTION, claims=claims(m), findings=findings(m), settings=asdict(s))
    res.data = {k: v for k, v in asdict(m).items() if k != "settings"}
    res.sections = sections(m, ctx)
    return res


__all__ = ["DESCRIPTION", "FULL", "NAME", "ORDER", "QUICK", "TITLE", "Claim", "Measurements", "Section", "Settings",
           "claims", "compute", "findings", "run", "sections"]
