"""Experiment ``engines``: shipping engines' SH irradiance (three.js, Babylon.js) against the reference.

The engines' own code runs headless in Node (:mod:`validate.local_models.irradiance.engines`: one process per
engine per run, registered as ``irradiance`` techniques ``three_sh``, ``babylon_sh``,
``babylon_polynomial``). Per environment each engine's error under every metric of
:mod:`validate.metrics.irradiance_error` sits beside the suite's own ``sh9``
(:mod:`.compute`); claims (:mod:`.claims`); findings, tables and plots (:mod:`.report`). Without Node or
without the npm engines (``python -m validate setup --engines``) the engines are skipped with the reason (nothing is
registered then, and no other experiment changes), the run names them (``not_run``), and only the cube faces the
engines would receive are checked.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, not_run, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "Shipping engines: three.js and Babylon.js SH irradiance vs Mitsuba"
DESCRIPTION = ("three.js and Babylon.js SH irradiance (run in Node) beside SH9, the engines' conventions, Babylon's "
               "4096 clamp, claims")
ORDER = 15




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "summary", "techniques", "not_run"]
