"""``sh9`` report: findings (sentences with numbers), sections (tables from the measurements, figures from
their arrays), and the ``results.json`` payload (summary, data, technique entries)."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from ...atomic import atomic_path
from ...figures import plots
from ...local_models import irradiance as irradiance_family
from ...local_models.irradiance import sh as shm
from ...metrics.irradiance_error import METRIC_NAMES
from ...metrics.published import PUBLISHED_TOLERANCE
from ...reference import pathtrace
from ...stats import measured_json
from ..base import Context, Figure, Section, Table
from ..formatting import col, pm
from ..formatting import pct as _pct
from ..techniques import error_stats_measured, technique_entry
from .claims import ATTAINS_BOUND, CMGEN, PAPER_MAX, PAPER_MEAN, ZH3_COMPARED, foreign_thresholds
from .compute import Measurements
from .settings import NAME

# Fixed margins of the error-vs-order plot (fractions of FIG_SIZE, 5 × 3.5 in): where constrained layout put the axes
# for these labels (measured: left 0.123, bottom 0.127, right 0.992, top 0.933), with 0.1 in more on the left for
# longer per-cent tick labels. Constrained layout measured every artist before the real draw: ~40 % of the plot's time.
ORDER_PLOT_MARGINS = {"left": 0.14, "right": 0.99, "bottom": 0.127, "top": 0.933}


def _save_png(path: Path, fig: Any, margins: dict[str, float] | None = None) -> None:
    """Write a :mod:`validate.figures.plots` figure as a PNG, with ``margins`` instead of its layout engine if given.
    Every axes title is pinned at y = 1 (where matplotlib's automatic placement leaves it when no x tick labels
    sit on top: the same pixels), which skips the per-draw search of every tick label's extent behind that
    placement (about a third of a log-axis plot's drawing time)."""
    if margins is not None:
        fig.set_layout_engine(None)
        fig.subplots_adjust(**margins)
    for ax in fig.axes:
        if ax.get_title() and ax.xaxis.get_ticks_position() not in ("top", "unknown") \
                and ax.xaxis.get_label_position() != "top":
            ax.set_title(ax.get_title(), fontsize=ax.title.get_fontsize(), y=1.0)
    with plots.FIGURE_LOCK, atomic_path(path, suffix=".png") as tmp:
        fig.savefig(tmp, format="png", dpi=plots.FIG_DPI, pil_kwargs={"compress_level": plots.PNG_COMPRESS_LEVEL})


def environment_figures(name: str, r: dict[str, Any], ctx: Context) -> list[Figure]:
    """Environment thumbnail, reference and SH9 spheres (one exposure), heat map, error vs order."""
    a = r["_arrays"]
    p_thumb, r_thumb = ctx.figure_path(NAME, f"{name}_env.png")
    plots.save_image(p_thumb, a["thumb"])
    exposure = plots.auto_exposure(a["sphere_reference"])
    p_ref, r_ref = ctx.figure_path(NAME, f"{name}_sphere_reference.png")
    p_sh, r_sh = ctx.figure_path(NAME, f"{name}_sphere_sh9.png")
    plots.save_image(p_ref, a["sphere_reference"], exposure=exposure)
    plots.save_image(p_sh, a["sphere_sh9"], exposure=exposure)
    p_err, r_err = ctx.figure_path(NAME, f"{name}_error_flux.png")
    _save_png(p_err, plots.heatmap_figure(a["error_grid"], title=f"{name}: |E_SH9 − E| / Φ (all normals, lat-long)",
                                          label="error / total flux", percent=True))
    sweep = r["order_sweep"]
    p_ord, r_ord = ctx.figure_path(NAME, f"{name}_error_vs_order.png")
    fig = plots.line_plot_figure(sweep["lmax"], {"mean": np.array(sweep["mean"]), "max": np.array(sweep["max"])},
                                 xlabel="SH order l_max", ylabel="|E′ − E| / Φ (luminance)",
                                 title=f"{name}: error vs SH order", logy=True, percent=True,
                                 hlines={"paper mean 1 %": PAPER_MEAN, "paper max 5 %": PAPER_MAX})
    _save_png(p_ord, fig, ORDER_PLOT_MARGINS)
    return [Figure(r_thumb, f"{name}: environment (tonemapped lat-long)", 256),
            Figure(r_ref, "reference sphere (Mitsuba quadrature), E/π", 160),
            Figure(r_sh, "SH9 sphere, E′/π (same exposure)", 160),
            Figure(r_err, "SH9 error heat map, % of Φ", 300),
            Figure(r_ord, "error vs SH order", 300)]


def technique_figures(name: str, r: dict[str, Any], ctx: Context) -> list[Figure]:
    """Every registered technique on this environment: its sphere beside the reference (one exposure) and
    its error map |Y(E′) − Y(E)| / Φ_Y on one colour scale."""
    a = r["_arrays"]
    techs = list(a.get("technique_spheres", {}))
    if not techs:
        return []
    p_sph, r_sph = ctx.figure_path(NAME, f"{name}_technique_spheres.png")
    plots.save_image_grid(p_sph, [a["sphere_reference"]] + [a["technique_spheres"][t] for t in techs],
                          ["reference"] + techs, exposure=plots.auto_exposure(a["sphere_reference"]), columns=7)
    p_err, r_err = ctx.figure_path(NAME, f"{name}_technique_errors.png")
    plots.save_heatmap_grid(p_err, [a["technique_errors"][t] for t in techs], techs,
                            label="|Y(E′) − Y(E)| / Φ_Y", percent=True, columns=6)
    return [Figure(r_sph, f"{name}: every registered irradiance technique, E′/π (same exposure as the reference)"),
            Figure(r_err, f"{name}: error of every technique on the sphere, % of Φ (one colour scale)")]


def crosscheck_figures(name: str, d: dict[str, Any], ctx: Context) -> list[Figure]:
    a = d["_arrays"]
    exposure = plots.auto_exposure(a["render"])
    p1, r1 = ctx.figure_path(NAME, f"{name}_pathtraced.png")
    p2, r2 = ctx.figure_path(NAME, f"{name}_pathtrace_quadrature.png")
    p3, r3 = ctx.figure_path(NAME, f"{name}_pathtrace_z.png")
    plots.save_image(p1, a["render"], exposure=exposure)
    plots.save_image(p2, a["quadrature"], exposure=exposure)
    absz = np.abs(a["z_image"])
    worst = np.where(np.isnan(absz).all(axis=-1), np.nan, np.nan_to_num(absz, nan=0.0).max(axis=-1))
    plots.save_heatmap(p3, worst, title=f"{name}: |z| per pixel (worst channel)", label="|z|", vmax=d["critical_z"])
    passes = d["settings"]["passes"]
    return [Figure(r1, f"{name}: path-traced Lambertian sphere (mean of {passes} passes)", 160),
            Figure(r2, "quadrature E/π over each pixel's footprint (same exposure)", 160),
            Figure(r3, f"|z| per pixel; colour bar ends at the critical value {d['critical_z']:.2f}", 300)]


def metric_section(m: Measurements) -> Section:
    rows = []
    for name, r in m.environments.items():
        e = r["errors"]
        rows.append([name, r["kind"], f"{r['flux_luminance']:.4g}", _pct(r["convergence"]),
                     *(pm(e["flux_luminance"][st], e["flux_luminance"][f"{st}_uncertainty"]) for st in ("mean", "max")),
                     _pct(e["flux_rgb"]["max"]),
                     _pct(e["relative"]["mean"]), _pct(e["relative"]["max"]), _pct(e["peak"]["mean"]),
                     _pct(e["peak"]["max"])])
    table = Table(["environment", "kind", "Φ_Y (W/m²)", "ref. convergence (%)", "flux mean (%)", "flux max (%)",
                   "flux max, worst RGB (%)", "relative mean (%)", "relative max (%)", "peak mean (%)",
                   "peak max (%)"], rows,
                  "SH9 error under every metric (definitions in README § Metrics).")
    return Section("Which metric reproduces the paper", [
        "R&H 2001 state that SH9 irradiance has average error < 1 % and maximum error < 5 % on their "
        "probes. Those figures are errors relative to the total incident flux Φ = ∫L dω: under that "
        "normalisation the error of any non-negative lighting is provably ≤ 3/32 = 9.375 % at every "
        "normal and ≤ 3.07 % on average, with equality for a directional light. Per-normal relative "
        "error (|E′−E|/E) and peak-normalised error (|E′−E|/max E) measure the same approximation more "
        "harshly and do not reproduce the paper's numbers."], tables=[table])


def published_section(m: Measurements) -> Section:
    rows = [[n, r["published"]["probe"], f"{r['published']['scale']:.4f}", f"{r['published']['max_deviation']:.4f}",
             "pass" if r["published"]["max_deviation"] < PUBLISHED_TOLERANCE else "FAIL"]
            for n, r in m.environments.items() if "published" in r]
    notes = [r["published_note"] for r in m.environments.values() if r.get("published_note")]
    return Section("Published coefficients (R&H prefilter convention)", [
        "Coefficients of the paper's probes computed in R&H's angular-map convention and compared with "
        "the published table after fitting one exposure factor per probe by least squares "
        f"(threshold ±{PUBLISHED_TOLERANCE})."] + notes,
        tables=[Table(["file", "table row", "exposure factor (×)", "max |c/s − table| (W/(m²·sr))", "within ±0.01?"],
                      rows)] if rows else [])


def technique_section(m: Measurements) -> Section:
    """One row per registered irradiance technique, one column per environment: flux_luminance
    mean / max, each ± uncertainty."""
    envs = list(m.environments)
    rows = []
    for tech in irradiance_family:
        row: list[Any] = [tech.name]
        for e in envs:
            st = m.environments[e]["models"].get(tech.name, {}).get("flux_luminance")
            row.append(" / ".join(pm(st[s], st[f"{s}_uncertainty"]) for s in ("mean", "max")) if st else "—")
        rows.append(row)
    return Section("Technique comparison (registered irradiance techniques)", [
        "Every technique registered in the irradiance family (validate.local_models.irradiance), built-in or "
        "plug-in, evaluated on every environment through the family's output contract: flux-normalised "
        "luminance error, mean / max, ± the reference's uncertainty. Declared thresholds become claims "
        "sh9.technique.<name>.<metric>, judged on the worst environment in the technique's scope."],
        tables=[Table(["technique"] + [col(e, "%") for e in envs], rows)])


def cmgen_section(m: Measurements) -> Section | None:
    """Per environment: the cut-off Filament cmgen's auto window picks, its weights, the Hölder bound of the
    resulting kernel, the windowed irradiance's minimum (chosen / rejected cut-off / no window), the error."""
    rows = []
    for name, r in m.environments.items():
        c = r.get("cmgen_auto")
        if c is None:
            continue
        st = r["models"].get("sh9_cmgen_auto", {}).get("flux_rgb")
        rej = "—" if c["rejected"] is None else f"{c['rejected']:.3f} ({_pct(-c['negative_rejected'])})"
        rows.append([name, f"{c['cutoff']:.3f}", f"({c['weights'][1]:.3f}, {c['weights'][2]:.3f})",
                     _pct(c["kernel_bound"]), _pct(st["max"]) if st else "—", _pct(-c["negative"]), rej,
                     _pct(-c["negative_unwindowed"])])
    if not rows:
        return None
    return Section("Filament cmgen's automatic SH window", [
        "cmgen --sh-window auto (its default; Filament CubemapSH::windowSH) multiplies band l of the irradiance SH "
        "by sinc⁴(πl/c) and bisects the cut-off c in [3, 13] per channel for the widest window whose windowed "
        "irradiance stays ≥ 0 on the whole sphere. Minima are over 20 000 normals, as fractions of Φ (worst "
        "channel); the error bound is the Hölder bound of the chosen window's kernel."],
        tables=[Table(["environment", "cut-off c (–)", "(w1, w2) (–)", "kernel bound (%)", "flux max, worst RGB (%)",
                       "min E′ / Φ (%)", "rejected c (–)", "min without window (%)"], rows)])


def crosscheck_section(m: Measurements, ctx: Context, gallery: list[list[Figure]] | None = None) -> Section | None:
    """The path-traced cross-check table and figures (``gallery``: the figures when already drawn, in
    ``m.crosschecks`` order)."""
    if not m.crosschecks:
        return None
    rows = [[n, d["n_pixels"], f"{d['max_abs_z']:.2f}", f"{d['critical_z']:.2f}", f"{d['mean_z']:+.3f}",
             f"{d['chi2_per_dof']:.3f}", _pct(d["max_rel_diff"]), _pct(d.get("rel_masked_fraction", 0.0)),
             "pass" if d["passed"] else "FAIL"]
            for n, d in m.crosschecks.items()]
    return Section("Reference cross-check: path-traced sphere", [
        "Before the quadrature judges anything it is judged itself: a white Lambertian sphere is path traced "
        "by Mitsuba (path, max_depth 2, independent passes) and every pixel is compared with the "
        "quadrature averaged over the pixel's footprint, z = (render − quadrature)/standard error. The relative "
        f"difference is taken only where the quadrature is ≥ {pathtrace.REL_FLOOR:g} of its mean over the tested "
        "pixels (a near-zero denominator measures nothing); 'masked' is the share of pixel-channels left out."],
        tables=[Table(["environment", "pixels (px)", "max |z| (–)", "critical z (–)", "mean z (–)", "χ²/dof (–)",
                       "max rel. diff (%)", "masked (%)", "result"], rows)],
        gallery=gallery if gallery is not None else [crosscheck_figures(n, d, ctx) for n, d in m.crosschecks.items()])


def _figure_task(item: tuple[str, str, dict[str, Any]], ctx: Context) -> list[list[Figure]]:
    """One ``ctx.map`` task of :func:`sections`: ``("environment", name, r)`` → [its environment figures, its
    technique figures]; ``("crosscheck", name, d)`` → [its cross-check figures]."""
    kind, name, r = item
    if kind == "crosscheck":
        return [crosscheck_figures(name, r, ctx)]
    return [environment_figures(name, r, ctx), technique_figures(name, r, ctx)]


def sections(m: Measurements, ctx: Context) -> list[Section]:
    """Every section; the figures are drawn by ``ctx.map`` tasks (one per environment and cross-check: on the
    Dask workers when there are any, which write them to ``ctx.out_dir``), in the order of the measurements."""
    coeff_rows = [[n] + [f"({c[0]:.3g}, {c[1]:.3g}, {c[2]:.3g})" for c in r["coefficients"]]
                  for n, r in m.environments.items()]
    items = [("crosscheck", n, d) for n, d in m.crosschecks.items()]
    items += [("environment", n, {"_arrays": r["_arrays"], "order_sweep": r["order_sweep"]})
              for n, r in m.environments.items()]
    drawn = ctx.map(partial(_figure_task, ctx=ctx), items, "sh9: figures")
    cross_gallery = [f[0] for f in drawn[:len(m.crosschecks)]]
    env_figs = drawn[len(m.crosschecks):]
    out = [s for s in [crosscheck_section(m, ctx, cross_gallery)] if s is not None]
    out += [
        metric_section(m), published_section(m), technique_section(m),
        *[x for x in [cmgen_section(m)] if x is not None],
        Section("SH9 coefficients (Mitsuba frame: y up, −z forward; L00, L1m1, L10, L11, L2m2, L2m1, L20, "
                "L21, L22)", tables=[Table(["environment"] + [col(n, "W/(m²·sr)") for n in shm.SH9_NAMES],
                                           coeff_rows)]),
        Section("Environments", ["Per environment: the environment, the reference sphere and the SH9 sphere "
                                 "(front view from +z, same exposure), the error over all normals and the "
                                 "error against SH order."],
                gallery=[f[0] for f in env_figs]),
        Section("Techniques on each environment", [
            "Every registered irradiance technique (built-in or plug-in) on the front-facing sphere of each "
            "environment: E′/π beside the reference at one exposure, and its error |Y(E′) − Y(E)| / Φ_Y per "
            "pixel on one colour scale per environment."],
                figures=[x for f in env_figs for x in f[1]]),
    ]
    return out


def technique_findings(m: Measurements) -> list[str]:
    """Per registered technique: its worst environment, and where it beats this experiment's SH9 (the
    R&H model analysed above, not a registry entry) by more than the reference's uncertainty."""
    out = []
    envs = m.environments
    names = list(dict.fromkeys(t for r in envs.values() for t in r["models"]))
    for name in names:
        rows = {e: r["models"][name]["flux_luminance"] for e, r in envs.items() if name in r["models"]}
        worst_mean = max(rows, key=lambda e: rows[e]["mean"])
        worst_max = max(rows, key=lambda e: rows[e]["max"])
        better = [e for e, st in rows.items()
                  if st["mean"] + st["mean_uncertainty"] < envs[e]["errors"]["flux_luminance"]["mean"]]
        shown = ", ".join(better[:5]) + (" …" if len(better) > 5 else "")
        out.append(f"technique {name}: worst flux-normalised error {_pct(rows[worst_mean]['mean'])} mean "
                   f"({worst_mean}) / {_pct(rows[worst_max]['max'])} max ({worst_max}); lower mean error than SH9 on "
                   f"{len(better)} of {len(rows)} environments" + (f" ({shown})" if better else "") + ".")
    return out


def _closer(a: dict, b: dict, stat: str, other: str) -> str:
    """'closer to the truth than <other> by x' / 'farther from the truth than <other> by x' / 'level with <other>'
    for flux_luminance stats a vs b (level: the difference is within the two uncertainties)."""
    diff = b[stat] - a[stat]
    unc = a[f"{stat}_uncertainty"] + b[f"{stat}_uncertainty"]
    if abs(diff) <= unc:
        return f"level with {other} (difference {_pct(abs(diff))} ≤ ±{_pct(unc)})"
    return f"{'closer to the truth than' if diff > 0 else 'farther from the truth than'} {other} by {_pct(abs(diff))}"


def zh3_environments(m: Measurements) -> list[str]:
    """grace_probe when present and the probe with the largest sun share (without probes: the built-in
    environment with the largest, other than near_directional, where stored ZH3 = SH9 by construction)."""
    envs = m.environments
    picked = [n for n in envs if n == "grace_probe"]
    probes = [n for n, r in envs.items() if r["kind"] == "probe"] or [n for n in envs if n != ATTAINS_BOUND]
    if not probes:
        return picked
    sunny = max(probes, key=lambda n: envs[n].get("sun_share", 0.0))
    return picked + [sunny] if sunny not in picked else picked


def zh3_findings(m: Measurements) -> list[str]:
    """Is ZH3 closer to the truth than SH9 (Roughton et al. 2024), on which maps, by how much: per selected
    environment every compared technique's flux-normalised mean / max, then the count over all environments."""
    envs = m.environments
    present = [t for t in ZH3_COMPARED if any(t in r["models"] for r in envs.values())]
    if "zh3_stored" not in present:
        return []
    out = []
    for name in zh3_environments(m):
        r = envs[name]
        sh9, models = r["errors"]["flux_luminance"], r["models"]
        parts = [f"SH9 {_pct(sh9['mean'])} / {_pct(sh9['max'])}"] + [
            f"{t} {_pct(models[t]['flux_luminance']['mean'])} / {_pct(models[t]['flux_luminance']['max'])}"
            for t in present if t in models]
        stored = _closer(models["zh3_stored"]["flux_luminance"], sh9, "mean", "SH9 (9)")
        line = (f"ZH3 vs SH9 on {name} ({r['kind']}, {r.get('sun_share', 0.0):.0%} of Φ_Y within 5° of the "
                f"brightest texel): flux-normalised error mean / max — {', '.join(parts)}. Stored ZH3 (4 + 1 "
                f"numbers per channel) is {stored} on the mean")
        if "zh3_hallucinated" in models and "sh1" in models:
            hall = _closer(models["zh3_hallucinated"]["flux_luminance"], models["sh1"]["flux_luminance"], "mean",
                           "L1 SH (4)")
            line += f"; hallucinated ZH3 (4 numbers) is {hall} on the mean"
        out.append(line + ".")
    closer = [n for n, r in envs.items() if "zh3_stored" in r["models"] and r["models"]["zh3_stored"]["flux_luminance"]
              ["mean"] + r["models"]["zh3_stored"]["flux_luminance"]["mean_uncertainty"]
              < r["errors"]["flux_luminance"]["mean"]]
    out.append(f"Stored ZH3 has a lower mean error than SH9 on {len(closer)} of {len(envs)} environments"
               + (f" ({', '.join(closer[:6])}{' …' if len(closer) > 6 else ''})" if closer else "")
               + "; Roughton et al. 2024 compare ZH3 with L1 SH (which it beats), not with SH9, which keeps 4 more "
                 "numbers per channel.")
    return out


def _identical_channels(coeffs: np.ndarray) -> bool:
    return bool(np.allclose(coeffs[:, 0], coeffs[:, 1], rtol=1e-6)
                and np.allclose(coeffs[:, 0], coeffs[:, 2], rtol=1e-6))


def cmgen_findings(m: Measurements) -> list[str]:
    """The cut-off cmgen's auto window picks per map, and what the window costs at the peak."""
    rows = {e: r["cmgen_auto"] for e, r in m.environments.items() if r.get("cmgen_auto")}
    if not rows:
        return []
    cuts = ", ".join(f"{e} {r['cutoff']:.2f}" for e, r in rows.items())
    worst = max(rows, key=lambda e: m.environments[e]["models"].get(CMGEN, {}).get("flux_luminance", {}).get("max", 0))
    r, w = rows[worst], rows[worst]["weights"]
    st = m.environments[worst]["models"][CMGEN]["flux_luminance"]
    sh9 = m.environments[worst]["errors"]["flux_luminance"]
    out = [f"cmgen auto window: cut-off (bands, bisected in [3, 13]) per environment: {cuts}. Worst: {worst}, "
           f"w = ({w[0]:.3f}, {w[1]:.3f}, {w[2]:.3f}), error {_pct(st['mean'])} mean / {_pct(st['max'])} max of Φ "
           f"(SH9 {_pct(sh9['mean'])} / {_pct(sh9['max'])}): no ringing, at the price of the peak (kernel bound "
           f"{_pct(r['kernel_bound'])}; unwindowed min {_pct(-r['negative_unwindowed'])} of Φ)."]
    grey = [e for e, r in rows.items() if len({round(b[0], 6) for b in r["brackets"]}) > 1
            and _identical_channels(np.array(m.environments[e]["coefficients"]))]
    if grey:
        out.append(f"cmgen auto window on grey lighting ({', '.join(grey)}): identical channels end with different "
                   "brackets, because each channel's bisection starts at the previous channel's answer and stops "
                   "after a 0.1-band bracket, so the cut-off shrinks by up to 0.1 band per channel without any "
                   "channel failing (as in CubemapSH::windowSH).")
    return out


def findings(m: Measurements) -> list[str]:
    """Sentences with numbers: the paper's probes, strong-sun environments, probes not compared."""
    out: list[str] = []
    paper = {k: v for k, v in m.environments.items() if "published" in v}
    for name, r in paper.items():
        e = r["errors"]
        out.append(f"{name}: flux-normalised error {_pct(e['flux_luminance']['mean'])} mean / "
                   f"{_pct(e['flux_luminance']['max'])} max reproduces the paper's < 1 % / < 5 %; the same "
                   f"approximation measures {_pct(e['relative']['mean'])} mean / {_pct(e['relative']['max'])} "
                   f"max per-normal relative error and {_pct(e['peak']['mean'])} mean / "
                   f"{_pct(e['peak']['max'])} max relative to the peak irradiance.")
    if not paper:
        out.append("None of the paper's probes (Debevec angular maps named as in probe_aliases.csv, e.g. "
                   "grace_probe.hdr) was found, so the paper's own claim was not checked; pass --probes DIR.")
    for r in m.environments.values():
        if r.get("published_note"):
            out.append(r["published_note"])
    for name, r in m.environments.items():
        st = r["errors"]["flux_luminance"]
        if name not in paper and (st["mean"] > PAPER_MEAN or st["max"] > PAPER_MAX):
            out.append(f"{name}: SH9 error {_pct(st['mean'])} mean / {_pct(st['max'])} max of Φ — beyond "
                       "the paper's 1 %/5 % (expected for concentrated light: a sun or small bright source), "
                       "still within the 3.07 %/9.375 % directional bound.")
    return out + technique_findings(m) + zh3_findings(m) + cmgen_findings(m) + foreign_thresholds()


def summary(m: Measurements) -> str:
    return ("Order-2 spherical-harmonic irradiance (9 coefficients, R&H 2001 eq. 12) against a "
            "deterministic quadrature of Mitsuba's own envmap radiance at "
            f"{m.settings.normals} quasi-uniform normals. Errors are shown under four normalisations; "
            "only the flux normalisation (|E′−E|/∫L dω) reproduces the paper's figures.")


def _json(d: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in d.items() if not k.startswith("_")}


def data(m: Measurements) -> dict[str, Any]:
    """``experiments.sh9``'s own keys: every environment and cross-check without its figure arrays."""
    return {"environments": {k: _json(v) for k, v in m.environments.items()},
            "pathtrace_crosscheck": {k: _json(v) for k, v in m.crosschecks.items()},
            "skipped_inputs": [list(s) for s in m.skipped]}


def techniques(m: Measurements) -> dict[str, Any]:
    """``experiments.sh9.techniques.<name>``: every metric ± uncertainty per environment, plus the same
    under mirrored normals (the power check)."""
    out = {}
    for tech in irradiance_family:
        metrics = {env: {metric: error_stats_measured(r["models"][tech.name][metric]) for metric in METRIC_NAMES}
                   for env, r in m.environments.items() if tech.name in r["models"]}
        mirrored = {env: {metric: error_stats_measured(r["models_mirrored"][tech.name][metric])
                          for metric in METRIC_NAMES}
                    for env, r in m.environments.items() if tech.name in r["models_mirrored"]}
        out[tech.name] = technique_entry(tech, metrics, mirrored_normals=measured_json(mirrored))
    return out
