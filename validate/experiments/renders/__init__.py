"""Experiment ``renders``: engines' pixels (three.js, Babylon.js) against the Mitsuba path tracer (issue 21).

Scenes (:mod:`validate.scenes.render_scenes`) are rendered by Mitsuba at pixel centres
(:mod:`validate.reference.render_reference`) and by each engine through its own pipeline in headless
Chromium (:mod:`validate.local_models.render`), then judged per pixel (:mod:`validate.metrics.pixel_z`).
Without Chromium or node_modules every engine is skipped with the reason.
"""

from __future__ import annotations

from ..base import Context, ExperimentResult, register_experiment
from .claims import claims
from .compute import Measurements, compute
from .report import findings, sections
from .settings import FULL, QUICK, Settings

NAME = "renders"
TITLE = "Engines' pixels against the path tracer: three.js and Babylon.js vs Mitsuba"
DESCRIPTION = "Furnace and directional-light spheres rendered by the engines, judged per pixel with uncertainty"
ORDER = 95


def data(m: Measurements) -> dict:
    return {"scenes": {s.scene.name: {"kind": s.kind, "skipped": s.skipped, "engines": {
        e: {"frame_ms": r.frame_ms, "wall_s": r.wall_s, "version": r.version, "energy": r.energy,
            "judgements": {k: j.to_json() for k, j in r.judgements.items()}} for e, r in s.engines.items()},
        "reference_energy": s.reference_energy} for s in m.scenes}, "startup": m.startup}


@register_experiment(NAME, TITLE, DESCRIPTION, ORDER)
def run(ctx: Context) -> ExperimentResult:
    s: Settings = QUICK if ctx.quick else FULL
    m = compute(ctx, s)
    skipped = sorted({why for sc in m.scenes for why in sc.skipped.values()})
    summary = "Skipped engines: " + "; ".join(skipped) if skipped and not any(sc.engines for sc in m.scenes) else \
        f"{len(m.scenes)} scenes × {len(s.engines)} engines at {s.resolution}² pixels."
    return ExperimentResult(NAME, TITLE, summary, claims(m), findings(m), sections(m, ctx), data(m),
                            settings={"spp": s.spp, "passes": s.passes, "resolution": s.resolution,
                                      "engines": list(s.engines), "seed": s.seed})


__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "run"]
