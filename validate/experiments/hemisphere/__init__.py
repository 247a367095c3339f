"""Experiment ``hemisphere``: hemisphere lighting (sky/ground blend) and every irradiance technique under
the skies hemisphere lighting is meant for, against Mitsuba (the method and references: :mod:`.compute`).

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` → :func:`.claims.claims` →
:func:`.report.findings`, :func:`.report.sections`; :func:`run` only wires them.
"""

from __future__ import annotations

from ..base import Context, ExperimentResult, register_experiment
from . import report
from .claims import claims
from .compute import compute
from .report import findings, sections
from .settings import FULL, NAME, QUICK

TITLE = "Hemisphere lighting vs Mitsuba (exact sky/ground blend vs the Red Book formula)"
DESCRIPTION = "both blend weights and every irradiance technique under a two-tone sky and sunsky"
ORDER = 20


@register_experiment(NAME, TITLE, DESCRIPTION, order=ORDER)
def run(ctx: Context) -> ExperimentResult:
    m = compute(ctx, QUICK if ctx.quick else FULL)
    techniques, data = report.techniques(m), report.data(m)
    return ExperimentResult(name=NAME, title=report.HEADING, summary=report.summary(m), claims=claims(m),
                            findings=findings(m), sections=sections(m, ctx), data=data, settings=m["settings"],
                            techniques=techniques)


__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections", "run"]
