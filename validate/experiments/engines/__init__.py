"""Experiment ``engines``: shipping engines' SH irradiance (three.js, Babylon.js) against the reference.

The engines' own code runs headless in Node (:mod:`validate.local_models.irradiance.engines`: one process per
engine per run, registered as ``irradiance`` techniques ``three_sh``, ``babylon_sh``,
``babylon_polynomial``). Per environment each engine's error under every metric of
:mod:`validate.metrics.irradiance_error` sits beside the suite's own ``sh9``
(:mod:`.engines_compute`); claims and findings (:mod:`.engines_claims`); tables and plots
(:mod:`.engines_report`). Without Node or without ``npm ci`` the experiment is skipped with the reason
(nothing is registered then, and no other experiment changes).
"""

from __future__ import annotations

from functools import partial
from typing import Any

from ...local_models.irradiance.engines import UNAVAILABLE
from ...local_models.irradiance.engines.worker import package_version
from ..base import Context, ExperimentResult, register_experiment
from .claims import Measurements, claims, face_claims, findings
from .compute import SETTINGS, engine_techniques, measure_environment, measure_face_sizes, measure_faces
from .report import sections
from ..techniques import technique_entry

TITLE = "Shipping engines: three.js and Babylon.js SH irradiance vs Mitsuba"
SWEEP_FALLBACK = ("disc_on_sky", "sunsky_30deg")  # face-size sweep when no named probe is present


def named_environments(envs: dict[str, dict[str, Any]]) -> dict[str, str]:
    """grace_probe (the paper's probe) and the probe with the brightest texel (the strongest sun), if present."""
    out = {}
    if "grace_probe" in envs:
        out["grace_probe"] = "grace_probe"
    probes = {n: r for n, r in envs.items() if r["kind"] == "probe"}
    if probes:
        out["brightest_sun"] = max(probes, key=lambda n: probes[n]["max_map_texel"])
    return out


def compute(ctx: Context) -> Measurements:
    """Every environment (``ctx.map``), then the face-size sweep on the named probes."""
    settings = SETTINGS["quick" if ctx.quick else "full"]
    envs, skipped = ctx.environments()
    results = ctx.map(partial(measure_environment, settings=settings), envs, "engines: environments")
    environments = {e.name: r for e, r in zip(envs, results, strict=True)}
    named = named_environments(environments)
    by_name = {e.name: e for e in envs}
    sweep_names = list(dict.fromkeys(named.values())) or [n for n in SWEEP_FALLBACK if n in by_name]
    sweeps = ctx.map(partial(measure_face_sizes, settings=settings), [by_name[n] for n in sweep_names],
                     "engines: face sizes")
    return Measurements(settings, environments, dict(zip(sweep_names, sweeps, strict=True)), list(skipped), named)


def technique_entries(m: Measurements) -> dict[str, Any]:
    """``experiments.engines.techniques.<name>``: every metric ± uncertainty per environment, the departure
    from the SH9 of its own faces, and the same metrics with band 1's sign flipped (the power check)."""
    from ...local_models import irradiance

    out = {}
    names = {n for r in m.environments.values() for n in r["techniques"]}
    for name in [t.name for t in irradiance if t.name in names]:
        tech = irradiance[name]
        per_env = {e: r["techniques"][name] for e, r in m.environments.items() if name in r["techniques"]}
        out[name] = technique_entry(
            tech, {e: t["errors"] for e, t in per_env.items()},
            faces_deviation={e: t["faces_deviation"] for e, t in per_env.items()},
            band1_flipped={e: t["errors_band1_flipped"] for e, t in per_env.items()},
            engine=tech.meta.get("engine"), face_size=tech.meta.get("face_size"))
    return out


def skipped_result(ctx: Context, reason: str) -> ExperimentResult:
    """No engine can run: only the faces they would receive are checked (no Node needed)."""
    settings = SETTINGS["quick" if ctx.quick else "full"]
    envs, skipped = ctx.environments()
    faces = ctx.map(partial(measure_faces, settings=settings), envs, "engines: faces")
    m = Measurements(settings, {e.name: r for e, r in zip(envs, faces, strict=True)}, skipped=list(skipped))
    return ExperimentResult(name="engines", title=TITLE, summary=f"Skipped: {reason}. Only the cube faces the "
                            "engines would receive were checked.", claims=face_claims(m),
                            findings=[f"The engines did not run: {reason}."],
                            data={"skipped": reason, "environments": m.environments}, settings=settings.to_json())


@register_experiment("engines", TITLE, "three.js and Babylon.js SH irradiance (run in Node) beside SH9, "
                     "the engines' conventions, Babylon's 4096 clamp, claims", order=15)
def run(ctx: Context) -> ExperimentResult:
    if UNAVAILABLE is not None or not engine_techniques():
        return skipped_result(ctx, UNAVAILABLE or "no engine technique is registered")
    m = compute(ctx)
    data = {"environments": m.environments, "face_size_sweep": m.sweeps, "named": m.named,
            "versions": {"three": package_version("three"), "@babylonjs/core": package_version("babylon")},
            "skipped_inputs": [list(s) for s in m.skipped]}
    return ExperimentResult(
        name="engines", title=TITLE,
        summary=("three.js r187 and Babylon.js 9.35 compute SH irradiance with their own unmodified code, run headless "
                 f"in Node on float32 cube faces (N = {m.settings.face_size}) rendered from the lat-long radiance the "
                 "reference integrates; each engine's error under every metric beside the suite's SH9, the engine "
                 "against the exact SH9 of its own faces, Babylon's 4096 clamp, half-float faces, the face size."),
        claims=claims(m), findings=findings(m), sections=sections(m, ctx), data=data,
        settings=m.settings.to_json(), techniques=technique_entries(m))


__all__ = ["run", "compute", "named_environments", "technique_entries", "TITLE"]
