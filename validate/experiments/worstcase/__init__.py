"""``worstcase``: the worst lighting for each irradiance technique (issue 22, items 1 and 2).

Linear techniques (tested, :func:`.certificate.linearity_defect`) get an exact certificate — the supremum of
the flux-normalised error over all non-negative lighting, attained by one direction (:mod:`.certificate`);
every technique gets a worst-case search over suns and skies (:mod:`.search`: drjit AD where a drjit version
exists, :mod:`.dr_models`; SPSA otherwise), whose worst lighting is written as an EXR probe.
"""

from __future__ import annotations

from typing import Any

from ...local_models import irradiance
from ..base import Context, ExperimentResult, register_experiment
from ..techniques import technique_entry
from .claims import claims
from .compute import NAME, Measurements, compute
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
    data = {"linearity": m.linearity,
            "certificates": {n: {k: c.to_json() for k, c in v.items()} for n, v in m.certificates.items()},
            "sh9_power": m.sh9_power, "threshold_power": m.threshold_power,
            "searches": {n: {k: r.to_json() for k, r in v.items()} for n, v in m.searches.items()},
            "probes": m.probes}
    return ExperimentResult(NAME, TITLE, DESCRIPTION, claims(m), findings(m), sections(m, ctx), data,
                            settings={k: v for k, v in s.__dict__.items()}, techniques=technique_entries(m))


def technique_entries(m: Measurements) -> dict[str, Any]:
    """results.json entries: linearity defect, certificates and worst errors found, per technique."""
    out = {}
    for name, lin in m.linearity.items():
        metrics: dict[str, float] = {"linearity_defect": lin["defect"]}
        for metric, c in m.certificates.get(name, {}).items():
            metrics[f"certificate.{metric}"] = c.value
        for metric, r in m.searches.get(name, {}).items():
            metrics[f"search.{metric}"] = r.value
        out[name] = technique_entry(irradiance[name], metrics, linear=lin["linear"])
    return out


__all__ = ["DESCRIPTION", "FULL", "NAME", "ORDER", "QUICK", "TITLE", "claims", "compute", "findings", "run", "sections"]
