"""``multiscatter`` report: findings, the white-furnace section, and the ``results.json`` payload."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...figures import plots
from ..base import Context, Figure, Section, Table
from ..formatting import col
from ..techniques import Measured, technique_entry
from .compute import Measurements, metric, metrics
from .settings import NAME


def bsdf_findings(m: Measurements) -> list[str]:
    """Sentences with the numbers of :func:`bsdf_checks`."""
    b = m.bsdf
    if not b:
        return []
    if "skipped" in b:
        return [f"Random-walk Mitsuba BSDF checks not run: {b['skipped']}."]
    chi = "; ".join(f"α = {r['alpha']:g}, θ_i = {r['theta_i']:g}°: p = {r['p_value']:.3g} (X² = {r['chi2']:.0f}, "
                    f"{r['dof']} d.o.f.; harness-only p = {r['harness_p_value']:.2g}; max Var Ê/Ê = "
                    f"{r['variance_ratio']:.2f}; pdf {r.get('repeats', 4)} × {r.get('walks', '?')} walks) → "
                    f"perturbed p = {q['p_value']:.2g}"
                    for r, q in zip(b["chi2"], b["chi2_power"], strict=True))
    rec = "; ".join(f"α = {r['alpha']:g}, F₀ = {r['f0']:g}: max |z| = {r['max_abs_z']:.2f} → {q['max_abs_z']:.1f}"
                    for r, q in zip(b["reciprocity"], b["reciprocity_power"], strict=True))
    fur = "; ".join(f"α = {r['alpha']:g}, μ_i = {r['mu_i']:g}: A = {r['albedo']:.4f} ± {r['se']:.4f} "
                    f"(distant G₁: {q['albedo']:.4f})" for r, q in zip(b["furnace"], b["furnace_power"], strict=True))
    ren = "; ".join(f"α = {r['alpha']:g}: {r['mean']:.4f} ± {r['se']:.4f} (single scattering {q['mean']:.3f})"
                    for r, q in zip(b["render"], b["render_power"], strict=True))
    ss = ", ".join(f"{r['max_rel_diff']:.1e} (α × 1.01: {r['power']:.3f})" for r in b["single_scatter"])
    s0 = b["chi2"][0]
    return [f"Walk BSDF χ² (Mitsuba ChiSquareTest histogram via BSDFAdapter, {s0['samples']} samples, {s0['cells']} "
            f"cells; pdf() integrated on the harness's grid, independent seeds, walks quadrupled until Var Ê ≤ Ê): "
            f"{chi}. Sampler α × 1.1 in sample() only is the perturbation.",
            f"Walk BSDF reciprocity (one-sided eval, {b['reciprocity'][0]['walks_per_side']} walks per side, "
            f"{len(b['reciprocity'][0]['z'])} direction pairs each): {rec} with the distant-G₁ next-event "
            "shadowing.",
            f"Walk BSDF white furnace from eval (F₀ = 1): {fur}.",
            f"Walk BSDF in Mitsuba's path tracer, white furnace (sphere, F₀ = 1, 32 × 32 pixels, "
            f"{b['render'][0]['spp']} spp): pixel mean {ren}.",
            f"Walk BSDF first order vs Mitsuba roughconductor × G₂/(G₁G₁), max relative difference by α: {ss}."]


def findings(m: Measurements) -> list[str]:
    s = m.settings
    pub = ", ".join(f"r = {p['roughness']:g}, NoV = {p['nov']:g}: {p['table']:.3f} vs {p['published']:.2f}"
                    for p in m.published)
    out = [f"Single-scattering GGX albedo (separable Smith G, as Mitsuba) vs three.js PR 33983's furnace column (their "
           f"LUT; height-correlated Smith G, which keeps more energy): {pub}."]
    for w in m.walk:
        wk = ", ".join(f"{f:g}: {a:.4f} ± {e:.4f}"
                       for f, a, e in zip(w["f0s"], w["albedo"], w["albedo_se"], strict=True))
        tech = "; ".join(f"{t} " + "/".join(f"{x:.4f}" for x in v) for t, v in w["techniques"].items()
                         if t == "cook_torrance" or any(tt.name == t and tt.meta.get("compensation")
                                                        for tt in m.techniques))
        out.append(f"Multiple-scattering reference (Heitz et al. 2016 random walk, Schlick F per bounce) at α = "
                   f"{w['alpha']:g}, μ_v = {w['mu']:g}: W by F₀ {wk} (first bounce {w['single'][0]:.4f} vs "
                   f"height-correlated {w['e_correlated']:.4f}, separable {w['e_separable']:.4f}; "
                   f"{w['mean_order']:.2f} bounces on average); techniques at F₀ = "
                   f"{'/'.join(f'{f:g}' for f in w['f0s'])}: {tech}.")
    out += bsdf_findings(m)
    if "cook_torrance" in m.w:
        w = np.asarray(m.w["cook_torrance"]["f0_1"]["value"])
        i, j = np.unravel_index(np.argmin(w), w.shape)
        out.append(f"Single-scattering GGX (cook_torrance, F = 1) loses up to {100 * (1 - w[i, j]):.1f} % of the light "
                   f"in the white furnace (W = {w[i, j]:.3f} at α = {s.alphas[i]:g}, μ_v = {s.mus[j]:g}); at α = "
                   f"{s.alphas[-1]:g} W ranges {w[-1].min():.3f}–{w[-1].max():.3f} over μ_v.")
    for t in m.techniques:
        if t.meta.get("compensation"):
            f1 = metric(m, t.name, "f0_1")
            mt = (f", {100 * metric(m, t.name, 'metal')['value']:.3f} ± "
                  f"{100 * metric(m, t.name, 'metal')['uncertainty']:.3f} % over metalness "
                  f"{', '.join(f'{x:g}' for x in s.metalness)} (base colour 1)" if "metal" in m.w[t.name] else "")
            out.append(f"{t.name}: furnace max |W − 1| = {100 * f1['value']:.3f} ± {100 * f1['uncertainty']:.3f} % "
                       f"(F = 1){mt}; dielectric F₀ = 0.04 / 0.5 at α = 1: W = "
                       f"{m.w[t.name]['f0_0.04']['value']:.4f} / {m.w[t.name]['f0_0.5']['value']:.4f}.")
    return out


def sections(m: Measurements, ctx: Context) -> list[Section]:
    s = m.settings
    rows = []
    for t in m.techniques:
        d = metrics(m, t.name)
        rows.append([t.name, *(f"{100 * d[k]['value']:.3g} ± {100 * d[k]['uncertainty']:.2g} %" if k in d else "—"
                               for k in ("furnace_error.f0_1", "furnace_error.metalness")),
                     *(f"{d[f'albedo.f0_{f:g}']['value']:.4f}" for f in s.f0s)])
    table = Table(["technique", "furnace_error.f0_1 (%)", "furnace_error.metalness (%)",
                   *(f"W, F₀ = {f:g}, α = 1, μ_v = 0.5 (–)" for f in s.f0s)], rows,
                  "Max |W − 1| of the white-furnace albedo W(v) = ∫ q dω_l over the α × μ_v (× metalness) grids; "
                  "± = |Δ| between n and n/2 quadrature nodes.")
    j = s.mus.index(0.5) if 0.5 in s.mus else 0
    series = {t.name: [r[j] for r in m.w[t.name]["f0_1"]["value"]] for t in m.techniques
              if t.name == "cook_torrance" or t.meta.get("compensation")}
    if 0.5 in s.metalness:
        k = s.metalness.index(0.5)
        series.update({f"{t.name} (metalness 0.5)": [r[j] for r in m.w[t.name]["metal"]["value"][k]]
                       for t in m.techniques if "metal" in m.w[t.name]})
    p, rel = ctx.figure_path(NAME, "furnace_vs_alpha.png")
    plots.save_line_plot(p, list(s.alphas), series, xlabel="GGX α", ylabel=f"W at μ_v = {s.mus[j]:g}",
                         title="White furnace (F = 1; base colour 1)", hlines={"target": 1.0})
    pub = Table(["roughness (–)", "α (–)", "NoV (–)", "three.js 33983 (–)", "this table (–)"],
                [[q["roughness"], q["alpha"], q["nov"], q["published"], f"{q['table']:.4f}"] for q in m.published],
                "Single-scattering GGX albedo E(μ) (F = 1) against three.js PR 33983's published furnace column.")
    walk = Table(["α (–)", "F₀ (–)", "walk W, Heitz 2016 (–)", *[col(t.name, "–") for t in m.techniques
                                                                 if t.name == "cook_torrance"
                                                                 or t.meta.get("compensation")]],
                 [[w["alpha"], f, f"{a:.4f} ± {e:.4f}", *[f"{w['techniques'][t.name][k]:.4f}" for t in m.techniques
                                                          if t.name == "cook_torrance" or t.meta.get("compensation")]]
                  for w in m.walk for k, (f, a, e) in enumerate(zip(w["f0s"], w["albedo"], w["albedo_se"],
                                                                   strict=True))],
                 f"Directional albedo at μ_v = {s.walk_mu:g}: the random-walk reference (height-correlated Smith "
                 "microsurface, Schlick F per bounce) and each technique (F₀ < 1: η real for exact-Fresnel "
                 "techniques, base colour F₀ for the metalness ones).")
    tables = [table, pub, walk]
    if m.bsdf and "skipped" not in m.bsdf:
        b = m.bsdf
        tables.append(Table(["α (–)", "θ_i (°)", "X² / d.o.f. (–)", "p (–)", "harness-only p (–)",
                             "p, sampler α × 1.1 (–)"],
                            [[r["alpha"], r["theta_i"], f"{r['chi2']:.0f} / {r['dof']}", f"{r['p_value']:.3g}",
                              f"{r['harness_p_value']:.2g}", f"{q['p_value']:.2g}"]
                             for r, q in zip(b["chi2"], b["chi2_power"], strict=True)],
                            "The random walk as a Mitsuba BSDF (microsurface_walk): χ² of sample() against pdf() "
                            "(Mitsuba's ChiSquareTest histogram; expected counts from pdf() on the harness's grid "
                            "with their Monte Carlo variance added; 'harness-only' treats them as exact)."))
        tables.append(Table(["α (–)", "F₀ (–)", "max |z| reciprocity (–)", "max |z| distant-G₁ NEE (–)"],
                            [[r["alpha"], r["f0"], f"{r['max_abs_z']:.2f}", f"{q['max_abs_z']:.1f}"]
                             for r, q in zip(b["reciprocity"], b["reciprocity_power"], strict=True)],
                            "Reciprocity of the one-sided stochastic eval: z = (f̂(a→b) − f̂(b→a))/se over direction "
                            "pairs."))
    return [Section("White furnace: multiple-scattering compensation", [
        f"Grid: α ∈ {{{', '.join(f'{a:g}' for a in s.alphas)}}}, μ_v ∈ {{{', '.join(f'{x:g}' for x in s.mus)}}}, "
        f"metalness ∈ {{{', '.join(f'{x:g}' for x in s.metalness)}}}; quadrature {s.nodes} × {2 * s.nodes}."],
        figures=[Figure(rel, "white-furnace albedo vs α", 480)], tables=tables)]


SUMMARY = ("Kulla–Conty, Fdez-Agüera and Turquin energy compensation for GGX, the metalness workflow with the "
           "compensation per path, and the three.js/Bevy blended-F₀ bug, against the closed white-furnace "
           "target W = 1 (F = 1).")


def summary(m: Any) -> str:
    return SUMMARY


def data(m: Measurements) -> dict[str, Any]:
    return {"w": m.w, "published": m.published, "walk": m.walk, "walk_bsdf": m.bsdf}


def techniques(m: Measurements) -> dict[str, Any]:
    """``experiments.multiscatter.techniques.<name>``: furnace and walk errors (fractions), albedos."""
    return {t.name: technique_entry(t, {k: Measured(v["value"], v["uncertainty"], unit="" if k.startswith("albedo.")
                                                    else "%") for k, v in metrics(m, t.name).items()})
            for t in m.techniques}
