"""Experiment ``hemisphere``: hemisphere lighting (sky/ground blend) and every irradiance technique under
the skies hemisphere lighting is meant for, against Mitsuba (the method and references: :mod:`.compute`).

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` → :func:`.claims.claims` →
:func:`.report.findings`, :func:`.report.sections`; :func:`..base.run` wires them.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "Hemisphere lighting vs Mitsuba"
DESCRIPTION = "both blend weights and every irradiance technique under a two-tone sky and sunsky"
ORDER = 20




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "summary", "techniques"]
