"""Experiment ``listings``: every lighting listing of the seeds run as printed, the printed equations, Mitsuba.

The seeds' listings (index: ``docs/listings.md``, :mod:`validate.local_models.listings.catalog`) run on
Mesa llvmpipe through :mod:`validate.gl.listing_harness`, each beside its float64 Python transcription;
printed equations without a listing run as "as printed" Python techniques beside their corrections;
Mitsuba references: ``roughconductor`` BSDF evaluations, the point emitter, the textured projector of the
``uberlight`` experiment, a Lambertian disc's exact on-axis irradiance. Without a GL runtime the GLSL
rows are skipped (the findings say why) and the Python transcriptions stand in.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, not_run, sections
from .settings import FULL, QUICK

NAME = "listings"
TITLE = "The textbooks' lighting listings, run as printed"
DESCRIPTION = ("Every lighting listing of the five seed texts on llvmpipe beside its Python transcription and "
               "Mitsuba; printed equations against their corrections")
ORDER = 92




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "not_run"]
