"""The glTF Sample Viewer's findings, its table (scene, accepted %, pass/fail beside the other engines of the same
run) and results.json data."""

from __future__ import annotations

from typing import Any

from ....format import col
from ....metrics.pixel_z import MIN_ACCEPTED
from ...base import Section, Table
from .compute import KhronosPart

NOTE = ("The Khronos glTF Sample Viewer (npm @khronosgroup/gltf-viewer) renders the exported scene files (validate "
        "scenes export) through its own glTF loader, its RGBE loader and WebGL IBL sampler and its PBR shader, tone "
        "mapping NONE; its only output is the 8-bit canvas with a 2.2 gamma, decoded as (q/255)^2.2/exposure, the "
        "rounding's σ = 2.2 c^1.2/(255·√12·e) per value added in quadrature to Mitsuba's standard error. Judged "
        "against the same Mitsuba references, interior masks and budgets as the other engines.")


def _cell(sr: Any, engine: str, key: str) -> str:
    er = sr.engines.get(engine)
    if er is None or key not in er.judgements:
        return "–"
    f = er.judgements[key].fraction_accepted
    return f"{100 * f:.2f} {'pass' if f >= MIN_ACCEPTED else 'fail'}"


def khronos_table(part: KhronosPart) -> Table:
    others = sorted({e for sr in part.parent_scenes.values() for e in sr.engines})
    rows: list[list[Any]] = []
    for n, ks in part.scenes.items():
        sr = part.parent_scenes[n]
        key = "energy" if ks.kind == "furnace" else "mitsuba"
        key = key if key in ks.judgements else next(iter(ks.judgements))
        j = ks.judgements[key]
        rows.append([n, key, f"{100 * j.fraction_accepted:.2f}", "pass" if j.fraction_accepted >= MIN_ACCEPTED
                     else "fail", f"{100 * j.mean_signed_rel:+.2f}", f"{ks.energy:.4f}", f"{ks.info['exposure']:g}",
                     *[_cell(sr, e, key) for e in others]])
    for n, why in part.not_rendered.items():
        rows.append([n, "not rendered", why, "", "", "", "", *["" for _ in others]])
    return Table([col("scene", "–"), col("reference", "–"), col("accepted", "%"), col("pass/fail", "–"),
                  col("mean signed rel. err.", "%"), col("mean radiance", "–"), col("exposure", "×"),
                  *[col(f"{e} accepted", "%") for e in others]], rows,
                 caption=f"glTF Sample Viewer {part.version}: pixels accepted per scene (≥ {100 * MIN_ACCEPTED:.2f} % "
                         f"passes), beside the other engines of this run")


def khronos_sections(part: KhronosPart | None, ctx: Any) -> list[Section]:
    if part is None:
        return []
    if part.skipped:
        return [Section("The Khronos glTF Sample Viewer", [NOTE, f"Not rendered: {part.skipped}"])]
    ibl = ", ".join(f"{k} {v}" for k, v in part.ibl.items())
    times = (f"Export {part.export_s:.1f} s, page {part.startup_s:.1f} s, renders {part.wall_s:.1f} s, the whole part "
             f"{part.total_s:.1f} s.")
    return [Section("The Khronos glTF Sample Viewer", [NOTE, f"IBL sampler fields: {ibl}. {times}"],
                    tables=[khronos_table(part)])]


def khronos_findings(part: KhronosPart | None) -> list[str]:
    if part is None:
        return []
    if part.skipped:
        return [f"glTF Sample Viewer not rendered: {part.skipped}"]
    first = {n: ks.judgements[next(iter(ks.judgements))].fraction_accepted for n, ks in part.scenes.items()}
    bad = [f"{n} ({100 * f:.1f} %)" for n, f in first.items() if f < MIN_ACCEPTED]
    return [f"glTF Sample Viewer {part.version}: {len(part.scenes) - len(bad)}/{len(part.scenes)} scenes accepted "
            f"against Mitsuba" + (f"; below the rule: {', '.join(bad)}" if bad else "")]


def data(part: KhronosPart | None) -> dict[str, Any]:
    """``experiments.renders.khronos_viewer``: per scene, the judgements, energy and what the page reported."""
    if part is None:
        return {}
    return {"khronos_viewer": {
        "version": part.version, "skipped": part.skipped, "not_rendered": part.not_rendered, "ibl": part.ibl,
        "export_s": part.export_s, "startup_s": part.startup_s, "wall_s": part.wall_s, "total_s": part.total_s,
        "scenes": {n: {"kind": ks.kind, "energy": ks.energy, "info": ks.info, "frame_ms": ks.frame_ms,
                       "judgements": {k: j.to_json() for k, j in ks.judgements.items()}}
                   for n, ks in part.scenes.items()}}}
