"""Report sections of the ``lights`` experiment: images, error maps, curves and tables (no computation)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...figures import plots
from ...local_models import light as family
from ...scenes import light_scenes as ls
from ..base import Context, Figure, Section, Table, settings_json
from ..formatting import pct_fixed as _pct
from ..formatting import pm
from ..techniques import technique_entry
from .compute import Measurements
from .settings import NAME, Settings
from .sweeps import lamp_profile, mitsuba_spot_profile


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
            rows.append([tech, kind, *(pm(met[k]["value"], met[k]["uncertainty"], 3, fixed=True)
                                       for k in ("mean", "max", "bias")), _pct(met["mismatch"]["value"], 3)])
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
    table = Table(["technique", "light", "mean (%)", "max (%)", "bias (%)", "mismatch (%)"], rows)
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
        tables=[Table(["technique", "at 0.5 m (%)", "at 1 m (%)", "at 2 m (%)", "at 5 m (%)", "at 10 m (%)",
                       "best scale (×)", "max error after scale (%)"],
                      rows)])


def standin_section(m: Any, ctx: Context, name: str) -> Section:
    st = m.data["standin"]
    x = np.asarray(st["ratios"])
    series = {k: np.asarray(st[k]["max_rel"], dtype=np.float64) for k in ("rectangle", "disk", "sphere")}
    path, rel = ctx.figure_path(name, "point_standin.png")
    plots.save_line_plot(path, x, {k: np.maximum(v, 1e-9) for k, v in series.items()}, "distance / light size",
                         "max relative error", "one point light for an area light", logx=True, logy=True,
                         percent=True, hlines={"1 %": 0.01})
    rows = [[k, "n/a" if st[k]["ratio_within_1pct"] is None else f"{st[k]['ratio_within_1pct']:.4f} ± {st['xtol']:g}",
             "n/a" if st[k]["crossing"]["grid_node"] is None else f"{st[k]['crossing']['grid_node']:.4g}",
             f"{st[k]['extent']:.3g} m", st[k]["skipped_receivers"]] for k in ("rectangle", "disk", "sphere")]
    return Section("When a point light stands in for an area light", [
        "Worst relative error over receivers at " + standin_receivers_text(st) + ". Rectangle and disc: a "
        "cosine-lobe point I = L·A·cos ψ at the centre (the n = 1 grid); sphere: an isotropic point I = π r² L. "
        "References: Lambert's formula (rectangle), the cap formula (sphere), the coaxial-disc configuration factors "
        "(disc); receivers whose horizon cuts a flat light are skipped. The crossing is the last root of the "
        "max-over-receivers error − 1 % (continuous, not smooth), bracketed on the grid and refined by Brent's "
        f"method on the closed forms to ± {st['xtol']:g} in d/size; the grid node is the first swept ratio past it."],
        figures=[Figure(rel, "max relative error vs distance / size", 520)],
        tables=[Table(["light", "d/size for ≤ 1 % (–)", "first grid node past it (–)", "size (m)",
                       "receivers skipped (count)"], rows)])


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
        tables=[Table(["light", "lit (%)", "penumbra (%)", "umbra (%)", "total (%)", "penumbra slope (–)",
                       "penumbra area (px)", "fine grid vs Mitsuba: pooled z / max |z| (–)"], rows,
                      f"errors at n = {gs['n'][-1]}")])


def spot_section(m: Any, ctx: Context, name: str) -> Section:
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
        tables=[Table(["model", "mean (%)", "max (%)", "bias (%)", "pooled z (–)"], rows)])


def linearity_section(m: Any, ctx: Context, name: str) -> Section:
    lin = m.data["linearity"]
    path, rel = ctx.figure_path(name, "linearity_z.png")
    plots.save_heatmap(path, m.images["linearity_z"], "all lights vs sum of single renders", "z")
    t = lin["test"]
    return Section("Lights add linearly", [
        "Per-pixel z of the four-light render against the sum of the single renders; pooled z of the image "
        f"total {t['pooled_z']:+.2f} (bound ±{t['bias_bound']:g}), max |z| {t['max_abs_z']:.2f} (Šidák critical "
        f"{t['critical_z']:.2f}, α = 0.01, {t['pixels']} pixels)."], figures=[Figure(rel, "z map", 420)])


def sections(m: Any, ctx: Context) -> list[Section]:
    name = NAME
    return [references_section(m, ctx, name), techniques_section(m, ctx, name), attenuation_section(m, ctx, name),
            standin_section(m, ctx, name), grid_section(m, ctx, name), spot_section(m, ctx, name),
            lamp_section(m, ctx, name), linearity_section(m, ctx, name)]


def _slope(x: float | None) -> str:
    return "n/a" if x is None else f"{x:.2f}"


def attenuation_findings(m: Measurements) -> list[str]:
    att, tech = m.data["attenuation"], m.data["techniques"]
    lo, hi = att["scene_distance_range"]
    out = []
    for name, a in att["techniques"].items():
        at = a["relative_error_at"]
        bias = tech[name]["metrics"].get("point", {}).get("bias", {}).get("value", float("nan"))
        out.append(f"{name}: E/E_(1/d²) − 1 = {at['1 m']:+.1%} at 1 m, {at['5 m']:+.1%} at 5 m, {at['10 m']:+.1%} at "
                   f"10 m; with the best single intensity scale ({a['best_scale']:.3g}×) still "
                   f"{a['best_scale_max_error']:.1%} off somewhere in the scene's {lo:.2f}–{hi:.2f} m; in the "
                   f"rendered scene its bias is {bias:+.1%}.")
    return out


def grid_findings(m: Measurements) -> list[str]:
    g, gs = m.data["grid"], m.data["grid_shadowed"]
    out = [f"n×n grid, unshadowed rectangle: max relative error {g['midpoint_max_rel'][0]:.2%} at n = 1, "
           f"{g['midpoint_max_rel'][-1]:.2e} at n = {g['n'][-1]}; slope {g['midpoint_slope']:.2f} (theory −2); "
           f"corner rule slope {g['corner_slope']:.2f} (theory −1)."]
    for kind in ls.AREA_KINDS:
        sh, sl, z = gs[kind], gs[kind]["slopes"], gs[kind]["mitsuba"]
        out.append(f"Shadowed {kind} grid against the {gs['reference_n']}² grid: penumbra mean error "
                   f"{sh['penumbra'][0]:.1%} at n = 1, {sh['penumbra'][-1]:.2%} at n = {gs['n'][-1]} (slope "
                   f"{_slope(sl['penumbra'])}), lit {sh['lit'][-1]:.2e} (slope {_slope(sl['lit'])}); the "
                   f"{gs['reference_n']}² grid vs Mitsuba: pooled z {z['pooled_z']:+.2f} (bound ±{z['bias_bound']:g}, "
                   f"relative bias {z['relative_bias']:+.2%}), max |z| {z['max_abs_z']:.2f} (critical "
                   f"{z['critical_z']:.2f}).")
    return out


def lamp_finding(lamp: dict[str, Any]) -> str:
    fit, mod = lamp["fit"], lamp["models"]
    z = mod["area_grid_shadowed"]["agreement"]
    return (f"A real lamp (disc r = {lamp['radius'] * 100:g} cm at the end of a {lamp['depth'] * 100:g} cm black tube "
            f"of radius {lamp['aperture'] * 100:g} cm, "
            f"beam edge {fit['edge_deg']:.1f}°): its far-field profile is matched by cos^f α with f = "
            f"{fit['cos_f_exponent']:.1f} (rms {fit['cos_f_rms']:.1%} of the peak) or by Mitsuba's linear spot with "
            f"beam {fit['mitsuba_beam_deg']:.1f}°, cutoff {fit['mitsuba_cutoff_deg']:.1f}° (rms "
            f"{fit['mitsuba_rms']:.1%}); rendered, the fitted cos^f spot is off by {mod['spot_cos_f']['mean']:.1%} on "
            f"average (max {mod['spot_cos_f']['max']:.0%}), the fitted linear spot by "
            f"{mod['spot_mitsuba']['mean']:.1%} "
            f"(max {mod['spot_mitsuba']['max']:.0%}), the 16² grid through the tube by "
            f"{mod['area_grid_shadowed']['mean']:.2%} ± {mod['area_grid_shadowed']['mean_uncertainty']:.2%} "
            f"(pooled z {z['pooled_z']:+.2f}).")


def standin_receivers_text(st: dict[str, Any]) -> str:
    """The receiver set behind the stand-in figures, in words."""
    return ("polar angles " + ", ".join(f"{p:g}°" for p in st["polar_deg"]) + " from the light's normal, normals "
            "tilted " + ", ".join(f"{t:+g}°" if t else "0°" for t in st["tilt_deg"])
            + " from the direction to the light in that plane")


def standin_finding(st: dict[str, Any], kind: str) -> str:
    c, ind = st[kind]["crossing"], st[kind]["independent"]
    head = f"A single point light stands in for the {kind} within 1 % (worst of the receivers at "
    if c["root"] is None:
        where = (f"≤ {c['grid_node']:.3g} (the first ratio swept)" if c["below_grid"]
                 else "> the largest ratio swept")
        return head + standin_receivers_text(st) + f") beyond d/size {where} (size = largest dimension)."
    return (head + standin_receivers_text(st) + f") beyond d/size = {c['root']:.4f} ± {c['xtol']:g} (size = largest "
            f"dimension; the last root of the max-over-receivers error − 1 %, which is continuous but not smooth, "
            f"bracketed on the sweep's grid in [{c['bracket'][0]:.4f}, {c['bracket'][1]:.4f}] and refined by Brent's "
            f"method on the closed form; beyond it the error stays ≤ {c['max_beyond']:.2%} at every grid node; the "
            f"first grid node past it is {c['grid_node']:.4g}; a bisection on an independent quadrature reference "
            f"puts it at {ind['root']:.4f}).")


def findings(m: Measurements) -> list[str]:
    out = attenuation_findings(m)
    st = m.data["standin"]
    out += [standin_finding(st, kind) for kind in ls.AREA_KINDS]
    out += grid_findings(m)
    sp, tech = m.data["spot"], m.data["techniques"]
    cos_f = tech.get("spot_cos_f", {}).get("metrics", {}).get("spot", {})
    out.append(f"Mitsuba's spot (beam {sp['beam_deg']:g}°, cutoff {sp['cutoff_deg']:g}°) is best matched by cos^f α "
               f"with f = {sp['fitted_exponent']:.1f} (rms {sp['fit_rms']:.1%} of the peak over the cone)"
               + (f"; rendered, that cos^f spot is off by {cos_f['mean']['value']:.1%} on average and "
                  f"{cos_f['max']['value']:.0%} at worst (of the mean lit radiance)." if cos_f else "."))
    out.append(lamp_finding(m.data["lamp"]))
    grid = {k: tech.get(k, {}).get("metrics", {}) for k in ("area_grid", "area_grid_shadowed")}
    if all(grid.values()):
        n = m.settings["technique_grid"]
        out.append(f"The {n}×{n} grid over the scene, without its shadow rays: bias " + ", ".join(
            f"{k} {v['bias']['value']:+.1%}" for k, v in grid["area_grid"].items()) + "; with them: " + ", ".join(
            f"{k} {v['bias']['value']:+.2%} (mean {v['mean']['value']:.2%} ± {v['mean']['uncertainty']:.2%})"
            for k, v in grid["area_grid_shadowed"].items()) + ".")
    two = tech.get("point_two_sided", {}).get("metrics", {}).get("point", {})
    if two:
        out.append(f"Two-sided lighting on this closed geometry with shadow rays: max difference from Mitsuba "
                   f"{two['max']['value']:.1e} — a back face is always shadowed by its own object.")
    lin, ms = m.data["linearity"]["test"], m.data["model_sum"]
    out.append(f"Lights add linearly: pooled z = {lin['pooled_z']:+.2f} (bound ±{lin['bias_bound']:g}), max |z| = "
               f"{lin['max_abs_z']:.2f} (critical {lin['critical_z']:.2f}); the local models summed are "
               f"{ms['mean']:.2%} ± {ms['mean_uncertainty']:.2%} off on average (bias {ms['bias']:+.2%}).")
    return out


SUMMARY = ("Directional, point (inverse square and engine attenuations), spot (cos^f and Mitsuba's "
           "profile) and area lights as n×n point grids, against Mitsuba's direct lighting.")


def summary(m: Any) -> str:
    return SUMMARY


def reported_settings(s: Settings, m: Any, ctx: Context) -> dict[str, Any]:
    """``experiments.lights.settings``: the settings without the two long sweep grids."""
    return settings_json(s, omit=("ratios", "distances"))


def data(m: Any) -> dict[str, Any]:
    return {k: v for k, v in m.data.items() if k != "techniques"}


def techniques(m: Any) -> dict[str, Any]:
    """``experiments.lights.techniques.<name>``: metrics per light type the technique models."""
    return {tech.name: technique_entry(tech, m.data["techniques"][tech.name]["metrics"],
                                       lights=m.data["techniques"][tech.name]["lights"]) for tech in family}
