"""Experiment ``arealights``: disc and sphere lights — zonal SH, the point-light shortcuts, the exact cap and
plug-ins — against Mitsuba, and specular area lights (:mod:`.specular`). The method and references are in
:mod:`.claims`.

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` → :func:`.claims.claims` →
:func:`.report.findings`, :func:`.report.sections`; :func:`run` only wires them. :mod:`.check` serves
``validate.testing.check_arealight``.
"""

from __future__ import annotations

from ..base import Context, ExperimentResult, register_experiment
from . import report
from .claims import claims
from .compute import compute
from .report import findings, sections
from .settings import FULL, NAME, QUICK

TITLE = "Disc and sphere lights: SH, point-light shortcuts and the exact cap vs Mitsuba"
DESCRIPTION = "every arealight technique vs α, elevation and d/r; the 5 % range of order-2 SH"
ORDER = 30


@register_experiment(NAME, TITLE, DESCRIPTION, order=ORDER)
def run(ctx: Context) -> ExperimentResult:
    m = compute(ctx, QUICK if ctx.quick else FULL)
    techniques = report.techniques(m)
    return ExperimentResult(name=NAME, title=report.HEADING, summary=report.summary(m), claims=claims(m),
                            findings=findings(m), sections=sections(m, ctx), techniques=techniques,
                            data=report.data(m), settings=m["settings"])


__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections", "run"]
