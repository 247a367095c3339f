"""Experiment ``arealights``: disc and sphere lights — zonal SH, the point-light shortcuts, the exact cap and
plug-ins — against Mitsuba, and specular area lights (:mod:`.specular`). The method and references are in
:mod:`.claims`.

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` → :func:`.claims.claims` →
:func:`.report.findings`, :func:`.report.sections`; :func:`..base.run` wires them. :mod:`.check` serves
``validate.testing.check_arealight``.
"""

from __future__ import annotations

from . import specular
from .claims import claims
from .compute import compute
from .report import data, findings, reported_settings, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "Disc and sphere lights, and specular area lights, vs Mitsuba"
DESCRIPTION = "every arealight technique vs α, elevation and d/r; the 5 % range of order-2 SH"
ORDER = 30


PARTS = (specular,)


__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "reported_settings", "summary", "techniques", "PARTS"]
