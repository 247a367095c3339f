"""Findings and report sections of the ``renders`` experiment: a table per scene (engine × metric) and the
images truth | engine | error."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..base import Figure, Section, Table
from ..formatting import pct, pm
from .compute import Measurements, SceneResult

FILAMENT_NOTE = ("Filament is not rendered: its npm package (1.53) ships no IBL prefilter (cmgen) to turn the "
                 "scene's file into its own prefiltered environment, and no readPixels of a float target, so it "
                 "cannot render these scenes through its own pipeline with an exact read-back (issue 21).")
REFERENCE_NOTE = ("Two references, kept apart: 'energy' — a white non-absorbing sphere in a radiance-1 furnace "
                  "returns exactly 1 (what a physically complete multiple-scattering model gives); 'model' — "
                  "glTF 2.0's single-scattering metal (Appendix B) path-traced by Mitsuba (roughconductor), so the "
                  "distance to it is the engine's approximation *plus* its multiscatter compensation; 'mitsuba' — "
                  "the Lambertian sphere under a directional light (exact model, exact integral).")


def scene_table(sr: SceneResult) -> Table:
    rows: list[list[Any]] = []
    for name, er in sr.engines.items():
        for kind, j in er.judgements.items():
            rows.append([name, kind, j.n_pixels, pct(j.fraction_accepted), f"{j.max_abs_z:.2f} / {j.critical_z:.2f}",
                         pm(j.mean_rel, j.mean_rel_unc), pm(j.max_rel, j.max_rel_unc), f"{j.mean_signed_rel:+.3%}",
                         f"{er.energy:.5f}",
                         f"{sr.reference_energy[kind][0]:.5f} ± {sr.reference_energy[kind][1]:.1e}"])
    for name, why in sr.skipped.items():
        rows.append([name, "skipped", why, "", "", "", "", "", "", ""])
    return Table(["engine", "reference", "pixels (px)", "accepted (%)", "max|z| / z* (–)", "mean |rel| (%)",
                  "max |rel| (%)", "mean rel, bias (%)", "engine mean (W/(m²·sr))", "reference mean (W/(m²·sr))"],
                 rows, caption=sr.scene.name)


def scene_figure(sr: SceneResult, ctx: Any) -> Figure | None:
    from ...report import plots

    if not sr.engines:
        return None
    kind = "mitsuba" if "mitsuba" in sr.references else ("model" if "model" in sr.references else "energy")
    images, titles = [np.nan_to_num(sr.references[kind])], [f"truth ({kind})"]
    for name, er in sr.engines.items():
        images.append(er.image)
        titles.append(name)
        rel = er.judgements[kind].rel_image
        images.append(np.repeat(np.nan_to_num(np.abs(rel))[..., None] * 10.0, 3, axis=-1))
        titles.append(f"{name} |rel| × 10")
    path, rel_path = ctx.figure_path("renders", f"{sr.scene.name}_r{sr.scene.resolution}.png")
    plots.save_image_grid(path, images, titles, exposure=1.0)
    return Figure(rel_path, f"{sr.scene.name}: truth | engine | relative error × 10 (white = 10 %)")


def findings(m: Measurements) -> list[str]:
    out = []
    for sr in m.scenes:
        for name, er in sr.engines.items():
            for kind, j in er.judgements.items():
                out.append(f"{sr.scene.name}, {name} vs {kind}: {pct(j.fraction_accepted)} of {j.n_pixels} pixels "
                           f"accepted (z* = {j.critical_z:.2f}), mean |rel| {pm(j.mean_rel, j.mean_rel_unc)}, max "
                           f"{pm(j.max_rel, j.max_rel_unc)}, bias {j.mean_signed_rel:+.3%}.")
    metal = [s for s in m.scenes if "model" in s.reference_energy]
    if metal:
        loss = ", ".join(f"r {s.scene.material.roughness:g}: {s.reference_energy['model'][0]:.4f} ± "
                         f"{s.reference_energy['model'][1]:.1e}" for s in metal)
        out.append(f"glTF single-scattering white metal in the furnace (Mitsuba roughconductor) keeps {loss} of the "
                   "energy; an engine at 1 adds that much by its multiscatter term (three PR 32190).")
    return out


def sections(m: Measurements, ctx: Any) -> list[Section]:
    out = []
    for kind, title in (("furnace", "(a) White furnace"), ("directional", "(c) Directional light, Lambertian")):
        scenes = [s for s in m.scenes if s.kind == kind]
        figs = [f for f in (scene_figure(s, ctx) for s in scenes) if f is not None]
        out.append(Section(title, [REFERENCE_NOTE] if kind == "furnace" else [], figures=figs,
                           tables=[scene_table(s) for s in scenes]))
    out.append(Section("Engines not rendered", [FILAMENT_NOTE]))
    return out


def data(m: Measurements) -> dict:
    """results.json data: per scene and engine, frame times, energy and the per-pixel judgements."""
    return {"scenes": {s.scene.name: {"kind": s.kind, "skipped": s.skipped, "engines": {
        e: {"frame_ms": r.frame_ms, "wall_s": r.wall_s, "version": r.version, "energy": r.energy,
            "judgements": {k: j.to_json() for k, j in r.judgements.items()}} for e, r in s.engines.items()},
        "reference_energy": s.reference_energy} for s in m.scenes}, "startup": m.startup}


def summary(m: Measurements) -> str:
    """One line: what was rendered, or why every engine was skipped."""
    s = m.settings
    skipped = sorted({why for sc in m.scenes for why in sc.skipped.values()})
    if skipped and not any(sc.engines for sc in m.scenes):
        return "Skipped engines: " + "; ".join(skipped)
    return f"{len(m.scenes)} scenes × {len(s.engines)} engines at {s.resolution}² pixels."


def settings_json(m: Measurements) -> dict[str, Any]:
    """The settings the run used."""
    s = m.settings
    return {"spp": s.spp, "passes": s.passes, "resolution": s.resolution, "engines": list(s.engines), "seed": s.seed}
