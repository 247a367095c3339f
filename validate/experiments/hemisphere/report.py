"""Report sections of the ``hemisphere`` experiment: figures and tables from the measurements alone."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...figures import plots
from ...local_models import irradiance
from ...local_models.irradiance import hemisphere as hm
from ..base import Context, Figure, Section, Table
from ..formatting import col
from ..formatting import pct as _pct
from ..techniques import technique_entry
from .compute import EXACT_TOLERANCE, technique_measured
from .settings import NAME


def sections(m: dict[str, Any], ctx: Context) -> list[Section]:
    return [_formula_section(m, ctx), _technique_section(m)]


def _figures(m: dict[str, Any], ctx: Context) -> list[Figure]:
    w, tt = m["weights"], m["two_tone"]
    b = np.asarray(w["beta_deg"])
    p_w, r_w = ctx.figure_path(NAME, "weights.png")
    f, a = np.asarray(w["exact"]), np.asarray(w["red_book"])
    plots.save_line_plot(p_w, b[::20], {"exact ½(1 + cos β)": f[::20], "Red Book (piecewise sine)": a[::20],
                                        "difference a − f": (a - f)[::20]},
                         xlabel="tilt β from up (degrees)", ylabel="sky weight", title="Hemisphere blend weights")
    p_t, r_t = ctx.figure_path(NAME, "two_tone_error.png")
    series = {fm: np.maximum(np.asarray(tt["formulas"][fm]["relative_error"]), 1e-7) for fm in hm.FORMULAS}
    series["Red Book, analytic"] = np.maximum(np.asarray(tt["red_book_predicted"]), 1e-7)
    plots.save_line_plot(p_t, np.asarray(tt["beta_deg"]), series, xlabel="tilt β from up (degrees)",
                         ylabel="|E′ − E| / E (luminance)", title="Two-tone sky: error vs tilt (reference quadrature)",
                         logy=True, percent=True, hlines={"0.1 % (exactness tolerance)": EXACT_TOLERANCE})
    figs = [Figure(r_w, "blend weights vs tilt", 420), Figure(r_t, "two-tone sky: relative error vs tilt", 420)]
    suns = {n: r for n, r in m["skies"].items() if n.startswith("sunsky")}
    if suns:
        p_s, r_s = ctx.figure_path(NAME, "sunsky_error.png")
        plots.save_line_plot(p_s, np.asarray(next(iter(suns.values()))["beta_deg"]),
                             {f"{n.replace('sunsky_', '')} {fm}": np.asarray(r["formulas"][fm]["max_over_azimuth"])
                              for n, r in suns.items() for fm in hm.FORMULAS},
                             xlabel="tilt β from up (degrees)", ylabel="max over azimuth |E′ − E| / max E",
                             title="sunsky: error vs tilt", percent=True)
        figs.append(Figure(r_s, "sunsky (sun elevation 5°, 30°, 60°): error vs tilt, worst azimuth", 420))
    return figs


def _formula_section(m: dict[str, Any], ctx: Context) -> Section:
    s, mt = m["settings"], m["two_tone"]["meter"]
    t = mt["tests"]
    rows = [[f"{beta:g}", f"{mean:.5f} ± {se:.5f}", f"{t['exact']['predicted'][i]:.5f}", f"{t['exact']['z'][i]:+.2f}",
             f"{t['red_book']['predicted'][i]:.5f}", f"{t['red_book']['z'][i]:+.1f}"]
            for i, (beta, mean, se) in enumerate(zip(mt["beta_deg"], mt["mean"], mt["stderr"], strict=True))]
    meter_table = Table(["β (°)", "Mitsuba E, red ± s.e. (W/m²)", "exact π·C (W/m²)", "z (–)", "Red Book π·C (W/m²)",
                         "z (–)"], rows,
                        f"Irradiance meter: {mt['passes']} passes × {mt['film']}² pixels × {mt['spp']} spp per tilt; "
                        f"critical |z| = {t['exact']['critical_z']:.2f} (Šidák, α = 0.01).")
    sky_rows = [[n, f"{r['peak_irradiance_luminance']:.4g}", _pct(r["formulas"]["exact"]["max"]),
                 f"{r['formulas']['exact']['worst_beta_deg']:g}°", _pct(r["formulas"]["red_book"]["max"]),
                 f"{r['formulas']['red_book']['worst_beta_deg']:g}°", _pct(r["convergence"])]
                for n, r in m["skies"].items() if n.startswith("sunsky")]
    sky_table = Table(["environment", "peak E, Y (W/m²)", "exact-weight max (%)", "at β (°)", "Red Book max (%)",
                       "at β (°)", "ref. convergence (%)"], sky_rows,
                      "sunsky: max over tilts and azimuths of |E′ − E| / max E.")
    return Section("Hemisphere lighting: which formula is exact", [
        "For a sky of radiance L_s above the horizon and L_g below it, the view factor of the upper hemisphere from a "
        "plane tilted by β is (1 + cos β)/2, so E = π(L_s(1 + cos β)/2 + L_g(1 − cos β)/2): the cosine blend is exact. "
        "The Red Book's a = 1 − ½ sin β (β ≤ 90°), ½ sin β (β > 90°) agrees at 0°, 90° and 180° only; its error is "
        "predicted analytically and the reference must find exactly that error.",
        "Error measures: two-tone sky — per-tilt relative error |E′ − E|/E of the luminance; sunsky — |E′ − E| / "
        f"max_n E (luminance, peak irradiance over all normals), maximum over {s['azimuths']} azimuths. Reference: "
        "Mitsuba's envmap radiance integrated by the quadrature of validate.reference.irradiance "
        f"({2 * s['cells']} rows), and Mitsuba's irradiance meter."],
        figures=_figures(m, ctx), tables=[meter_table, sky_table])


def _technique_section(m: dict[str, Any]) -> Section:
    skies = list(m["skies"])
    names = list(next(iter(m["skies"].values()))["techniques"]) if skies else []
    rows = []
    for t in names:
        row = [t]
        for sky in skies:
            st = m["skies"][sky]["techniques"][t]["flux_luminance"]
            row.append(f"{_pct(st['mean'])} / {_pct(st['max'])} ± {_pct(st['max_uncertainty'])}")
        rows.append(row)
    return Section("Every irradiance technique under these skies", [
        "Each registered irradiance technique (the hemisphere techniques take C_sky = E(U)/π and C_ground = E(−U)/π "
        "from the map itself, exact for a two-tone sky; SH of order 1, 2, 4; plug-ins) on the tilt × azimuth normals, "
        "flux-normalised luminance error |Y(E′) − Y(E)| / Φ_Y (mean / max ± the reference's uncertainty); every metric "
        "of validate.metrics.irradiance_error is in results.json."],
        tables=[Table(["technique"] + [col(sky, "%") for sky in skies], rows, "flux_luminance mean / max per sky.")])


def _rel_at(tt: dict, formula: str, beta: float) -> float:
    betas = np.asarray(tt["beta_deg"])
    return float(np.asarray(tt["formulas"][formula]["relative_error"])[int(np.argmin(np.abs(betas - beta)))])


def findings(m: dict[str, Any]) -> list[str]:
    tt, w = m["two_tone"], m["weights"]
    ex, rb, mt = tt["formulas"]["exact"], tt["formulas"]["red_book"], tt["meter"]["tests"]
    f = [f"The cosine blend f = ½(1 + N·U) is exact for a two-tone sky: against the reference quadrature its largest "
         f"relative error is {ex['max_relative_error']:.2e} (quadrature uncertainty {ex['uncertainty']:.1e}), and "
         f"against Mitsuba's irradiance meter its largest |z| is {mt['exact']['max_abs_z']:.2f} "
         f"(critical {mt['exact']['critical_z']:.2f}).",
         f"The Red Book's piecewise-sine weight, called 'the actual analytic function', is not: its weight differs "
         f"from the exact one by up to {w['worst_abs_weight_difference']:.4f} = ½(√2 − 1) at β = "
         f"{w['worst_beta_deg']:g}° (and 135°), i.e. {_pct(w['worst_abs_weight_difference'])} of the sky−ground "
         f"difference. On this two-tone sky that is a relative irradiance error of "
         f"{_pct(_rel_at(tt, 'red_book', 45.0))} "
         f"at 45° and {_pct(rb['max_relative_error'])} at its worst tilt, {rb['worst_beta_deg']:g}° (luminance; the "
         f"meter rejects it with |z| = {mt['red_book']['max_abs_z']:.0f})."]
    for name, r in m["skies"].items():
        if not name.startswith("sunsky"):
            continue
        fe, fr = r["formulas"]["exact"], r["formulas"]["red_book"]
        fl = {t: r["techniques"][t]["flux_luminance"]["max"] for t in ("hemisphere", "sh1", "sh9")
              if t in r["techniques"]}
        f.append(f"{name}: calibrated at the poles (C_sky = E(up)/π, C_ground = E(down)/π), the cosine blend errs by "
                 f"up to {_pct(fe['max'])} of the peak irradiance (worst tilt {fe['worst_beta_deg']:g}°, mean "
                 f"{_pct(fe['mean'])}), the Red Book weight by up to {_pct(fr['max'])} (worst tilt "
                 f"{fr['worst_beta_deg']:g}°): the sun's direction, which neither formula sees, dominates. Flux-"
                 "normalised max: " + ", ".join(f"{t} {_pct(v)}" for t, v in fl.items()) + ".")
    return f


def summary(m: dict[str, Any]) -> str:
    return ("Hemisphere lighting C = w·C_sky + (1 − w)·C_ground with the cosine weight w = ½(1 + N·U) and with "
            "the Red Book's piecewise-sine weight, against Mitsuba: its irradiance meter and a deterministic "
            "quadrature of its radiance, under a two-tone sky and under sunsky (sky + sun); every registered "
            "irradiance technique on the same skies.")


def data(m: dict[str, Any]) -> dict[str, Any]:
    """``experiments.hemisphere``'s own keys: the worst weight difference, the two-tone analysis, the skies."""
    keep = ("worst_beta_deg", "worst_abs_weight_difference")
    return {"weights": {k: v for k, v in m["weights"].items() if k in keep},
            "two_tone": m["two_tone"], "sunsky": {k: v for k, v in m["skies"].items() if k.startswith("sunsky")},
            "skies": {k: v["techniques"] for k, v in m["skies"].items()}}


def techniques(m: dict[str, Any]) -> dict[str, Any]:
    """``experiments.hemisphere.techniques.<name>``: the worst-sky values and every sky's metrics."""
    return {tech.name: technique_entry(tech, technique_measured(m, tech.name),
                                       skies={n: sky["techniques"][tech.name] for n, sky in m["skies"].items()})
            for tech in irradiance}
