"""``sh9`` report sections: tables from the measurements, figures from their arrays."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...local_models import irradiance as irradiance_family
from ...local_models import sh as shm
from ...metrics.published import PUBLISHED_TOLERANCE
from ...report import plots
from ..base import Context, Figure, Section, Table
from ..formatting import pct as _pct
from .claims import PAPER_MAX, PAPER_MEAN, Measurements

EXPERIMENT = "sh9"




def _pm(st: dict[str, float], stat: str) -> str:
    return f"{_pct(st[stat])} ± {_pct(st[f'{stat}_uncertainty'])}"


def environment_figures(name: str, r: dict[str, Any], ctx: Context) -> list[Figure]:
    """Environment thumbnail, reference and SH9 spheres (one exposure), heat map, error vs order."""
    a = r["_arrays"]
    p_thumb, r_thumb = ctx.figure_path(EXPERIMENT, f"{name}_env.png")
    plots.save_image(p_thumb, a["thumb"])
    exposure = plots.auto_exposure(a["sphere_reference"])
    p_ref, r_ref = ctx.figure_path(EXPERIMENT, f"{name}_sphere_reference.png")
    p_sh, r_sh = ctx.figure_path(EXPERIMENT, f"{name}_sphere_sh9.png")
    plots.save_image(p_ref, a["sphere_reference"], exposure=exposure)
    plots.save_image(p_sh, a["sphere_sh9"], exposure=exposure)
    p_err, r_err = ctx.figure_path(EXPERIMENT, f"{name}_error_flux.png")
    plots.save_heatmap(p_err, a["error_grid"], title=f"{name}: |E_SH9 − E| / Φ (all normals, lat-long)",
                       label="error / total flux", percent=True)
    sweep = r["order_sweep"]
    p_ord, r_ord = ctx.figure_path(EXPERIMENT, f"{name}_error_vs_order.png")
    plots.save_line_plot(p_ord, sweep["lmax"], {"mean": np.array(sweep["mean"]), "max": np.array(sweep["max"])},
                         xlabel="SH order l_max", ylabel="|E′ − E| / Φ (luminance)",
                         title=f"{name}: error vs SH order", logy=True, percent=True,
                         hlines={"paper mean 1 %": PAPER_MEAN, "paper max 5 %": PAPER_MAX})
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
    p_sph, r_sph = ctx.figure_path(EXPERIMENT, f"{name}_technique_spheres.png")
    plots.save_image_grid(p_sph, [a["sphere_reference"]] + [a["technique_spheres"][t] for t in techs],
                          ["reference"] + techs, exposure=plots.auto_exposure(a["sphere_reference"]), columns=7)
    p_err, r_err = ctx.figure_path(EXPERIMENT, f"{name}_technique_errors.png")
    plots.save_heatmap_grid(p_err, [a["technique_errors"][t] for t in techs], techs,
                            label="|Y(E′) − Y(E)| / Φ_Y", percent=True, columns=6)
    return [Figure(r_sph, f"{name}: every registered irradiance technique, E′/π (same exposure as the reference)"),
            Figure(r_err, f"{name}: error of every technique on the sphere, % of Φ (one colour scale)")]


def crosscheck_figures(name: str, d: dict[str, Any], ctx: Context) -> list[Figure]:
    a = d["_arrays"]
    exposure = plots.auto_exposure(a["render"])
    p1, r1 = ctx.figure_path(EXPERIMENT, f"{name}_pathtraced.png")
    p2, r2 = ctx.figure_path(EXPERIMENT, f"{name}_pathtrace_quadrature.png")
    p3, r3 = ctx.figure_path(EXPERIMENT, f"{name}_pathtrace_z.png")
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
                     _pm(e["flux_luminance"], "mean"), _pm(e["flux_luminance"], "max"), _pct(e["flux_rgb"]["max"]),
                     _pct(e["relative"]["mean"]), _pct(e["relative"]["max"]), _pct(e["peak"]["mean"]),
                     _pct(e["peak"]["max"])])
    table = Table(["environment", "kind", "Φ_Y", "ref. convergence", "flux mean", "flux max", "flux max (worst RGB)",
                   "relative mean", "relative max", "peak mean", "peak max"], rows,
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
        tables=[Table(["file", "table row", "exposure factor", "max |c/s − table|", "±0.01"], rows)] if rows else [])


def technique_section(m: Measurements) -> Section:
    """One row per registered irradiance technique, one column per environment: flux_luminance
    mean / max, each ± uncertainty."""
    envs = list(m.environments)
    rows = []
    for tech in irradiance_family:
        row: list[Any] = [tech.name]
        for e in envs:
            st = m.environments[e]["models"].get(tech.name, {}).get("flux_luminance")
            row.append(f"{_pm(st, 'mean')} / {_pm(st, 'max')}" if st else "—")
        rows.append(row)
    return Section("Technique comparison (registered irradiance techniques)", [
        "Every technique registered in the irradiance family (validate.local_models.irradiance), built-in or "
        "plug-in, evaluated on every environment through the family's output contract: flux-normalised "
        "luminance error, mean / max, ± the reference's uncertainty. Declared thresholds become claims "
        "sh9.technique.<name>.<metric>, judged on the worst environment in the technique's scope."],
        tables=[Table(["technique"] + envs, rows)])


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
        tables=[Table(["environment", "cut-off c", "(w1, w2)", "kernel bound", "flux max (worst RGB)",
                       "min E′ / Φ", "rejected c (min)", "min without window"], rows)])


def crosscheck_section(m: Measurements, ctx: Context) -> Section | None:
    if not m.crosschecks:
        return None
    rows = [[n, d["n_pixels"], f"{d['max_abs_z']:.2f}", f"{d['critical_z']:.2f}", f"{d['mean_z']:+.3f}",
             f"{d['chi2_per_dof']:.3f}", _pct(d["max_rel_diff"]), "pass" if d["passed"] else "FAIL"]
            for n, d in m.crosschecks.items()]
    return Section("Reference cross-check: path-traced sphere", [
        "Before the quadrature judges anything it is judged itself: a white Lambertian sphere is path traced "
        "by Mitsuba (path, max_depth 2, independent passes) and every pixel is compared with the "
        "quadrature averaged over the pixel's footprint, z = (render − quadrature)/standard error."],
        tables=[Table(["environment", "pixels", "max |z|", "critical z", "mean z", "χ²/dof", "max rel. diff",
                       "result"], rows)],
        gallery=[crosscheck_figures(n, d, ctx) for n, d in m.crosschecks.items()])


def sections(m: Measurements, ctx: Context) -> list[Section]:
    coeff_rows = [[n] + [f"({c[0]:.3g}, {c[1]:.3g}, {c[2]:.3g})" for c in r["coefficients"]]
                  for n, r in m.environments.items()]
    out = [s for s in [crosscheck_section(m, ctx)] if s is not None]
    out += [
        metric_section(m), published_section(m), technique_section(m),
        *[x for x in [cmgen_section(m)] if x is not None],
        Section("SH9 coefficients (Mitsuba frame: y up, −z forward; L00, L1m1, L10, L11, L2m2, L2m1, L20, "
                "L21, L22)", tables=[Table(["environment"] + list(shm.SH9_NAMES), coeff_rows)]),
        Section("Environments", ["Per environment: the environment, the reference sphere and the SH9 sphere "
                                 "(front view from +z, same exposure), the error over all normals and the "
                                 "error against SH order."],
                gallery=[environment_figures(n, r, ctx) for n, r in m.environments.items()]),
        Section("Techniques on each environment", [
            "Every registered irradiance technique (built-in or plug-in) on the front-facing sphere of each "
            "environment: E′/π beside the reference at one exposure, and its error |Y(E′) − Y(E)| / Φ_Y per "
            "pixel on one colour scale per environment."],
                figures=[f for n, r in m.environments.items() for f in technique_figures(n, r, ctx)]),
    ]
    return out
