"""Experiment ``ibl``, part 5: findings (sentences with numbers) and report sections (figures, tables)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...figures import plots
from ...local_models.specular import split_sum as ss
from ...scenes.ibl_scenes import ALBEDO, ANGLE_BINS, BLEND_EXPONENT, BLEND_WEIGHT, CAMERA_OFFSET_DEG
from ..base import Context, Figure, Section, Table
from ..formatting import pct, pm
from .claims import technique_results
from .compute import CRATER_AO, MAP_MAX_ERROR, Comparison, IblMeasurements
from .settings import NAME, Settings

SEC_A = "Diffuse irradiance maps: resolution"
SEC_B = "Diffuse irradiance on a rendered sphere (maps and irradiance techniques)"
SEC_C = "Specular techniques vs the modified-Phong BSDF"
SEC_M = "The seed's mixing shader"
SEC_D = "Specular techniques vs roughconductor and roughplastic (GGX)"
SEC_K = "Checks of the reference BSDFs"
SEC_E = "Concave shape: what local IBL misses"
MIDS = 0.5 * (ANGLE_BINS[:-1] + ANGLE_BINS[1:])


class Figures:
    """Writes figures under figures/ibl/ and remembers them per section."""

    def __init__(self, ctx: Context, heatmaps_per_section: int | None = None):
        self.ctx = ctx
        self.items: dict[str, list[Figure]] = {}
        self.heat_budget = heatmaps_per_section
        self.heat_count: dict[str, int] = {}

    def add(self, section: str, rel: str, caption: str, width: int | None = None) -> None:
        self.items.setdefault(section, []).append(Figure(rel, caption, width))

    def grid(self, section: str, name: str, images: list[np.ndarray], titles: list[str], caption: str) -> None:
        p, rel = self.ctx.figure_path(NAME, name)
        plots.save_image_grid(p, [np.nan_to_num(i, nan=0.0) for i in images], titles)
        self.add(section, rel, caption)

    def heat(self, section: str, name: str, values: np.ndarray, title: str, caption: str,
             vmax: float | None = None, label: str = "relative error") -> None:
        if self.heat_budget is not None and self.heat_count.get(section, 0) >= self.heat_budget:
            return
        self.heat_count[section] = self.heat_count.get(section, 0) + 1
        p, rel = self.ctx.figure_path(NAME, name)
        plots.save_heatmap(p, values, title, label, vmax=vmax, percent=label.startswith("relative"))
        self.add(section, rel, caption, 300)

    def line(self, section: str, name: str, x: Any, series: dict, xlabel: str, ylabel: str, title: str,
             caption: str, **kw: Any) -> None:
        p, rel = self.ctx.figure_path(NAME, name)
        plots.save_line_plot(p, x, series, xlabel, ylabel, title, **kw)
        self.add(section, rel, caption, 400)


def fnum(x: float) -> str:
    """FLIP value (3 decimals), or "—" when skipped (quick settings)."""
    return "—" if x is None or not np.isfinite(x) else f"{x:.3f}"




# ---------------------------------------------------------------------------------------------
# Findings
# ---------------------------------------------------------------------------------------------

def findings(m: IblMeasurements) -> list[str]:
    return diffuse_findings(m) + specular_findings(m) + [concave_finding(m)]


def diffuse_findings(m: IblMeasurements) -> list[str]:
    mp, st = m.maps, m.st
    i8, i32 = st.faces.index(8), st.faces.index(32)
    per = {n: float(np.sqrt(s["cube"]["max"][i8] / s["cube"]["max"][i32])) for n, s in mp.sweeps.items()}
    xc = m.diffuse.consistency.stats
    out = [f"Smallest irradiance-map resolution keeping the max error < 1 % (of the peak irradiance, all "
           f"{len(mp.sweeps)} environments): cube faces {mp.face}² ({6 * mp.face ** 2 if mp.face else '—'} texels), "
           f"lat-long {mp.height}×{2 * mp.height if mp.height else '—'}; the independent check at {mp.claim_face}² "
           f"gives {pm(mp.check.max, mp.check.uncertainty)} (worst: {mp.check.env}). From faces 8² to 32² the max "
           "error falls " + ", ".join(f"{r:.1f}× ({n})" for n, r in per.items()) + " per doubling: 4× would be "
           "second order (bilinear, smooth E); a source much smaller than a texel leaves a kink in E at its "
           "terminator, where interpolation is first order (2×).",
           "Reference cross-check: Mitsuba's Lambertian sphere vs ρ/π × quadrature: bias "
           f"{pm(xc.bias, xc.bias_uncertainty)}, mean |error| {pct(xc.mean)} (MC noise {pct(xc.mean_uncertainty)})."]
    techs = m.diffuse.techniques
    out.append("Irradiance techniques on the rendered Lambertian sphere (mean relative error, bias "
               "Σ(Y_model − Y_ref)/ΣY_ref): "
               + "; ".join(f"{k} {pm(c.rel.stats.mean, c.rel.stats.mean_uncertainty)}, {pct(c.rel.stats.bias)}"
                           for k, c in techs.items()) + ".")
    return out


def specular_findings(m: IblMeasurements) -> list[str]:
    out = []
    for tech, comps in m.specular.comparisons.items():
        if comps:
            out.append(f"Specular technique {tech}: mean relative error " + "; ".join(
                f"{c.group} {c.parameter}: {pm(c.rel.stats.mean, c.rel.stats.mean_uncertainty)} (θ_v < 10°: "
                f"{pct(c.bands[0].mean)}, 80–90°: {pct(c.bands[-1].mean)})" for c in comps.values()) + ".")
    ratios = {a: ss.centre_weight_ratio(a) for a in m.st.alphas}
    out.append("Why the split sum errs even at normal incidence: the n·l-weighted prefilter lobe K_α is normalised "
               "by ∫K_α, the DFG table by the BRDF's albedo A + B, so a small source at the lobe centre is "
               "over-weighted by " + ", ".join(f"{r:.3f} (α = {a:g})" for a, r in ratios.items())
               + "; a uniform environment is exact (claim ibl.split_sum.constant_environment).")
    for key, v in m.phong_ni.items():
        out.append(f"Phong map at θ_v ≤ 5°, s = {key}: Σ|ΔY| is {v['ratio']:.2f} ± {v['ratio_u']:.2f} of the "
                   f"independent bound for the s + 1 map and {v['ratio_s']:.2f} for the same-exponent map.")
    mx = m.mix
    out.append(f"Mixing shader (w = {BLEND_WEIGHT:g}, s = {BLEND_EXPONENT:g}): bias {pct(mx.bias)} against "
               f"blendbsdf, {pm(mx.predicted, mx.sigma)} predicted by its ingredient maps, mean |error| "
               f"{pct(mx.comparison.rel.stats.mean)}, FLIP {fnum(mx.comparison.flip.mean)}; with DiffusePercent = 0.9 "
               f"the bias is {pct(mx.bias_unlit)}.")
    return out


def concave_finding(m: IblMeasurements) -> str:
    c = m.concave.data
    tot, occ = c["map vs direct render"]["crater"]["mean"], c["unoccluded reference vs direct"]["crater"]["mean"]
    return (f"Dented sphere (Lambertian, {c['crater_pixels']} crater pixels with AO < {CRATER_AO:g}): the irradiance "
            f"map ({m.maps.claim_face}²) is off by {pct(tot)} on average in the crater against Mitsuba's direct "
            f"lighting; the exact unoccluded irradiance by {pct(occ)} — missing occlusion is "
            f"{pct(c['occlusion_share_crater'])} of the crater error — while the map differs from it by only "
            f"{pct(c['map vs unoccluded reference']['crater']['mean'])}. AO × map leaves "
            f"{pct(c['AO × map vs direct']['crater']['mean'])}; with inter-reflections (max_depth "
            f"{m.st.interreflection_depth}) the map errs by "
            f"{pct(c['map vs render with inter-reflections']['crater']['mean'])} and AO × map by "
            f"{pct(c['AO × map vs inter-reflections']['crater']['mean'])} in the crater.")


# ---------------------------------------------------------------------------------------------
# Sections
# ---------------------------------------------------------------------------------------------

def comparison_row(c: Comparison) -> list[Any]:
    s = c.rel.stats
    return [c.group, c.parameter, c.label, pm(s.mean, s.mean_uncertainty), pct(s.p95), pm(s.bias, s.bias_uncertainty),
            pct(c.bands[0].mean), fnum(c.flip.mean)]


BIAS_HEADER = "bias Σ(Y_model − Y_ref)/ΣY_ref ± σ (%)"  # signed: negative = the technique is too dark
COMPARISON_HEADERS = ["BSDF", "parameter", "technique", "mean |ΔY|/Y ± MC (%)", "p95 (%)", BIAS_HEADER,
                      "θ_v < 10° (%)", "FLIP mean (–)"]


def sections(m: IblMeasurements, ctx: Context) -> list[Section]:
    figs = Figures(ctx, m.st.heatmaps_per_section)
    secs = [map_section(m, figs), diffuse_section(m, figs), *specular_sections(m, figs), mix_section(m, figs),
            checks_section(m), concave_section(m, figs)]
    for sec in secs:
        sec.figures = figs.items.get(sec.title, [])
    return secs


def map_section(m: IblMeasurements, figs: Figures) -> Section:
    st, mp = m.st, m.maps
    for kind, label in (("cube", "cube face size N (6·N² texels)"), ("latlong", "lat-long height H (H × 2H)")):
        figs.line(SEC_A, f"sweep_{kind}.png", st.faces if kind == "cube" else st.heights,
                  {n: np.array(s[kind]["max"]) for n, s in mp.sweeps.items()}, label, "max |ΔE| / max E",
                  f"irradiance {kind} map: max error vs resolution",
                  f"Max error of bilinear lookups in the {kind} irradiance map at {st.test_normals} quasi-uniform "
                  "normals, relative to the peak irradiance; dashed: the 1 % criterion.",
                  logx=True, logy=True, hlines={"1 %": MAP_MAX_ERROR}, percent=True)
    rows = []
    for name, s in mp.sweeps.items():
        first = {k: next((n for n, x, u in zip(s[k]["size"], s[k]["max"], s[k]["max_uncertainty"], strict=True)
                          if x + u < MAP_MAX_ERROR), "—") for k in ("cube", "latlong")}
        rows.append([name, first["cube"], first["latlong"], pct(s["cube"]["max"][0]), pct(s["cube"]["max"][-1]),
                     pct(s["latlong"]["max"][-1])])
    return Section(SEC_A, [
        f"Cube maps (faces {st.faces[0]}…{st.faces[-1]}) and lat-long maps of E(n) by brute-force cosine convolution, "
        f"looked up bilinearly (cube seams: padded faces), against the irradiance quadrature at {st.test_normals} "
        f"quasi-uniform normals; the claim re-checks the chosen size on {st.claim_normals} rotated normals.",
        "SH9-derived maps differ from the convolution maps by at most: "
        + "; ".join(f"{k} {pct(v[0])} of Φ" for k, v in mp.sh.items()) + " (bound 9.375 %)."],
        tables=[Table(["environment", "smallest cube face < 1 % (texels)",
                       "smallest lat-long height < 1 % (texels)",
                       f"cube {st.faces[0]}² max (%)", f"cube {st.faces[-1]}² max (%)",
                       f"lat-long {st.heights[-1]} max (%)"],
                      rows, "Max error relative to the peak irradiance.")])


def diffuse_section(m: IblMeasurements, figs: Figures) -> Section:
    dif = m.renders["diffuse"]
    comps = m.diffuse.maps + list(m.diffuse.techniques.values())
    figs.grid(SEC_B, "diffuse_images.png", [dif.mean] + [c.approx for c in comps],
              ["Mitsuba"] + [c.label for c in comps],
              f"Lambertian sphere (ρ = {ALBEDO:g}) under {m.scene.render_env.name}: Mitsuba and every irradiance map "
              "and registered irradiance technique (same exposure).")
    for k, c in enumerate(comps):
        figs.heat(SEC_B, f"diffuse_err_{k}.png", c.rel.error, f"{c.label}: |ΔY|/Y",
                  f"Relative error of {c.label} (FLIP mean {fnum(c.flip.mean)}).")
    return Section(SEC_B, [f"Lambertian sphere rendered by Mitsuba ({m.st.size}² pixels, {m.st.spp} spp in "
                           f"{m.st.passes} passes, one ray per pixel centre) and shaded from its G-buffer normals by "
                           "each irradiance map and each technique of the irradiance family (plug-ins included)."],
                   tables=[Table(COMPARISON_HEADERS, [comparison_row(c) for c in comps])])


def specular_sections(m: IblMeasurements, figs: Figures) -> list[Section]:
    out = []
    for title, models in ((SEC_C, ("phong",)), (SEC_D, ("ggx", "ggx_plastic"))):
        cases = [c for c in m.specular.cases if c.model in models]
        comps = [(case, tech, m.specular.comparisons[tech][case.key]) for case in cases
                 for tech in m.specular.comparisons if case.key in m.specular.comparisons[tech]]
        imgs, titles = [], []
        for case in cases:
            imgs.append(m.renders[case.key].mean)
            titles.append(f"Mitsuba {case.group} {case.label}")
            for c in (c for cs, _, c in comps if cs is case):
                imgs.append(c.approx)
                titles.append(c.label)
        if imgs:
            figs.grid(title, f"images_{models[0]}.png", imgs, titles,
                      "Mitsuba renders and every registered specular technique supporting the BRDF.")
        for case, tech, c in comps:
            figs.heat(title, f"err_{tech}_{case.key}.png", c.rel.error, f"{tech}, {case.label}: |ΔY|/Y",
                      f"{tech} on {case.group} {case.label}: relative error (FLIP mean {fnum(c.flip.mean)}).")
        for tech in dict.fromkeys(t for _, t, _ in comps):  # registry order (a set's order varies with the hash seed)
            figs.line(title, f"angle_{models[0]}_{tech}.png", MIDS,
                      {f"{case.label}": np.array([b.mean for b in c.bands]) for case, t, c in comps if t == tech},
                      "view angle θ_v (deg)", "mean |ΔY|/Y", f"{tech}: error vs view angle",
                      "Mean relative error per 10° band of θ_v = angle(n, v).", logy=True, percent=True)
        out.append(Section(title, ["Every technique of the specular family that declares the BRDF model is run "
                                   "on the rendered sphere's G-buffer (normals, views)."],
                           tables=[Table(COMPARISON_HEADERS, [comparison_row(c) for _, _, c in comps])]))
    return out


def mix_section(m: IblMeasurements, figs: Figures) -> Section:
    blend, cm = m.renders["blend"], m.mix.comparison
    figs.grid(SEC_M, "mix_images.png", [blend.mean, cm.approx], ["Mitsuba blendbsdf", "mixing shader"],
              f"blendbsdf((1−w)·diffuse ρ={ALBEDO:g} + w·modified Phong s={BLEND_EXPONENT:g}, w={BLEND_WEIGHT:g}) and "
              "the seed's shader with BaseColor = (1−w)ρ, DiffusePercent = 1, SpecularPercent = w.")
    figs.heat(SEC_M, "mix_err.png", cm.rel.error, "mixing shader: |ΔY|/Y",
              f"Relative error of the mixing shader (FLIP mean {fnum(cm.flip.mean)}).")
    return Section(SEC_M, ["mix(BaseColor, diffuse·BaseColor, DiffusePercent) then mix(color, specular + color, "
                           "SpecularPercent): with DiffusePercent = 1 this is the physical blend; DiffusePercent < 1 "
                           "adds an unlit BaseColor term no BSDF has."],
                   tables=[Table(COMPARISON_HEADERS, [comparison_row(cm)])])


def checks_section(m: IblMeasurements) -> Section:
    ch = m.chi2
    rows = [["χ² (sample vs pdf)", f"s = {s:g}, μ = {c:g}", f"p = {p:.3g}", f"p = {q:.2g} (pdf of s + 1)"]
            for s, c, p, q in zip(ch.exponents, ch.cos_views, ch.p_values, ch.p_values_off_by_one, strict=True)]
    for name, z in (("furnace (path integrator)", m.furnace), ("split sum, constant env.", m.split_constant)):
        zs, zp = z.z(), z.z(z.perturbed)
        rows += [[name, lab, f"{mv:.5f} vs {ev:.5f} ± {se:.1e} (|z| = {a:.2f})", f"|z| = {b:.1f}"]
                 for lab, mv, ev, se, a, b in zip(z.labels, z.measured, z.expected, z.stderr, zs, zp, strict=True)]
    return Section(SEC_K, ["The modified-Phong BSDF is a Python plug-in, so its sampling, eval() and pdf() are "
                           "checked: χ² of sample() against pdf(), and a white furnace through the path integrator "
                           "(MIS) against the albedo by quadrature. The split-sum DFG table is checked against "
                           "Mitsuba's roughconductor in the same furnace."],
                   tables=[Table(["check", "case", "result", "power check"], rows)])


def concave_section(m: IblMeasurements, figs: Figures) -> Section:
    c = m.concave
    figs.grid(SEC_E, "dent_images.png", list(c.images.values()),
              ["Mitsuba direct", f"Mitsuba depth {m.st.interreflection_depth}", "irradiance map", "unoccluded exact",
               "AO × map"],
              "Dented sphere (Lambertian): renders, the map, the exact unoccluded irradiance and AO × map.")
    figs.heat(SEC_E, "dent_ao.png", c.ao, "ambient occlusion", "Cosine-weighted visibility (Mitsuba ray casts).",
              vmax=1.0, label="visibility")
    figs.heat(SEC_E, "dent_err_map.png", c.errors["map vs direct render"], "map vs direct: |ΔY|/Y",
              "Relative error of the irradiance map.")
    rows = [[k, pm(v["all"]["mean"], v["all"]["mean_uncertainty"]), pm(v["crater"]["mean"],
             v["crater"]["mean_uncertainty"]), pct(v["crater"]["bias"]), fnum(v["flip"])]
            for k, v in c.data.items() if isinstance(v, dict)]
    return Section(SEC_E, ["Local IBL shades every point as if it saw the whole hemisphere. The exact unoccluded "
                           "irradiance (quadrature at the G-buffer normals) isolates the occlusion error from the "
                           "map's own; AO is Mitsuba-ray-cast cosine-weighted visibility."],
                   tables=[Table(["comparison", "mean, all pixels (%)", "mean, crater (%)",
                                  "bias, crater Σ(Y_model − Y_ref)/ΣY_ref (%)", "FLIP (–)"], rows)])


def data(m: IblMeasurements) -> dict[str, Any]:
    """The JSON part of the result (besides claims, findings, sections and techniques)."""
    z = {name: {"labels": c.labels, "measured": c.measured.tolist(), "expected": c.expected.tolist(),
                "stderr": c.stderr.tolist(), "allowance": c.allowance.tolist(), "z": c.z().tolist(),
                "z_perturbed": c.z(c.perturbed).tolist(), "critical": c.critical}
         for name, c in (("furnace", m.furnace), ("split_sum_constant", m.split_constant))}
    comps = (m.diffuse.maps + list(m.diffuse.techniques.values()) + [m.mix.comparison]
             + [c for d in m.specular.comparisons.values() for c in d.values()])
    return {"resolution_sweep": m.maps.sweeps, "reported_face": m.maps.face, "reported_height": m.maps.height,
            "sh_vs_convolution": {k: {"max_flux_fraction": v[0], "uncertainty": v[1]} for k, v in m.maps.sh.items()},
            "phong_normal_incidence": m.phong_ni, "concave": m.concave.data,
            "mix": {"bias": m.mix.bias, "predicted": m.mix.predicted, "sigma": m.mix.sigma, "z": m.mix.z(),
                    "bias_unlit": m.mix.bias_unlit, "z_unlit": m.mix.z(m.mix.bias_unlit)},
            "chi2": {"exponents": m.chi2.exponents, "cos_views": m.chi2.cos_views, "p_values": m.chi2.p_values,
                     "p_values_off_by_one": m.chi2.p_values_off_by_one, "level": m.chi2.level},
            **z, "comparisons": [c.row() for c in comps]}


def summary(m: IblMeasurements) -> str:
    return ("Diffuse irradiance maps, specular techniques (Phong-prefiltered maps, split-sum GGX, plug-ins), the "
            "seed's mixing shader against the irradiance quadrature and Mitsuba path-traced renders of a sphere "
            f"and a dented sphere under {m.scene.render_env.name} (maps: faces {m.maps.claim_face}²).")


def techniques(m: IblMeasurements) -> dict[str, Any]:
    """``experiments.ibl.techniques.<name>`` (:func:`.claims.technique_results`)."""
    return technique_results(m)[0]


def reported_settings(st: Settings, m: IblMeasurements, ctx: Context) -> dict[str, Any]:
    """``experiments.ibl.settings``: the sweep's effort, the rendered environment and the run's seed."""
    return {"quick": st.quick, "environments": list(st.sweep_envs), "render_environment": m.scene.render_env.name,
            "faces": list(st.faces), "heights": list(st.heights), "image": st.size, "spp": st.spp,
            "passes": st.passes, "exponents": list(st.exponents), "alphas": list(st.alphas),
            "camera_offset_deg": CAMERA_OFFSET_DEG, "seed": ctx.seed}
