"""(e) Shadows: the section (tables per scene, images truth | engine | error per shadow type), findings and data."""

from __future__ import annotations

from typing import Any

import numpy as np

from ....format import col
from ....format import pm as fpm
from ...base import Figure, Section, Table
from ...formatting import pct
from .compute import REGIONS, ShadowSceneResult, shadow_factor

NOTE = ("(e) Shadows. The Lambertian plane under a directional light (3 lux, 45° incidence) and a spot light (6 cd, "
        "the whole view inside its inner cone), each with a thin box occluder outside the camera's view. The engines "
        "model both lights as delta lights — a hard shadow — filtered by their shadow maps (three and Babylon: 512², "
        "the same light frustum, only the box casts; Filament 1.53: PCF, the only type its JS View can select, its "
        "default 1024² map, biases and own light frustum — its ShadowOptions are not bound in the npm build — and the "
        "plane casts as well as receives, without which Filament draws no shadow). Mitsuba path-traces the light "
        "with a size: the sun as a "
        "sphere of 3° angular radius at 10 km (radiance E/(π sin²α), so the unshadowed plane receives exactly "
        "E cos θ), the spot as a sphere of radius 0.15 m (radiance I/(π r²): exactly I cos θ/d²); per-pixel standard "
        "error from 8 passes. Regions from the geometric visibility of the light's disc: lit (2 px or more from any "
        "shadow), penumbra (partly visible), umbra (nothing visible). Penumbra width W = pixels with shadow factor "
        "0.1 < s < 0.9 (s = radiance / unshadowed radiance); leak = umbra pixels brighter than the budget. "
        "three 0.187's PCFSoftShadowMap is removed (it renders PCF: column 'used'). Filament's 8-bit canvas carries "
        "its ±½ LSB quantisation as a known uncertainty in the per-pixel test.")


def region_table(sr: ShadowSceneResult) -> Table:
    rows: list[list[Any]] = []
    for r in sr.results:
        for region in REGIONS:
            j = r.judgements.get(region)
            if j is None:
                continue
            rows.append([r.engine, r.shadow_type, r.used, region, j.n_pixels, f"{100 * j.fraction_accepted:.2f}",
                         f"{j.max_abs_z:.1f} / {j.critical_z:.2f}",
                         fpm(j.mean_rel, j.mean_rel_unc, scale=100) if region != "umbra" else "",
                         fpm(j.max_rel, j.max_rel_unc, scale=100) if region != "umbra" else ""])
    for name, why in sr.skipped.items():
        rows.append([name, "skipped", why, "", "", "", "", "", ""])
    return Table(["engine", col("shadow type", "–"), col("type used", "–"), col("region", "–"), col("pixels", "px"),
                  col("accepted", "%"),
                  col("max|z| / z*", "–"), col("mean rel. err.", "%"), col("max rel. err.", "%")], rows,
                 caption=f"{sr.scene.name}: per-pixel judgement by region")


def width_table(sr: ShadowSceneResult) -> Table:
    wt, ut = sr.truth_width
    rows: list[list[Any]] = [["mitsuba", "path traced", f"{wt:.0f} ± {ut:.1f}", "1", "0", "0"]]
    for r in sr.results:
        rows.append([r.engine, r.shadow_type, f"{r.width_px:.0f}", fpm(r.width_px / wt, r.width_px * ut / wt**2),
                     fpm(r.leak[0], r.leak[1], scale=100), fpm(r.umbra_mean[0], r.umbra_mean[1], scale=100)])
    return Table(["engine", col("shadow type", "–"), col("penumbra width W (10–90 %)", "px"), col("W / W_truth", "×"),
                  col("umbra pixels lit (leak)", "%"), col("mean shadow factor in the umbra", "%")], rows,
                 caption=f"{sr.scene.name}: penumbra width and light leak (three issue 23551)")


def shadow_figures(sr: ShadowSceneResult, ctx: Any) -> list[Figure]:
    """One figure per engine: truth | each shadow type's image and its shadow-factor error × 10."""
    from ....figures import plots

    st = shadow_factor(sr.mean, sr.unshadowed)
    out = []
    for engine in dict.fromkeys(r.engine for r in sr.results):
        images, titles = [np.nan_to_num(sr.mean)], ["truth (mitsuba)"]
        for r in (x for x in sr.results if x.engine == engine):
            err = np.abs(shadow_factor(r.image, sr.unshadowed) - st) * 2.0
            images += [r.image, np.repeat(np.nan_to_num(err)[..., None], 3, axis=-1)]
            titles += [f"{r.shadow_type}", f"{r.shadow_type} |Δs| × 2"]
        path, rel = ctx.figure_path("renders", f"{sr.scene.name}_{engine}_r{sr.scene.resolution}.png")
        plots.save_image_grid(path, images, titles, exposure=1.0)
        out.append(Figure(rel, f"{sr.scene.name}, {engine}: truth | engine | shadow-factor error "
                               "|s_engine − s_truth| × 2 (white = 0.5), per shadow type"))
    return out


def shadow_sections(shadows: list[ShadowSceneResult], ctx: Any) -> list[Section]:
    if not shadows:
        return []
    figs = [f for sr in shadows for f in shadow_figures(sr, ctx)]
    tables = [t for sr in shadows for t in (width_table(sr), region_table(sr))]
    return [Section("(e) Shadows: directional and spot light with an occluder", [NOTE], figures=figs, tables=tables)]


def leak_finding(shadows: list[ShadowSceneResult]) -> list[str]:
    """three issue 23551 ("shadow light leaks no bias fixes"): lit pixels in the umbra, per engine × type."""
    parts = [f"{sr.scene.name} {r.engine} {r.shadow_type} {fpm(r.leak[0], r.leak[1], '%')} of "
             f"{int(sr.regions['umbra'].sum())} px" for sr in shadows for r in sr.results]
    if not parts:
        return []
    return ["three issue 23551 (shadow light leaks that no bias fixes), umbra pixels brighter than the budget (light "
            "leak; three/Babylon receiver not casting, three's bias 0, Babylon's 5e-5; Filament's plane casts, its "
            "default biases): " + "; ".join(parts) + ". A leak here is the filter's (or, Filament's spot, a shadow "
            "never drawn), not a bias's (three's VSM draws receivers into its map, which darkens the lit plane, not "
            "the umbra)."]


def shadow_findings(shadows: list[ShadowSceneResult]) -> list[str]:
    out = leak_finding(shadows)
    for sr in shadows:
        wt, ut = sr.truth_width
        for r in sr.results:
            jl, jp = r.judgements.get("lit"), r.judgements.get("penumbra")
            lit = f"lit {pct(jl.fraction_accepted)} accepted" if jl else "no lit pixels"
            pen = (f"penumbra {pct(jp.fraction_accepted)} accepted, mean rel. err. "
                   f"{fpm(jp.mean_rel, jp.mean_rel_unc, '%')}" if jp else "no penumbra pixels")
            out.append(f"{sr.scene.name}, {r.engine} {r.shadow_type} (used {r.used}): {lit}; {pen}; penumbra width "
                       f"{r.width_px:.0f} px vs the path tracer's {wt:.0f} ± {ut:.1f} px (ratio "
                       f"{fpm(r.width_px / wt, r.width_px * ut / wt**2)}); three issue 23551 (light leaks): "
                       f"{fpm(r.leak[0], r.leak[1], '%')} of the umbra lit, mean shadow factor there "
                       f"{fpm(r.umbra_mean[0], r.umbra_mean[1], '%')}.")
    return out


def shadow_data(shadows: list[ShadowSceneResult]) -> dict[str, Any]:
    return {sr.scene.name: {
        "truth_width_px": list(sr.truth_width), "reference_s": sr.reference_s, "skipped": sr.skipped,
        "light_size": sr.scene.light_size, "regions_px": {k: int(m.sum()) for k, m in sr.regions.items()},
        "engines": {f"{r.engine} {r.shadow_type}": {
            "used": r.used, "frame_ms": r.frame_ms, "wall_s": r.wall_s, "width_px": r.width_px,
            "leak": list(r.leak), "umbra_mean": list(r.umbra_mean),
            "judgements": {k: j.to_json() for k, j in r.judgements.items()}} for r in sr.results}}
        for sr in shadows}


def data(shadows: list[ShadowSceneResult]) -> dict[str, Any]:
    """``experiments.renders.shadows``."""
    return {"shadows": shadow_data(shadows)}
