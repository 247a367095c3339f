"""Experiment ``sh9``: SH9 irradiance (Ramamoorthi & Hanrahan 2001) against Mitsuba's radiance.

Sweeps every environment (built-ins plus every probe found) and checks:

* the paper's headline claim on its own probes (Debevec angular maps whose stem is exactly a
  ``debevec_file`` of ``probe_aliases.csv``): flux-normalised luminance error mean < 1 %, max < 5 %;
* the "any lighting" theorem on every environment: per channel, max error ≤ 3/32 = 9.375 % Φ and
  mean error ≤ 3.07 % Φ (equality only for a directional light);
* exactness on the band-limited environment (< 0.1 % Φ);
* the published coefficient table, in R&H's ``prefilter`` convention, up to one exposure factor per
  probe (every scaled coefficient within ±0.01);
* the reference itself: closed forms (constant, two-tone, band-limited) and convergence (< 0.1 %).

Every registered irradiance model (:mod:`validate.local_models`) is evaluated on every environment
and gets a row in the model comparison.
"""

from __future__ import annotations

import numpy as np

from ..local_models import irradiance as irradiance_family
from ..local_models import sh as shm
from ..metrics.irradiance_error import METRIC_NAMES, WORST_CASE_MAX, WORST_CASE_MEAN, ErrorStats, irradiance_errors
from ..metrics.published import PUBLISHED_TOLERANCE, fit_exposure
from ..reference.irradiance import reference_irradiance
from ..reference.pathtrace import crosscheck_sphere
from ..report import plots
from ..scenes import latlong, procedural
from ..scenes.environment import Environment
from ..scenes.probes import published_row, read_aliases, read_published_sh9
from .base import Claim, Context, ExperimentResult, Figure, Section, Table, register_experiment

PAPER_MEAN = 0.01  # R&H 2001: "average error < 1 %" on their probes
PAPER_MAX = 0.05  # "maximum error < 5 %"
BANDLIMITED_EXACT = 1e-3  # band-limited (order ≤ 2) environment: SH9 exact up to quadrature (< 0.1 %)
CONVERGENCE = 1e-3  # reference converged to < 0.1 % of peak irradiance when the grid is doubled
CLOSED_FORM = 1e-3  # quadrature vs closed form, relative, everywhere
MAX_ORDER = 8
ATTAINS_BOUND = "near_directional"  # built to approach the directional worst case
TIGHT = 0.95  # "attains": within 5 % of the bound (a 0.5° disc gives 98 % of the max, 99.9 % of the mean)
SWEEP_METRIC = "flux_luminance"


def sphere_normals(res: int) -> tuple[np.ndarray, np.ndarray]:
    """Front view of a unit sphere from +z (orthographic): normals (res, res, 3), NaN outside; mask."""
    t = (np.arange(res) + 0.5) / res * 2 - 1
    yy, xx = np.meshgrid(-t, t, indexing="ij")
    r2 = xx**2 + yy**2
    mask = r2 < 1.0
    n = np.stack([xx, yy, np.sqrt(np.clip(1 - r2, 0, 1))], axis=-1)
    n[~mask] = np.nan
    return n, mask


def closed_form_irradiance(env: Environment, normals: np.ndarray) -> np.ndarray | None:
    """Exact E(n) for the built-ins that have one (constant, two-tone, band-limited), else None."""
    if env.name == "constant":
        return np.pi * np.broadcast_to(env.radiance[0, 0].astype(np.float64), normals.shape)
    if env.name == "two_tone":
        c = normals[:, 1:2]
        return np.pi * (procedural.SKY * (1 + c) / 2 + procedural.GROUND * (1 - c) / 2)
    if env.name == "bandlimited":
        return shm.render_irradiance(procedural.BANDLIMITED_SH, normals)
    return None


def _stats_json(stats: dict[str, ErrorStats]) -> dict:
    return {k: v.to_json() for k, v in stats.items()}


def _settings(quick: bool) -> dict:
    return {"normals": 2500 if quick else 10000, "cells": 64,
            "grid": (24, 48) if quick else (48, 96), "sphere_px": 48 if quick else 96}


def analyse_environment(env: Environment, ctx: Context, settings: dict, published: dict) -> dict:
    """Everything the experiment measures on one environment (JSON-able, plus figures)."""
    n_fib = latlong.fibonacci_sphere(settings["normals"])
    gh, gw = settings["grid"]
    th = (np.arange(gh) + 0.5) * np.pi / gh
    ph = (np.arange(gw) + 0.5) * 2 * np.pi / gw
    tt, pp = np.meshgrid(th, ph, indexing="ij")
    n_grid = latlong.spherical_to_direction(tt, pp).reshape(-1, 3)
    sph, mask = sphere_normals(settings["sphere_px"])
    n_sph = sph[mask]
    alln = np.concatenate([n_fib, n_grid, n_sph])
    ref = reference_irradiance(env, alln, cells=settings["cells"])
    flux = env.total_flux()
    k1, k2 = len(n_fib), len(n_fib) + len(n_grid)

    coeffs = shm.project_environment(env.radiance, MAX_ORDER)
    e_sh9_all = shm.render_irradiance_rh2001(coeffs[:9], alln)
    e_ref, unc = ref.irradiance[:k1], ref.uncertainty[:k1]
    errors = irradiance_errors(e_ref, e_sh9_all[:k1], flux, unc)

    sweep = {"lmax": list(range(MAX_ORDER + 1)), "mean": [], "max": []}
    for lm in range(MAX_ORDER + 1):
        e = shm.render_irradiance(coeffs[: shm.n_coeffs(lm)], n_fib, lm)
        st = irradiance_errors(e_ref, e, flux, unc)[SWEEP_METRIC]
        sweep["mean"].append(st.mean)
        sweep["max"].append(st.max)

    models = {}
    for tech in irradiance_family:
        e = irradiance_family.call(tech, env.radiance, n_fib)
        models[tech.name] = _stats_json(irradiance_errors(e_ref, e, flux, unc))

    out: dict = {
        "kind": env.kind, "description": env.description, "layout": env.layout,
        "source": str(env.source) if env.source else None, "notes": list(env.notes),
        "resolution": [env.width, env.height],
        "flux": flux.tolist(), "flux_luminance": float(latlong.luminance(flux)),
        "coefficients": coeffs[:9].tolist(),
        "errors": _stats_json(errors),
        "convergence": ref.convergence,
        "order_sweep": sweep,
        "models": models,
    }
    exact = closed_form_irradiance(env, n_fib)
    if exact is not None:
        out["closed_form_max_rel"] = float(np.max(np.abs(e_ref - exact) / exact))
    key = published_row(env)
    if key is not None and key in published:
        table = np.array([published[key][c] for c in shm.SH9_NAMES])
        fit = fit_exposure(shm.project_angular_rh2001(env.angular, 2), table, key)
        out["published"] = fit.to_json()

    # figures
    stem = env.name
    thumb = env.radiance[:: max(1, env.height // 128), :: max(1, env.width // 256)]
    p_thumb, r_thumb = ctx.figure_path("sh9", f"{stem}_env.png")
    plots.save_image(p_thumb, thumb)
    ref_img = np.full(sph.shape, np.nan)
    sh_img = np.full(sph.shape, np.nan)
    ref_img[mask] = ref.irradiance[k2:] / np.pi
    sh_img[mask] = e_sh9_all[k2:] / np.pi
    exposure = plots.auto_exposure(ref_img)  # one exposure for both spheres
    p_ref, r_ref = ctx.figure_path("sh9", f"{stem}_sphere_reference.png")
    p_sh, r_sh = ctx.figure_path("sh9", f"{stem}_sphere_sh9.png")
    plots.save_image(p_ref, ref_img, exposure=exposure)
    plots.save_image(p_sh, sh_img, exposure=exposure)
    err_grid = (np.abs(latlong.luminance(e_sh9_all[k1:k2]) - latlong.luminance(ref.irradiance[k1:k2]))
                / latlong.luminance(flux)).reshape(gh, gw)
    p_err, r_err = ctx.figure_path("sh9", f"{stem}_error_flux.png")
    plots.save_heatmap(p_err, err_grid, title=f"{stem}: |E_SH9 − E| / Φ (all normals, lat-long)",
                       label="error / total flux", percent=True)
    p_ord, r_ord = ctx.figure_path("sh9", f"{stem}_error_vs_order.png")
    plots.save_line_plot(p_ord, sweep["lmax"], {"mean": np.array(sweep["mean"]), "max": np.array(sweep["max"])},
                         xlabel="SH order l_max", ylabel="|E′ − E| / Φ (luminance)",
                         title=f"{stem}: error vs SH order", logy=True, percent=True,
                         hlines={"paper mean 1 %": PAPER_MEAN, "paper max 5 %": PAPER_MAX})
    out["_figures"] = [Figure(r_thumb, f"{stem}: environment (tonemapped lat-long)", 256),
                       Figure(r_ref, "reference sphere (Mitsuba quadrature), E/π", 160),
                       Figure(r_sh, "SH9 sphere, E′/π (same exposure)", 160),
                       Figure(r_err, "SH9 error heat map, % of Φ", 300),
                       Figure(r_ord, "error vs SH order", 300)]
    return out


PATHTRACE_ENVS = ("two_tone", "disc_on_sky", "grace_probe")  # built-ins plus one real probe when present


def pathtrace_crosscheck(env: Environment, ctx: Context) -> tuple[list[Claim], dict, list[Figure]]:
    """The reference judged by an independent Mitsuba computation: a path-traced white Lambertian sphere
    (``path``, direct light, independent passes) against the quadrature over each pixel's footprint."""
    cc = crosscheck_sphere(env, resolution=48, spp=256, passes=8, seed=ctx.seed)
    claims = [
        Claim(f"reference.pathtrace.{env.name}", f"{env.name}: path-traced sphere = quadrature, every pixel "
              f"({cc.n_pixels} px × RGB, Šidák α = {cc.alpha})", "max |z| over pixels", cc.critical_z,
              cc.max_abs_z, 0.0, source="Student t from 8 independent passes → normal quantile; Šidák-corrected"),
        Claim(f"reference.pathtrace.{env.name}.bias", f"{env.name}: no systematic offset between path tracing and "
              "quadrature", "|mean z| (worst channel)", cc.bias_limit, float(np.max(np.abs(cc.mean_z_channels))),
              0.0, source="4/√N: a bias of 4 standard errors of the mean z"),
    ]
    data = {"n_pixels": cc.n_pixels, "max_abs_z": cc.max_abs_z, "critical_z": cc.critical_z, "mean_z": cc.mean_z,
            "chi2_per_dof": cc.chi2_per_dof, "p_value": cc.p_value, "max_rel_diff": cc.max_rel_diff,
            "passed": cc.passed, "settings": cc.settings}
    exposure = plots.auto_exposure(cc.render)
    p1, r1 = ctx.figure_path("sh9", f"{env.name}_pathtraced.png")
    p2, r2 = ctx.figure_path("sh9", f"{env.name}_pathtrace_quadrature.png")
    p3, r3 = ctx.figure_path("sh9", f"{env.name}_pathtrace_z.png")
    plots.save_image(p1, cc.render, exposure=exposure)
    plots.save_image(p2, cc.quadrature, exposure=exposure)
    absz = np.abs(cc.z_image)
    worst = np.where(np.isnan(absz).all(axis=-1), np.nan, np.nan_to_num(absz, nan=0.0).max(axis=-1))
    plots.save_heatmap(p3, worst, title=f"{env.name}: |z| per pixel (worst channel)",
                       label="|z|", vmax=cc.critical_z)
    figs = [Figure(r1, f"{env.name}: path-traced Lambertian sphere (mean of 8 passes)", 160),
            Figure(r2, "quadrature E/π over each pixel's footprint (same exposure)", 160),
            Figure(r3, f"|z| per pixel; colour bar ends at the critical value {cc.critical_z:.2f}", 300)]
    return claims, data, figs


def _pct(x: float) -> str:
    return f"{100 * x:.3g} %"


@register_experiment("sh9", "SH9 irradiance vs Mitsuba (Ramamoorthi & Hanrahan 2001)",
                     "SH9 coefficients, errors under every metric, error vs order, published table, claims",
                     order=10)
def run(ctx: Context) -> ExperimentResult:
    settings = _settings(ctx.quick)
    envs, skipped = ctx.environments()
    published = read_published_sh9()
    aliases = read_aliases()
    results: dict[str, dict] = {}
    for env in ctx.progress(envs, "sh9: environments"):
        results[env.name] = analyse_environment(env, ctx, settings, published)

    claims: list[Claim] = []
    findings: list[str] = []
    crosschecks: dict[str, dict] = {}
    cross_figs: list[list[Figure]] = []
    by_name = {e.name: e for e in envs}
    for name in ctx.progress([n for n in PATHTRACE_ENVS if n in by_name][: 1 if ctx.quick else None],
                             "sh9: path-traced cross-checks"):
        c, d, f = pathtrace_crosscheck(by_name[name], ctx)
        claims += c
        crosschecks[name] = d
        cross_figs.append(f)
    paper = {k: v for k, v in results.items() if "published" in v}
    for name, r in paper.items():
        st = r["errors"]["flux_luminance"]
        claims.append(Claim(f"sh9.paper.{name}.mean", f"{name}: SH9 mean error < 1 % (R&H 2001)",
                            "flux_luminance mean", PAPER_MEAN, st["mean"], st["mean_uncertainty"], unit="%",
                            source="R&H 2001 §4: average error < 1 %"))
        claims.append(Claim(f"sh9.paper.{name}.max", f"{name}: SH9 max error < 5 % (R&H 2001)",
                            "flux_luminance max", PAPER_MAX, st["max"], st["max_uncertainty"], unit="%",
                            source="R&H 2001 §4: maximum error < 5 %"))
        pub = r["published"]
        claims.append(Claim(f"sh9.published.{name}", f"{name}: rh2001 coefficients = table row "
                            f"'{pub['probe']}' × {pub['scale']:.3f} (±{PUBLISHED_TOLERANCE})",
                            "max |c/s − table|", PUBLISHED_TOLERANCE, pub["max_deviation"], 0.0,
                            source="sh9_coefficients.csv (R&H 2001 / Orange Book)"))
    if not paper:
        findings.append("None of the paper's probes (Debevec angular maps named as in probe_aliases.csv, e.g. "
                        "grace_probe.hdr) was found, so the paper's own claim was not checked; pass --probes DIR.")

    # The theorem: every non-negative lighting stays within the directional bound. near_directional is
    # built to attain it (equality for a directional light), so no finite uncertainty can prove it is
    # strictly under; it gets its own claim that the bound is *tight* instead.
    bounded = {k: v for k, v in results.items() if k != ATTAINS_BOUND}
    if bounded:
        worst_max = max(bounded.items(), key=lambda kv: kv[1]["errors"]["flux_rgb"]["max"])
        worst_mean = max(bounded.items(), key=lambda kv: kv[1]["errors"]["flux_rgb"]["mean"])
        wm, wa = worst_max[1]["errors"]["flux_rgb"], worst_mean[1]["errors"]["flux_rgb"]
        claims.append(Claim("sh9.bound.max", f"every environment (but {ATTAINS_BOUND}): max error ≤ 3/32 Φ "
                            f"(worst: {worst_max[0]})", "flux_rgb max (worst channel)", WORST_CASE_MAX,
                            wm["max"], wm["max_uncertainty"], unit="%",
                            source="R&H JOSA 2001: |K̃(x) − max(x,0)| ≤ 3/32"))
        claims.append(Claim("sh9.bound.mean", f"every environment (but {ATTAINS_BOUND}): mean error ≤ 3.07 % Φ "
                            f"(worst: {worst_mean[0]})", "flux_rgb mean (worst channel)", WORST_CASE_MEAN,
                            wa["mean"], wa["mean_uncertainty"], unit="%",
                            source="R&H 2001: directional light mean error 3.07 %"))
    if ATTAINS_BOUND in results:
        st = results[ATTAINS_BOUND]["errors"]["flux_rgb"]
        claims.append(Claim(f"sh9.worst_case.{ATTAINS_BOUND}.max", "near-directional light attains the max bound "
                            "(> 95 % of 3/32)", "flux_rgb max", TIGHT * WORST_CASE_MAX, st["max"],
                            st["max_uncertainty"], comparison=">", unit="%",
                            source="R&H 2001: equality for a directional light"))
        claims.append(Claim(f"sh9.worst_case.{ATTAINS_BOUND}.mean", "near-directional light attains the mean "
                            "bound (> 95 % of 3.07 %)", "flux_rgb mean", TIGHT * WORST_CASE_MEAN, st["mean"],
                            st["mean_uncertainty"], comparison=">", unit="%",
                            source="R&H 2001: equality for a directional light"))
    if "bandlimited" in results:
        st = results["bandlimited"]["errors"]["flux_rgb"]
        claims.append(Claim("sh9.bandlimited.exact", "band-limited (order ≤ 2) environment: SH9 exact",
                            "flux_rgb max", BANDLIMITED_EXACT, st["max"], st["max_uncertainty"], unit="%",
                            source="SH9 represents order ≤ 2 exactly; 0.1 % = quadrature tolerance"))
    worst_conv = max(results.items(), key=lambda kv: kv[1]["convergence"])
    claims.append(Claim("reference.convergence", f"reference quadrature converged (worst: {worst_conv[0]})",
                        "max |E_2H − E_H| / max E", CONVERGENCE, worst_conv[1]["convergence"], 0.0, unit="%",
                        source="issue: converged to < 0.1 % (doubling the grid)"))
    for name, r in results.items():
        if "closed_form_max_rel" in r:
            claims.append(Claim(f"reference.closed_form.{name}", f"{name}: quadrature = closed form",
                                "max |E − E_exact| / E_exact", CLOSED_FORM, r["closed_form_max_rel"], 0.0,
                                unit="%", source="E = πL; (1 ± cos β)/2 view factors; Σ A_l L_lm Y_lm"))

    for name, r in results.items():
        st = r["errors"]["flux_luminance"]
        if name not in paper and (st["mean"] > PAPER_MEAN or st["max"] > PAPER_MAX):
            findings.append(f"{name}: SH9 error {_pct(st['mean'])} mean / {_pct(st['max'])} max of Φ — beyond "
                            "the paper's 1 %/5 % (expected for concentrated light: a sun or small bright source), "
                            "still within the 3.07 %/9.375 % directional bound.")
    for name, r in paper.items():
        e = r["errors"]
        findings.insert(0, f"{name}: flux-normalised error {_pct(e['flux_luminance']['mean'])} mean / "
                        f"{_pct(e['flux_luminance']['max'])} max reproduces the paper's < 1 % / < 5 %; the same "
                        f"approximation measures {_pct(e['relative']['mean'])} mean / {_pct(e['relative']['max'])} "
                        f"max per-normal relative error and {_pct(e['peak']['mean'])} mean / "
                        f"{_pct(e['peak']['max'])} max relative to the peak irradiance.")

    sections = _sections(results, aliases)
    if crosschecks:
        rows = [[n, d["n_pixels"], f"{d['max_abs_z']:.2f}", f"{d['critical_z']:.2f}", f"{d['mean_z']:+.3f}",
                 f"{d['chi2_per_dof']:.3f}", _pct(d["max_rel_diff"]), "pass" if d["passed"] else "FAIL"]
                for n, d in crosschecks.items()]
        sections.insert(0, Section("Reference cross-check: path-traced sphere", [
            "Before the quadrature judges anything it is judged itself: a white Lambertian sphere is path traced "
            "by Mitsuba (path, max_depth 2, 8 independent passes × 256 spp) and every pixel is compared with the "
            "quadrature averaged over the pixel's footprint, z = (render − quadrature)/standard error."],
            tables=[Table(["environment", "pixels", "max |z|", "critical z", "mean z", "χ²/dof",
                           "max rel. diff", "result"], rows)], gallery=cross_figs))
    data = {"environments": {k: {kk: vv for kk, vv in v.items() if not kk.startswith("_")}
                             for k, v in results.items()},
            "pathtrace_crosscheck": crosschecks,
            "skipped_inputs": [list(s) for s in skipped]}
    return ExperimentResult(
        name="sh9", title="SH9 irradiance vs Mitsuba (Ramamoorthi & Hanrahan 2001)",
        summary=("Order-2 spherical-harmonic irradiance (9 coefficients, R&H 2001 eq. 12) against a "
                 "deterministic quadrature of Mitsuba's own envmap radiance at "
                 f"{settings['normals']} quasi-uniform normals. Errors are shown under four normalisations; "
                 "only the flux normalisation (|E′−E|/∫L dω) reproduces the paper's figures."),
        claims=claims, findings=findings, sections=sections, data=data, settings=settings)


def _sections(results: dict[str, dict], aliases: dict) -> list[Section]:
    rows = []
    for name, r in results.items():
        e = r["errors"]
        rows.append([name, r["kind"], f"{r['flux_luminance']:.4g}", _pct(r["convergence"]),
                     f"{_pct(e['flux_luminance']['mean'])} ± {_pct(e['flux_luminance']['mean_uncertainty'])}",
                     f"{_pct(e['flux_luminance']['max'])} ± {_pct(e['flux_luminance']['max_uncertainty'])}",
                     _pct(e["flux_rgb"]["max"]), _pct(e["relative"]["mean"]), _pct(e["relative"]["max"]),
                     _pct(e["peak"]["mean"]), _pct(e["peak"]["max"])])
    metric_table = Table(["environment", "kind", "Φ_Y", "ref. convergence", "flux mean", "flux max",
                          "flux max (worst RGB)", "relative mean", "relative max", "peak mean", "peak max"],
                         rows, "SH9 error under every metric (definitions in README § Metrics).")
    pub_rows = [[n, r["published"]["probe"], f"{r['published']['scale']:.4f}",
                 f"{r['published']['max_deviation']:.4f}",
                 "pass" if r["published"]["max_deviation"] < PUBLISHED_TOLERANCE else "FAIL"]
                for n, r in results.items() if "published" in r]
    model_names = list(next(iter(results.values()))["models"]) if results else []
    model_rows = [[n] + [f"{_pct(r['models'][m]['flux_luminance']['mean'])} / "
                         f"{_pct(r['models'][m]['flux_luminance']['max'])}" for m in model_names]
                  for n, r in results.items()]
    coeff_rows = [[n] + [f"({c[0]:.3g}, {c[1]:.3g}, {c[2]:.3g})" for c in r["coefficients"]]
                  for n, r in results.items()]
    gallery = [r["_figures"] for r in results.values()]
    return [
        Section("Which metric reproduces the paper", [
            "R&H 2001 state that SH9 irradiance has average error < 1 % and maximum error < 5 % on their "
            "probes. Those figures are errors relative to the total incident flux Φ = ∫L dω: under that "
            "normalisation the error of any non-negative lighting is provably ≤ 3/32 = 9.375 % at every "
            "normal and ≤ 3.07 % on average, with equality for a directional light. Per-normal relative "
            "error (|E′−E|/E) and peak-normalised error (|E′−E|/max E) measure the same approximation more "
            "harshly and do not reproduce the paper's numbers."], tables=[metric_table]),
        Section("Published coefficients (R&H prefilter convention)", [
            "Coefficients of the paper's probes computed in R&H's angular-map convention and compared with "
            "the published table after fitting one exposure factor per probe by least squares "
            f"(threshold ±{PUBLISHED_TOLERANCE})."],
            tables=[Table(["file", "table row", "exposure factor", "max |c/s − table|", "±0.01"], pub_rows)]
            if pub_rows else []),
        Section("Model comparison (registered irradiance models)", [
            "Every model registered with validate.local_models.register_irradiance_model, evaluated on every "
            "environment: flux-normalised luminance error, mean / max."],
            tables=[Table(["environment"] + model_names, model_rows)]),
        Section("SH9 coefficients (Mitsuba frame: y up, −z forward; L00, L1m1, L10, L11, L2m2, L2m1, L20, "
                "L21, L22)", tables=[Table(["environment"] + list(shm.SH9_NAMES), coeff_rows)]),
        Section("Environments", ["Per environment: the environment, the reference sphere and the SH9 sphere "
                                 "(front view from +z, same exposure), the error over all normals and the "
                                 "error against SH order."], gallery=gallery),
    ]


__all__ = ["run", "analyse_environment", "METRIC_NAMES"]
