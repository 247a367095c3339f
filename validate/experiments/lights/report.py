"""Report sections of the ``lights`` experiment: images, error maps, curves and tables (no computation)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...report import plots
from ..base import Context, Figure, Section, Table
from ..formatting import pct_fixed as _pct


def _pm(entry: dict[str, Any]) -> str:
    return f"{_pct(entry['value'], 3)} ± {_pct(entry['uncertainty'], 3)}"


def references_section(m: Any, ctx: Context, name: str) -> Section:
    refs = m.images["references"]
    figs = []
    for key, img in refs.items():
        path, rel = ctx.figure_path(name, f"reference_{key}.png")
        plots.save_image(path, img, upscale=4 if img.shape[1] <= 96 else 2)
        figs.append(Figure(rel, key.replace("_", " "), 200))
    text = [f"Mitsuba direct lighting at the pixel centres ({m.settings['width']}×{m.settings['height']}); per render "
            "spp × passes: " + ", ".join(f"{k} {v['spp_per_pass']}×{v['passes']}"
                                        for k, v in m.data["references"].items()) + ". Delta lights alone render "
            "deterministically (standard error 0); their comparison is limited by float32 rounding only."]
    return Section("Reference renders", text, gallery=[figs[:4], figs[4:]])


def techniques_section(m: Any, ctx: Context, name: str) -> Section:
    rows = []
    for tech, d in m.data["techniques"].items():
        for kind, met in d["metrics"].items():
            rows.append([tech, kind, _pm(met["mean"]), _pm(met["max"]), _pm(met["bias"]),
                         _pct(met["mismatch"]["value"], 3)])
    figs = []
    for tech, (kind, err) in m.images.get("error", {}).items():
        path, rel = ctx.figure_path(name, f"error_{tech}.png")
        plots.save_heatmap(path, err, f"{tech} on {kind}: (Y(a) − Y(r)) / L_norm", "signed error", percent=True)
        figs.append(Figure(rel, f"{tech} ({kind})", 300))
    text = ["Every registered light technique shades the G-buffer (L = ρ/π · E, with the scene's own shadow rays) for "
            "each light it models. mean = mean |ΔY| / L_norm, max = max |ΔY| / L_norm (L_norm = mean lit reference "
            "luminance; over pixels both images light or both leave black), bias = Σ ΔY / Σ Y(r), each ± its Monte "
            "Carlo uncertainty; mismatch = fraction of pixels black in exactly one image (a shadow ray answered "
            "differently). Area lights use the n = "
            f"{m.settings['technique_grid']} grid; the spot's cos^f uses the fitted f = "
            f"{m.data['spot']['fitted_exponent']:.1f}; windowed falloffs use range = {m.settings['range']:g} m."]
    table = Table(["technique", "light", "mean", "max", "bias", "mismatch"], rows)
    return Section("Techniques against Mitsuba", text, tables=[table],
                   gallery=[figs[i:i + 3] for i in range(0, len(figs), 3)])


def attenuation_section(m: Any, ctx: Context, name: str) -> Section:
    att = m.data["attenuation"]
    d = np.asarray(att["distances"])
    series = {k: np.abs(np.asarray(v["ratio"]) - 1.0) + 1e-9 for k, v in att["techniques"].items()}
    path, rel = ctx.figure_path(name, "attenuation_vs_distance.png")
    plots.save_line_plot(path, d, series, "distance d (m)", "|E / (I/d²) − 1|", "attenuation against inverse square",
                         logx=True, logy=True, percent=True, hlines={"1 %": 0.01})
    rows = [[k, *[_pct(v["relative_error_at"][x], 1) for x in ("0.5 m", "1 m", "2 m", "5 m", "10 m")],
             f"{v['best_scale']:.3g}", _pct(v["best_scale_max_error"], 1)] for k, v in att["techniques"].items()]
    lo, hi = att["scene_distance_range"]
    return Section("Attenuation against 1/d²", [
        "E/E_(1/d²) − 1 on the light's axis for unit intensity (the constant-term sets were tuned for unit colours, "
        f"so their error is scale and shape); best scale: the one intensity factor minimising the max error over the "
        f"scene's distances {lo:.2f}–{hi:.2f} m, and that max error."],
        figures=[Figure(rel, "relative error of each attenuation vs distance", 520)],
        tables=[Table(["technique", "0.5 m", "1 m", "2 m", "5 m", "10 m", "best scale", "max error after scale"],
                      rows)])


def standin_section(m: Any, ctx: Context, name: str) -> Section:
    st = m.data["standin"]
    x = np.asarray(st["ratios"])
    series = {k: np.asarray(st[k]["max_rel"], dtype=np.float64) for k in ("rectangle", "disk", "sphere")}
    path, rel = ctx.figure_path(name, "point_standin.png")
    plots.save_line_plot(path, x, {k: np.maximum(v, 1e-9) for k, v in series.items()}, "distance / light size",
                         "max relative error", "one point light for an area light", logx=True, logy=True,
                         percent=True, hlines={"1 %": 0.01})
    rows = [[k, "n/a" if st[k]["ratio_within_1pct"] is None else f"{st[k]['ratio_within_1pct']:.3g}",
             f"{st[k]['extent']:.3g} m", st[k]["skipped_receivers"]] for k in ("rectangle", "disk", "sphere")]
    return Section("When a point light stands in for an area light", [
        "Worst relative error over receivers at polar angles " + ", ".join(f"{p:g}°" for p in st["polar_deg"])
        + " from the light's normal and normals tilted " + ", ".join(f"{t:g}°" for t in st["tilt_deg"])
        + " from the light. Rectangle and disc: a cosine-lobe point I = L·A·cos ψ at the centre (the n = 1 grid); "
        "sphere: an isotropic point I = π r² L. References: Lambert's formula (rectangle; receivers whose horizon cuts "
        "the rectangle skipped), the cap formula (sphere), a 64×64 grid (disc)."],
        figures=[Figure(rel, "max relative error vs distance / size", 520)],
        tables=[Table(["light", "d/size for ≤ 1 %", "size", "receivers skipped"], rows)])


def grid_section(m: Any, ctx: Context, name: str) -> Section:
    g = m.data["grid"]
    n = np.asarray(g["n"], dtype=np.float64)
    path, rel = ctx.figure_path(name, "grid_convergence.png")
    series = {"midpoint (unshadowed, exact ref.)": g["midpoint_max_rel"], "corner rule": g["corner_max_rel"],
              "n⁻² from n = 1": g["midpoint_max_rel"][0] / n**2}
    plots.save_line_plot(path, n, series, "n (n×n points)", "max relative error", "n×n grid vs Lambert's formula",
                         logx=True, logy=True, percent=True)
    gs = m.data["grid_shadowed"]
    path2, rel2 = ctx.figure_path(name, "grid_shadowed.png")
    sh = {f"{k} {reg}": np.maximum(gs[k][reg], 1e-9) for k in ("rectangle", "disk", "sphere")
          for reg in ("penumbra", "lit")}
    plots.save_line_plot(path2, np.asarray(gs["n"], dtype=np.float64), sh, "n (n×n points)", "mean |ΔY| / L_norm",
                         f"shadowed grid vs the {gs['reference_n']}² grid, by region", logx=True, logy=True,
                         percent=True)
    rows = []
    for k in ("rectangle", "disk", "sphere"):
        v, z = gs[k], gs[k]["mitsuba"]
        rows.append([k, *[_pct(v[r][-1], 3) for r in ("lit", "penumbra", "umbra", "total")],
                     "n/a" if v["slopes"]["penumbra"] is None else f"{v['slopes']['penumbra']:.2f}",
                     v["pixels"]["penumbra"], f"{z['pooled_z']:+.2f} / {z['max_abs_z']:.2f}"])
    return Section("Area lights as n×n point lights", [
        f"Unshadowed: slope {g['midpoint_slope']:.2f} (midpoint rule, theory −2), {g['corner_slope']:.2f} "
        "(corner rule, theory −1), against Lambert's formula. Shadowed: the grid with one shadow ray per point "
        f"against the {gs['reference_n']}×{gs['reference_n']} grid (noise-free), split into lit / penumbra / umbra by "
        "the visible fraction of the light (as in the shadows experiment); the fine grid itself is tested against "
        "Mitsuba's render (pooled z / max |z|)."],
        figures=[Figure(rel, "unshadowed convergence", 520), Figure(rel2, "shadowed convergence", 520)],
        tables=[Table(["light", "lit", "penumbra", "umbra", "total", "penumbra slope", "penumbra px",
                       "fine grid vs Mitsuba: pooled z / max |z|"], rows, f"errors at n = {gs['n'][-1]}")])


def spot_section(m: Any, ctx: Context, name: str) -> Section:
    from .sweeps import mitsuba_spot_profile

    sp = m.data["spot"]
    a = np.linspace(0.0, sp["cutoff_deg"] + 4.0, 57)
    cos_a = np.cos(np.radians(a))
    inside = a < sp["cutoff_deg"]
    f = sp["fitted_exponent"]
    series = {"Mitsuba spot (linear in α)": mitsuba_spot_profile(a, sp["beam_deg"], sp["cutoff_deg"]),
              f"cos^f, f = {f:.1f}, hard cutoff": np.where(inside, cos_a**f, 0.0),
              "cos^0 (OpenGL default exponent)": np.where(inside, 1.0, 0.0)}
    path, rel = ctx.figure_path(name, "spot_profile.png")
    plots.save_line_plot(path, a, series, "angle from the axis α (°)", "I(α) / I₀", "spot profiles")
    return Section("Spot profiles", [
        f"Mitsuba's spot ramps linearly in angle from the beam width {sp['beam_deg']:g}° to the cutoff "
        f"{sp['cutoff_deg']:g}° (src/emitters/spot.cpp falloff_curve); the Red Book / Ganovelli spot is cos^f α "
        f"with a hard cutoff. Least-squares f (solid-angle weighted) = {f:.2f}, rms {_pct(sp['fit_rms'])}."],
        figures=[Figure(rel, "spot intensity profiles", 520)])


def lamp_section(m: Any, ctx: Context, name: str) -> Section:
    from .sweeps import lamp_profile, mitsuba_spot_profile

    lamp = m.data["lamp"]
    fit = lamp["fit"]
    a = np.linspace(0.0, fit["edge_deg"] * 1.15, 47)
    series = {"lamp (far field)": lamp_profile(a, lamp["radius"], lamp["depth"], lamp["aperture"]),
              f"cos^f, f = {fit['cos_f_exponent']:.1f}": np.where(a < fit["edge_deg"],
                                                                  np.cos(np.radians(a)) ** fit["cos_f_exponent"], 0.0),
              "Mitsuba spot, fitted": mitsuba_spot_profile(a, fit["mitsuba_beam_deg"], fit["mitsuba_cutoff_deg"])}
    path, rel = ctx.figure_path(name, "lamp_profile.png")
    plots.save_line_plot(path, a, series, "angle from the axis α (°)", "I(α) / I₀", "a disc behind an aperture")
    images = m.images["lamp"]
    ref = images["Mitsuba lamp"]
    path2, rel2 = ctx.figure_path(name, "lamp_images.png")
    plots.save_image_grid(path2, [np.nan_to_num(v) for v in images.values()], list(images), plots.auto_exposure(ref))
    rows = [[k, _pct(v["mean"]), _pct(v["max"]), _pct(v["bias"]), f"{v['agreement']['pooled_z']:+.2f}"]
            for k, v in lamp["models"].items()]
    return Section("A real lamp: a disc behind an aperture", [
        f"A disc of radius {lamp['radius'] * 100:g} cm at the closed end of a black tube {lamp['depth'] * 100:g} cm "
        f"deep and {lamp['aperture'] * 100:g} cm in radius: its far-field intensity is the disc area seen through the "
        f"mouth, I(α) = L cos α · A(h tan α), which ends at {fit['edge_deg']:.1f}° with a soft edge. Spot models "
        "fitted to it (least squares, solid-angle weighted) placed at the mouth with I₀ = L π r², and the 16×16 "
        "grid over the disc with the tube's shadow rays, against Mitsuba's render."],
        figures=[Figure(rel, "lamp profile and fitted spots", 520), Figure(rel2, "render and models", 720)],
        tables=[Table(["model", "mean", "max", "bias", "pooled z"], rows)])


def linearity_section(m: Any, ctx: Context, name: str) -> Section:
    lin = m.data["linearity"]
    path, rel = ctx.figure_path(name, "linearity_z.png")
    plots.save_heatmap(path, m.images["linearity_z"], "all lights vs sum of single renders", "z")
    t = lin["test"]
    return Section("Lights add linearly", [
        "Per-pixel z of the four-light render against the sum of the single renders; pooled z of the image "
        f"total {t['pooled_z']:+.2f} (bound ±{t['bias_bound']:g}), max |z| {t['max_abs_z']:.2f} (Šidák critical "
        f"{t['critical_z']:.2f}, α = 0.01, {t['pixels']} pixels)."], figures=[Figure(rel, "z map", 420)])


def sections(m: Any, ctx: Context, name: str) -> list[Section]:
    return [references_section(m, ctx, name), techniques_section(m, ctx, name), attenuation_section(m, ctx, name),
            standin_section(m, ctx, name), grid_section(m, ctx, name), spot_section(m, ctx, name),
            lamp_section(m, ctx, name), linearity_section(m, ctx, name)]
