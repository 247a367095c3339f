"""(b) Babylon's CDF irradiance (Babylon PR 16247): findings, a table and a figure per run, and results.json data."""

from __future__ import annotations

from typing import Any

import numpy as np

from ....format import col
from ....format import pm as fpm
from ...base import Figure, Section, Table
from ...formatting import pct
from .compute import CdfScene

NOTE = ("(b) Babylon's CDF irradiance (Babylon PR 16247, 'Make prefiltering using CDF default to supersample': "
        "below a cube size of 256 the CDF irradiance 'varies considerably (and usually gets darker)'). The "
        "Lambertian sphere under a sunny 1k probe, rendered by Babylon with HDRCubeTexture(prefilterIrradianceOnLoad, "
        "prefilterUsingCdf) at each cube size, its panorama-to-cube supersampling as shipped (forced by the PR: "
        "round(W/4/size)² samples per texel, 16 at 64, 4 at 128, 1 from 256) and as before the PR (none), against "
        "Mitsuba's envmap of the same texels. r = Σ engine / Σ Mitsuba over the judged pixels and channels, ± the "
        "reference's standard error; Babylon's own 4096-point Hammersley estimate is deterministic.")


def cdf_table(sc: CdfScene) -> Table:
    rows: list[list[Any]] = []
    for r in sorted(sc.results, key=lambda x: (x.size, x.variant)):
        j = r.judgement
        rows.append([r.size, r.variant, bool(r.info.get("cdf", {}).get("supersample")), fpm(r.ratio, r.ratio_unc),
                     j.n_pixels, f"{100 * j.fraction_accepted:.2f}", fpm(j.mean_rel, j.mean_rel_unc, scale=100),
                     f"{r.frame_ms:.0f}"])
    for name, why in sc.skipped.items():
        rows.append([name, "skipped", why, "", "", "", "", ""])
    return Table([col("cube size", "px"), col("variant", "–"), col("supersampled", "–"),
                  col("energy ratio r = engine/Mitsuba", "×"), col("pixels", "px"), col("accepted", "%"),
                  col("mean rel. err.", "%"), col("frame", "ms")], rows,
                 caption=f"{sc.scene.name} ({sc.note}): Babylon's CDF irradiance per cube size")


def cdf_figure(sc: CdfScene, ctx: Any) -> Figure | None:
    from ....figures import plots

    if not sc.results:
        return None
    images, titles = [np.nan_to_num(sc.mean)], ["truth (mitsuba)"]
    for r in sorted(sc.results, key=lambda x: (x.variant, x.size)):
        images.append(r.image)
        titles.append(f"{r.size} {r.variant}")
    path, rel = ctx.figure_path("renders", f"{sc.scene.name}_babylon_r{sc.scene.resolution}.png")
    plots.save_image_grid(path, images, titles, exposure=1.0)
    return Figure(rel, f"{sc.scene.name}: truth | Babylon's CDF irradiance per cube size and variant")


def cdf_sections(scenes: list[CdfScene], ctx: Any) -> list[Section]:
    if not scenes:
        return []
    figs = [f for f in (cdf_figure(sc, ctx) for sc in scenes) if f is not None]
    return [Section("(b) Babylon's CDF irradiance below and above 256 (Babylon PR 16247)", [NOTE], figures=figs,
                    tables=[cdf_table(sc) for sc in scenes])]


def cdf_findings(scenes: list[CdfScene]) -> list[str]:
    out = []
    for sc in scenes:
        for v in ("shipped", "pre16247"):
            rs = sorted((r for r in sc.results if r.variant == v), key=lambda r: r.size)
            if not rs:
                continue
            parts = "; ".join(f"{r.size}: {fpm(r.ratio, r.ratio_unc)} ({pct(r.judgement.fraction_accepted)} of "
                              f"{r.judgement.n_pixels} px accepted)" for r in rs)
            what = ("as shipped (supersampling forced by the PR)" if v == "shipped"
                    else "without supersampling (before the PR)")
            out.append(f"Babylon PR 16247 (CDF irradiance darker below 256), {sc.note}, {what}: energy ratio "
                       f"engine/Mitsuba by cube size {parts}.")
        for name, why in sc.skipped.items():
            out.append(f"{sc.scene.name}: {name} skipped: {why}")
    return out


def cdf_data(scenes: list[CdfScene]) -> dict[str, Any]:
    return {sc.scene.name: {"note": sc.note, "skipped": sc.skipped, "results": {
        f"{r.size} {r.variant}": {"ratio": r.ratio, "ratio_unc": r.ratio_unc, "info": r.info, "frame_ms": r.frame_ms,
                                  "wall_s": r.wall_s, "judgement": r.judgement.to_json()} for r in sc.results}}
        for sc in scenes}


def data(scenes: list[CdfScene]) -> dict[str, Any]:
    """``experiments.renders.cdf_irradiance``, when the part ran (full runs)."""
    return {"cdf_irradiance": cdf_data(scenes)} if scenes else {}
