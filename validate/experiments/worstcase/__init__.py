"""``worstcase``: the worst lighting for each irradiance technique (issue 22, items 1 and 2).

Linear techniques (tested, :func:`.certificate.linearity_defect`) get an exact certificate — the supremum of
the flux-normalised error over all non-negative lighting, attained by one direction (:mod:`.certificate`);
every technique gets a worst-case search over suns and skies (:mod:`.search`: drjit AD where a drjit version
exists, :mod:`.dr_models`; SPSA otherwise), whose worst lighting is written as an EXR probe.
"""

from __future__ import annotations

from ..base import Context, ExperimentResult, register_experiment
from . import report
from .claims import claims
from .compute import NAME, compute
from .report import findings, sections
from .settings import FULL, QUICK

TITLE = "Worst case for any lighting: certificates of linear techniques and a differentiable search"
DESCRIPTION = ("sup of the flux-normalised irradiance error over all non-negative lighting (one direction for a "
               "linear technique), and a drjit-AD / SPSA search over spherical-Gaussian suns and soft skies")
ORDER = 15


@register_experiment(NAME, TITLE, DESCRIPTION, ORDER)
def run(ctx: Context) -> ExperimentResult:
    s = QUICK if ctx.quick else FULL
    m = compute(ctx, s)
    return ExperimentResult(NAME, TITLE, DESCRIPTION, claims(m), findings(m), sections(m, ctx), report.data(m),
                            settings=report.settings_json(s), techniques=report.techniques(m))


__all__ = ["DESCRIPTION", "FULL", "NAME", "ORDER", "QUICK", "TITLE", "claims", "compute", "findings", "run", "sections"]
