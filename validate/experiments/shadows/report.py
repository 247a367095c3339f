"""Report sections, summary and JSON data of the ``shadows`` experiment (figures and tables only).

Every registered shadow technique gets a column in the image grid, an error map, a row per light
radius in the comparison table and a column in the resolution table.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...figures import plots
from ...local_models import shadow
from ...metrics import shadow_error as se
from ..base import Context, Figure, Section, Table, settings_json
from ..formatting import pct_fixed as pct
from ..formatting import pm
from ..techniques import technique_entry
from .claims import (
    PENUMBRA_SHARE_X,
    Z_ONE_SIDED_99,
    error_metrics,
    light_distance,
    technique_metrics,
)
from .compute import Measurements
from .settings import NAME, Settings

ERROR_VMAX = 0.5  # error maps clip at 50 % of L_norm


def summary(m: Measurements) -> str:
    s = m.settings
    return ("A ground plane with a floating sphere, a box, a thin pole and steps under a disc light of radius "
            f"{m.r_pt:g}–{m.r_max:g} m, 4 m up. Mitsuba's direct lighting at the pixel centres ({s.passes} × {s.spp} "
            f"spp, {s.width}×{s.height}) is the reference; every registered shadow technique "
            f"({', '.join(t.name for t in m.techniques)}) shades Mitsuba's G-buffer with the closed-form disc "
            "irradiance times its visibility V′ from a shadow map. Errors are |ΔY| relative to the mean lit radiance, "
            "split into lit, penumbra and umbra regions by the reference's visible fraction of the disc.")


def data(m: Measurements) -> dict[str, Any]:
    ref = m.frame.refs[m.r_pt]
    return {"reference": ref.settings() | {"width": m.settings.width, "height": m.settings.height},
            "radii": m.radii,
            "resolution_sweep": {str(q): {f"{r:g}": {n: e.to_json() for n, e in d.items()} for r, d in rr.items()}
                                 for q, rr in m.sweep.items()},
            "bias_sweep": m.bias, "kernel_sweep": m.kernels, "convergence_rate": m.rate,
            "band_test": {k: v for k, v in m.band.items() if not k.startswith("_")},
            "pcss_without_receiver_plane_largest_light": m.pcss_flat.to_json() if m.pcss_flat else None,
            "light_bleeding_case": m.bleeding,
            "flip_noise_floor": {f"{r:g}": m.frame.flip_noise[r] for r in m.settings.flip_radii if r in m.frame.refs}}
    # (shadow-map build times are not results: results.json is a function of the inputs; speed is `validate bench`)


def sections(m: Measurements, ctx: Context) -> list[Section]:
    return [Section("Images", [
                "Reference (Mitsuba direct lighting at the pixel centres) and every shadow technique for the largest "
                "light, with per-pixel error maps (|ΔY| / L_norm, clipped at 50 %); then the near-point light at the "
                "lowest and highest shadow-map resolutions and the mask of the edge-band claim."],
                gallery=[_technique_row(m, ctx, m.r_max), *_near_point_row(m, ctx)]),
            Section("Curves", [
                "Error against shadow-map resolution, polygon-offset bias, PCF kernel and light radius. The penumbra "
                "'share' is the penumbra pixels' summed error divided by all valid pixels (it grows with the "
                "penumbra's area); the penumbra 'mean' is the average over penumbra pixels."], figures=_curves(m, ctx)),
            Section("Tables", _table_notes(m), tables=[comparison_table(m), resolution_table(m), *_bias_table(m),
                                                          *_bleeding_table(m)])]


def _error_map(m: Measurements, ctx: Context, r: float, approx: np.ndarray, title: str, filename: str) -> Figure:
    e = se.pixel_error(m.frame.refs[r].radiance[m.frame.valid], approx, m.frame.norm[r])
    p, rel = ctx.figure_path(NAME, filename)
    plots.save_heatmap(p, m.frame.image(e, np.nan), title, "error", vmax=ERROR_VMAX, percent=True)
    return Figure(rel, title, 300)


def _technique_row(m: Measurements, ctx: Context, r: float) -> list[Figure]:
    d = m.settings.default_resolution
    tag = f"r{r:g}".replace(".", "p")
    names = [t.name for t in m.techniques]
    p, rel = ctx.figure_path(NAME, f"{tag}_{d}_images.png")
    plots.save_image_grid(p, [m.frame.refs[r].radiance] + [m.frame.image(m.images[(d, r, n)]) for n in names],
                          ["reference (Mitsuba)"] + names)
    row = [Figure(rel, f"r = {r:g} m, shadow map {d}²: reference and every technique (same exposure)")]
    return row + [_error_map(m, ctx, r, m.images[(d, r, n)], f"{n}: |ΔY| / L_norm (r = {r:g} m)",
                             f"{tag}_{d}_error_{n}.png") for n in names]


def _near_point_row(m: Measurements, ctx: Context) -> list[list[Figure]]:
    ress = sorted(m.sweep)
    lo, hi = ress[0], ress[-1]
    if (lo, m.r_pt, "hard") not in m.images or not m.band:
        return []
    img = {q: m.images[(q, m.r_pt, "hard")] for q in (lo, hi)}
    p, rel = ctx.figure_path(NAME, f"near_point_hard_{lo}_{hi}.png")
    plots.save_image_grid(p, [m.frame.refs[m.r_pt].radiance] + [m.frame.image(img[q]) for q in (lo, hi)],
                          ["reference", f"hard {lo}²", f"hard {hi}²"])
    row = [Figure(rel, f"near-point light (r = {m.r_pt:g} m): hard shadows at {lo}² and {hi}²")]
    row += [_error_map(m, ctx, m.r_pt, img[q], f"hard {q}²: |ΔY| / L_norm", f"near_point_error_hard_{q}.png")
            for q in (lo, hi)]
    cat = np.where(m.band["_band_image"][m.frame.valid], 2.0, np.where(m.band["_include"], 0.0, 1.0))
    p, rel = ctx.figure_path(NAME, f"near_point_band_{hi}.png")
    plots.save_heatmap(p, m.frame.image(cat, np.nan), f"edge-band claim mask ({hi}²): 0 tested, 1 penumbra/horizon, "
                       "2 one-texel band", "class", vmax=2.0, cmap="viridis")
    row.append(Figure(rel, "pixels tested by the edge-band claim (0) and excluded (1: reference penumbra or below the "
                           "horizon, 2: one-texel band)", 300))
    return [row]


def _curves(m: Measurements, ctx: Context) -> list[Figure]:
    figs = [_resolution_curve(m, ctx)]
    if m.bias:
        figs.append(_bias_curve(m, ctx))
    for key, kd in m.kernels.items():
        if isinstance(kd, dict) and "classic_penumbra" in kd:
            p, rel = ctx.figure_path(NAME, f"error_vs_pcf_kernel_r{key.replace('.', 'p')}.png")
            plots.save_line_plot(p, m.kernels["kernels"], {
                "PCF penumbra (classic)": kd["classic_penumbra"], "PCF penumbra (receiver plane)":
                kd["receiver_plane_penumbra"], "PCF total (classic)": kd["classic_total"],
                "PCF total (receiver plane)": kd["receiver_plane_total"]}, "PCF kernel k (k×k bilinear taps)",
                "|ΔY| / L_norm", f"PCF kernel, r = {key} m, {m.kernels['resolution']}²", logx=True, percent=True,
                hlines={"PCSS penumbra": kd["pcss_penumbra"]} if "pcss_penumbra" in kd else None)
            figs.append(Figure(rel, f"PCF kernel sweep, r = {key} m", 500))
    figs.append(_radius_curve(m, ctx))
    return figs


def _resolution_curve(m: Measurements, ctx: Context) -> Figure:
    ress = sorted(m.sweep)
    p, rel = ctx.figure_path(NAME, "error_vs_resolution.png")
    series = {f"{t.name}, r = {r:g} m": [m.sweep[q][r][t.name].total.mean for q in ress]
              for r in (m.r_pt, m.r_max) for t in m.techniques}
    noise = m.sweep[ress[-1]][m.r_pt][m.techniques[0].name].total.uncertainty if m.techniques else 0.0
    plots.save_line_plot(p, ress, series, "shadow-map resolution (texels per side)", "total |ΔY| / L_norm",
                         "Error vs shadow-map resolution", logx=True, logy=True, percent=True,
                         hlines={f"reference noise (r = {m.r_pt:g} m)": noise})
    return Figure(rel, "total error vs resolution, near-point and largest light", 500)


def _bias_curve(m: Measurements, ctx: Context) -> Figure:
    b = m.bias
    nz = [i for i, x in enumerate(b["scale"]) if x > 0]

    def gaps(key: str) -> list[float]:  # zeros leave gaps on a log axis
        return [b[key][i] if b[key][i] > 0 else float("nan") for i in nz]

    p, rel = ctx.figure_path(NAME, f"error_vs_bias_{b['resolution']}.png")
    plots.save_line_plot(p, [b["factor"][i] for i in nz], {
        "total error": gaps("total"), "false shadow (acne), share of lit area": gaps("false_shadow"),
        "false light (peter-panning), share of umbra": gaps("false_light")},
        "glPolygonOffset factor (units = 2 × factor)", "fraction",
        f"Bias sweep, hard {b['resolution']}², r = {b['radius']:g} m", logx=True, logy=True, percent=True)
    return Figure(rel, "acne vs peter-panning as the polygon offset grows", 500)


def _radius_curve(m: Measurements, ctx: Context) -> Figure:
    d = m.settings.default_resolution
    p, rel = ctx.figure_path(NAME, "error_vs_light_radius.png")
    series = {f"{t.name} penumbra {kind}": [getattr(m.at_default(r)[t.name].regions["penumbra"], kind) for r in m.radii]
              for kind in ("share", "mean") for t in m.techniques}
    plots.save_line_plot(p, m.radii, series, "light radius r (m)", "|ΔY| / L_norm",
                         f"Penumbra error vs light radius ({d}²)", logx=True, logy=True, percent=True,
                         hlines={f"{pct(PENUMBRA_SHARE_X, 0)} share": PENUMBRA_SHARE_X})
    return Figure(rel, "penumbra error vs light radius: mean over penumbra pixels and share of the image", 500)




def comparison_table(m: Measurements) -> Table:
    rows = []
    for r in m.radii:
        for t in m.techniques:
            e = m.at_default(r)[t.name]
            v = error_metrics(e, m.frame.flip_noise[r])
            cell = {k: pm(*v[k], 2, fixed=True) for k in ("total", "lit", "penumbra", "umbra", "false_shadow",
                                                          "false_light", "leak")}
            rows.append([f"{r:g}", t.name, cell["total"], cell["lit"],
                         f"{cell['penumbra']} ({e.regions['penumbra'].pixels} px)", cell["umbra"],
                         cell["false_shadow"], cell["false_light"], cell["leak"],
                         f"{v['flip'][0]:.4f} ± {v['flip'][1]:.4f}" if np.isfinite(v["flip"][0]) else "—",
                         str(t.meta.get("memory_bytes_per_texel", "—"))])
    return Table(["r (m)", "technique", "total (%)", "lit (%)", "penumbra (%)", "umbra (%)", "false shadow, acne (%)",
                  "false light, peter-panning (%)", "light leak (%)", "FLIP (–)", "memory per texel (B)"], rows,
                 f"Every registered shadow technique at {m.settings.default_resolution}², per light radius (|ΔY| / "
                 "L_norm ± the reference's mean σ / L_norm; false shadow: share of the lit area with V′ < ½; false "
                 "light: share of the umbra with V′ > ½, ± binomial standard error; light leak: mean V′ over the "
                 "umbra; FLIP: mean HDR-FLIP ± the reference's own noise floor, at r = "
                 f"{', '.join(f'{r:g}' for r in m.settings.flip_radii)} m).")


def resolution_table(m: Measurements) -> Table:
    ress = sorted(m.sweep)
    names = [t.name for t in m.techniques]
    rows = [[str(q)] + [pct(m.sweep[q][m.r_pt][n].total.mean, 3) for n in names] +
            [pct(m.sweep[q][m.r_max][n].regions["penumbra"].mean) for n in names] for q in ress]
    return Table(["resolution (texels)"] + [f"{n} total, r = {m.r_pt:g} m (%)" for n in names] +
                 [f"{n} penumbra, r = {m.r_max:g} m (%)" for n in names], rows,
                 "Every technique vs shadow-map resolution.")


def _bias_table(m: Measurements) -> list[Table]:
    b = m.bias
    if not b:
        return []
    rows = [[f"({f:g}, {u:g})", pct(t, 3), pct(a), pct(pp)] for f, u, t, a, pp in
            zip(b["factor"], b["units"], b["total"], b["false_shadow"], b["false_light"], strict=True)]
    return [Table(["glPolygonOffset factor, units (–)", "total error (%)", "false shadow, lit area (%)",
                   "false light, umbra (%)"],
                  rows, f"Hard shadows, {b['resolution']}², r = {b['radius']:g} m")]


def _bleeding_table(m: Measurements) -> list[Table]:
    b = m.bleeding
    cases = [c for c in ("far apart", "contact") if c in b]
    if not cases:
        return []
    rows = [[t.name] + [f"{pct(b[c][t.name]['leak'], 3)} / {pct(b[c][t.name]['leak_area'], 1)}" for c in cases]
            for t in m.techniques if all(t.name in b[c] for c in cases)]
    return [Table(["technique"] + [f"{c}: occluders at {b[c]['depths'][0]:g} / {b[c]['depths'][1]:g} m (%)"
                                   for c in cases],
                  rows, f"Light bleeding on a synthetic {b['resolution']}² map: mean V′ / share of receivers with "
                        f"V′ > 0.1, receivers at {b['receiver_depth']:g} m behind both occluders (exact V = 0).")]


def _table_notes(m: Measurements) -> list[str]:
    if not m.band:
        return []
    t, b = m.band["outside"], m.band
    return [f"Edge-band claim detail: {t['exceeded']} of {t['tested']} tested pixels exceed the t bound "
            f"({t['t_bound']:.2f} σ); inside the band and penumbra {b['inside_band']['exceeded']} of "
            f"{b['inside_band']['tested']} do. One texel = {b['texel_tan']:.2e} in the light's tan plane."]


def techniques(m: Measurements) -> dict[str, Any]:
    """``ExperimentResult.techniques``: every metric of every technique at every radius, ± uncertainty."""
    return {t.name: technique_entry(t, technique_metrics(m, t.name),
                                    resolution=m.settings.default_resolution,
                                    memory_bytes_per_texel=t.meta.get("memory_bytes_per_texel"))
            for t in m.techniques}



def findings(m: Measurements) -> list[str]:
    return [f for f in (_resolution_finding(m), _bias_finding(m), _radius_finding(m), _pcss_finding(m),
                        _lit_finding(m), _leak_finding(m), _bleeding_finding(m), *_technique_findings(m)) if f]


def _resolution_finding(m: Measurements) -> str:
    if "hard" not in shadow:
        return ""
    ress = sorted(m.sweep)
    e = [m.sweep[q][m.r_pt]["hard"] for q in ress]
    txt = (f"Resolution (near-point light, r = {m.r_pt:g} m): the hard map's total error falls from "
           f"{pct(e[0].total.mean)} at {ress[0]}² to {pct(e[-1].total.mean)} at {ress[-1]}² of the mean lit radiance "
           f"(reference noise "
           f"±{pct(e[-1].total.uncertainty, 3)}); false shadow {pct(e[0].false_shadow)} → {pct(e[-1].false_shadow)}.")
    if m.rate:
        txt += (f" On a {m.rate['grid_side']}² ground grid the misclassified cells fall {m.rate['counts']} "
                f"(slope {m.rate['slope']:.2f} ± {m.rate['stderr']:.2f}; first-order theory −1).")
    return txt


def _bias_finding(m: Measurements) -> str:
    bias = m.bias
    if not bias:
        return ""
    tot = np.asarray(bias["total"])
    k = int(np.argmin(tot))
    txt = (f"Bias ({bias['resolution']}², near-point light, hard): total error is smallest, {pct(tot[k], 3)} ± "
           f"{pct(bias['total_uncertainty'][k], 3)}, at glPolygonOffset({bias['factor'][k]:g}, {bias['units'][k]:g})")
    i_def = bias["scale"].index(1.0) if 1.0 in bias["scale"] else None
    if i_def is not None and i_def != k:
        txt += f"; the Red Book's (2, 4) gives {pct(tot[i_def], 3)}"
        if tot[i_def] - tot[k] < bias["total_uncertainty"][i_def] + bias["total_uncertainty"][k]:
            txt += " (a difference within the reference's uncertainty)"
    elif i_def == k:
        txt += ", the Red Book's own choice"
    if bias["scale"][0] == 0.0:
        txt += f"; no bias leaves acne on {pct(bias['false_shadow'][0], 1)} of the lit area (error {pct(tot[0], 1)})"
    return txt + (f"; ({bias['factor'][-1]:g}, {bias['units'][-1]:g}) detaches shadows: "
                  f"{pct(bias['false_light'][-1], 1)} of the umbra turns lit (error {pct(tot[-1], 2)}).")


def crossing(x: list[float], y: list[float], level: float) -> float | None:
    """First x where y rises through ``level`` (log-linear interpolation in x), None if it never does."""
    for i in range(len(x) - 1):
        if y[i] <= level < y[i + 1]:
            t = (level - y[i]) / (y[i + 1] - y[i])
            return float(math.exp(math.log(x[i]) + t * (math.log(x[i + 1]) - math.log(x[i]))))
    return float(x[0]) if y and y[0] > level else None


def _radius_finding(m: Measurements) -> str:
    d = m.settings.default_resolution
    share = {t.name: [m.at_default(r)[t.name].regions["penumbra"].share for r in m.radii] for t in m.techniques}
    others = ", ".join(f"{n} {pct(v[-1])}" for n, v in share.items() if n != "hard")
    if "hard" not in share:
        return f"Light radius ({d}²): penumbra error share at r = {m.r_max:g} m: {others}."
    x = crossing(m.radii, share["hard"], PENUMBRA_SHARE_X)
    if x is None:
        return (f"Light radius ({d}²): hard shadows' penumbra error stays below {pct(PENUMBRA_SHARE_X, 0)} of the "
                f"mean lit radiance (image average) up to r = {m.r_max:g} m; {others}.")
    lo = max((r for r in m.radii if r <= x), default=m.radii[0])
    hi = min((r for r in m.radii if r >= x), default=m.radii[-1])
    return (f"Light radius ({d}²): above r ≈ {x:.2g} m (r/d ≈ {x / light_distance():.2g}; log-linear interpolation "
            f"between the swept radii {lo:g} and {hi:g} m, not a refined root: every point is a path-traced "
            f"reference) hard shadows' penumbra error exceeds {pct(PENUMBRA_SHARE_X, 0)} of the mean lit radiance "
            f"averaged over the image; at r = {m.r_max:g} m it is {pct(share['hard'][-1])} ({others}).")


def _pcss_finding(m: Measurements) -> str:
    kd = m.kernels.get(f"{m.r_max:g}", {})
    if "difference" not in kd:
        return ""
    d = m.settings.default_resolution
    at = m.at_default(m.r_max)
    ship = "; ".join(f"{n} {pct(at[n].regions['penumbra'].mean)}" for n in ("hard", "pcf", "pcss") if n in at)
    rp = ", receiver-plane depth" if kd["best_receiver_plane"] else ""
    verdict = "beats" if kd["difference"] - Z_ONE_SIDED_99 * kd["difference_stderr"] > 0 else "does not beat"
    txt = (f"PCSS vs the best fixed PCF kernel (r = {m.r_max:g} m, {m.kernels['resolution']}²): PCSS "
           f"{pct(kd['pcss_penumbra'])} penumbra error against {pct(kd['best_penumbra'])} for PCF "
           f"{kd['best_kernel']}×{kd['best_kernel']}{rp} ({kd['best_penumbra'] / kd['pcss_penumbra']:.2f}×; paired "
           f"difference {pct(kd['difference'])} ± {pct(kd['difference_stderr'])}): PCSS {verdict} it, and needs no "
           f"per-light tuning. As shipped at {d}²: {ship}.")
    if m.pcss_flat is not None and "pcss" in at:
        txt += (f" Without receiver-plane depth PCSS's penumbra error is {pct(m.pcss_flat.regions['penumbra'].mean)} "
                f"and its false-shadow area {pct(m.pcss_flat.false_shadow)} (with: {pct(at['pcss'].false_shadow)}).")
    return txt


def _lit_finding(m: Measurements) -> str:
    lit = [m.at_default(r)[m.techniques[0].name].regions["lit"] for r in (m.r_max, m.r_pt)] if m.techniques else []
    if not lit:
        return ""
    return (f"Unoccluded term: in the fully lit region every technique shares the closed-form disc irradiance's error, "
            f"{pct(lit[0].mean)} ± {pct(lit[0].uncertainty)} at r = {m.r_max:g} m (r/d = "
            f"{m.r_max / light_distance():.2g}; {pct(lit[1].mean, 3)} at r = {m.r_pt:g} m) unless its V′ < 1 there: "
            "the floor no shadow filter removes.")


def _leak_finding(m: Measurements) -> str:
    names = [t.name for t in m.techniques if t.meta.get("upper_bound")]
    if not names:
        return ""
    at = m.at_default(m.r_pt)
    parts = ", ".join(f"{n} {pct(at[n].leak)} ± {pct(at[n].leak_uncertainty)}" for n in ["hard", *names] if n in at)
    mem = ", ".join(f"{t.name} {t.meta.get('memory_bytes_per_texel')} B" for t in m.techniques
                    if t.meta.get("memory_bytes_per_texel"))
    return (f"Filterable maps (5×5 Gauss + bilinear, {m.settings.default_resolution}², near-point light): light leaked "
            f"into the umbra (mean V′ there) {parts}. This scene has no receiver that is itself shadowed by a second, "
            "farther occluder inside one filter footprint (VSM's light-bleeding case; see the synthetic case "
            f"below). Memory per texel: {mem}.")


def _bleeding_finding(m: Measurements) -> str:
    b = m.bleeding
    if not b:
        return ""
    parts = []
    for case in ("far apart", "contact"):
        if case in b:
            za, zb = b[case]["depths"]
            vals = ", ".join(f"{n} {pct(v['leak'], 3)}" for n, v in b[case].items() if isinstance(v, dict))
            parts.append(f"occluders at {za:g} m and {zb:g} m ({case}): {vals}")
    txt = ("Light bleeding (synthetic map, every filter sees two occluders, receivers at "
           f"{b['receiver_depth']:g} m fully shadowed; mean V′ there): " + "; ".join(parts) + ".")
    contact = {n: v["leak"] for n, v in b.get("contact", {}).items() if n in ("vsm", "esm", "msm")}
    if len(contact) == 3:
        order = " < ".join(sorted(contact, key=contact.get))
        txt += (f" At contact the leak orders {order}" + (" — the published ordering (Annen et al. 2008 Fig. 1: ESMs "
                "avoid VSMs' leaks; Peters & Klein 2015: MSM reduces them)" if order == "msm < esm < vsm" else "") +
                "; VSM's Chebyshev bound leaks where the two depths meet (Donnelly & Lauritzen 2006 §3.2), ESM where "
                "the occluder nearly touches the receiver (e^(−c(t − d))).")
    return txt


def _technique_findings(m: Measurements) -> list[str]:
    builtin = {"hard", "pcf", "pcss"}
    out = []
    for t in m.techniques:
        if t.name in builtin:
            continue
        e = m.at_default(m.r_max)[t.name]
        out.append(f"{t.name} (r = {m.r_max:g} m, {m.settings.default_resolution}²): total {pct(e.total.mean)}, "
                   f"penumbra {pct(e.regions['penumbra'].mean)}, umbra {pct(e.regions['umbra'].mean)}, light leak "
                   f"{pct(e.leak)} ± {pct(e.leak_uncertainty)} of the light in the umbra, false light "
                   f"{pct(e.false_light)}, acne {pct(e.false_shadow)}.")
    return out


def reported_settings(s: Settings, m: Measurements, ctx: Context) -> dict[str, Any]:
    """``experiments.shadows.settings``: the settings and the techniques measured."""
    return settings_json(s, techniques=[t.name for t in m.techniques])
