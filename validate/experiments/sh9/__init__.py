"""Experiment ``sh9``: SH9 irradiance (Ramamoorthi & Hanrahan 2001) against Mitsuba's radiance.

Pipeline: :func:`compute` (numbers, :mod:`.sh9_compute`) → :func:`~.sh9_claims.claims` →
:func:`~.sh9_claims.findings` → :func:`~.sh9_sections.sections`; :func:`run` only wires them.
Quick and full settings are data (:data:`.sh9_compute.SETTINGS`).

Claims (each with a power check that fails; sources in :mod:`.sh9_claims`):

* ``sh9.paper.<probe>.mean|max`` — the paper's headline on its own probes (Debevec angular maps whose
  stem is exactly a ``debevec_file`` of ``probe_aliases.csv``): flux-normalised luminance error mean
  < 1 %, max < 5 %. Power: a Condon–Shortley phase mismatch.
* ``sh9.published.<probe>`` — the coefficients in R&H's ``prefilter`` convention equal the published
  table up to one exposure factor (every scaled coefficient within ±0.01). Power: the frame z-mirrored.
* ``sh9.bound.max|mean`` — the "any lighting" theorem on every environment: per channel, max error ≤
  3/32 Φ and mean ≤ 3.07 % Φ; ``sh9.worst_case.near_directional.*`` — a 0.5° disc attains > 95 % of
  both; ``sh9.bandlimited.exact`` — exact on order-≤ 2 lighting (< 0.1 %).
* ``reference.convergence``, ``reference.closed_form.<env>`` (constant, two-tone, band-limited from its
  analytic coefficients, near-directional cap), ``reference.pathtrace.<env>[.bias]`` — the reference
  judged by convergence, closed forms and a path-traced Lambertian sphere.
* ``sh9.technique.<name>.<metric>`` — each registered irradiance technique's declared thresholds.

Every registered irradiance technique is evaluated on every environment and gets a row in the
technique comparison and ``results.json`` entries at ``experiments.sh9.techniques.<name>``.
"""

from __future__ import annotations

from functools import partial
from typing import Any

from ...local_models import irradiance as irradiance_family
from ...metrics.irradiance_error import METRIC_NAMES
from ...scenes.probes import read_aliases, read_published_sh9
from ..base import Context, ExperimentResult, register_experiment
from .claims import (
    ATTAINS_BOUND,
    BANDLIMITED_EXACT,
    CLOSED_FORM,
    CONVERGENCE,
    PAPER_MAX,
    PAPER_MEAN,
    TIGHT,
    Measurements,
    claims,
    findings,
)
from .compute import SETTINGS, Settings, pathtrace_crosscheck, sphere_normals
from .compute import analyse_environment as _analyse
from .report import sections
from ..techniques import technique_entry

TITLE = "SH9 irradiance vs Mitsuba (Ramamoorthi & Hanrahan 2001)"


def compute(ctx: Context) -> Measurements:
    """Every environment (``ctx.map``), then the path-traced cross-checks of the reference."""
    settings = SETTINGS["quick" if ctx.quick else "full"]
    envs, skipped = ctx.environments()
    published, aliases = read_published_sh9(), read_aliases()
    results = ctx.map(partial(_analyse, settings=settings, published=published, aliases=aliases),
                      envs, "sh9: environments")
    by_name = {e.name: e for e in envs}
    checked = [n for n in settings.pathtrace if n in by_name]
    cross = ctx.map(partial(pathtrace_crosscheck, settings=settings, seed=ctx.seed), [by_name[n] for n in checked],
                    "sh9: path-traced cross-checks")
    return Measurements(settings, {e.name: r for e, r in zip(envs, results, strict=True)},
                        dict(zip(checked, cross, strict=True)),
                        list(skipped))


def analyse_environment(env: Any, settings: Settings, published: dict | None = None,
                        aliases: dict | None = None) -> dict:
    """:func:`.sh9_compute.analyse_environment` with the published table and aliases defaulted to none / the
    shipped aliases."""
    return _analyse(env, settings, published or {}, read_aliases() if aliases is None else aliases)


def technique_entries(m: Measurements) -> dict[str, Any]:
    """``experiments.sh9.techniques.<name>``: every metric ± uncertainty per environment, plus the same
    under mirrored normals (the power check)."""
    out = {}
    for tech in irradiance_family:
        metrics = {env: {metric: r["models"][tech.name][metric] for metric in METRIC_NAMES}
                   for env, r in m.environments.items() if tech.name in r["models"]}
        mirrored = {env: {metric: r["models_mirrored"][tech.name][metric] for metric in METRIC_NAMES}
                    for env, r in m.environments.items() if tech.name in r["models_mirrored"]}
        out[tech.name] = technique_entry(tech, metrics, mirrored_normals=mirrored)
    return out


def _json(d: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in d.items() if not k.startswith("_")}


@register_experiment("sh9", TITLE, "SH9 coefficients, errors under every metric, error vs order, published table, "
                     "every registered irradiance technique, claims", order=10)
def run(ctx: Context) -> ExperimentResult:
    m = compute(ctx)
    data = {"environments": {k: _json(v) for k, v in m.environments.items()},
            "pathtrace_crosscheck": {k: _json(v) for k, v in m.crosschecks.items()},
            "skipped_inputs": [list(s) for s in m.skipped]}
    return ExperimentResult(
        name="sh9", title=TITLE,
        summary=("Order-2 spherical-harmonic irradiance (9 coefficients, R&H 2001 eq. 12) against a "
                 "deterministic quadrature of Mitsuba's own envmap radiance at "
                 f"{m.settings.normals} quasi-uniform normals. Errors are shown under four normalisations; "
                 "only the flux normalisation (|E′−E|/∫L dω) reproduces the paper's figures."),
        claims=claims(m), findings=findings(m), sections=sections(m, ctx), data=data,
        settings=m.settings.to_json(), techniques=technique_entries(m))


__all__ = ["run", "compute", "analyse_environment", "Settings", "SETTINGS", "METRIC_NAMES", "PAPER_MEAN",
           "PAPER_MAX", "BANDLIMITED_EXACT", "CONVERGENCE", "CLOSED_FORM", "ATTAINS_BOUND", "TIGHT",
           "sphere_normals"]
