"""The specular part of ``arealights``: findings, its section, its technique entries and its ``results.json`` data."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ....figures import plots
from ....local_models import family
from ....local_models.specular_arealight.ltc import (
    load_table,
)
from ...base import Figure, Section, Table
from ...formatting import col
from ...techniques import technique_entry
from ..settings import NAME
from .claims import TUBE, TUBE_UNNORMALIZED, measured, rel_error, technique_metrics, tube_rel_error
from .compute import CONFIGS, RENDER_SIGMA, SHAPES, TUBE_AXES, TUBE_RADIUS, TUBE_VARIANTS


def findings(m: dict[str, Any]) -> list[str]:
    s = m["settings"]
    out = []
    for t in m["techniques"]:
        d = technique_metrics(m, t)
        for shape in SHAPES:
            if f"rel_err.{shape}" not in d:
                continue
            by_a = ", ".join(f"α = {a:g}: {100 * d[f'rel_err.{shape}.a{a:g}']['value']:.2f} %" for a in s["alphas"])
            by_s = ", ".join(f"σ = {x:g}°: {100 * d[f'rel_err.{shape}.s{x:g}']['value']:.2f} %"
                             for x in s["sigmas_deg"])
            rows = [r for r in m["rows"] if r["shape"] == shape and t in r["techniques"]]
            bias = sum(r["techniques"][t] - r["ref"] for r in rows) / sum(r["ref"] for r in rows)
            out.append(f"{t} under a {shape} light vs Mitsuba roughconductor (GGX, F = 1): Σ|ΔL|/ΣL = "
                       f"{100 * d[f'rel_err.{shape}']['value']:.2f} ± {100 * d[f'rel_err.{shape}']['uncertainty']:.2f} "
                       f"% over {len(rows) // (len(s['alphas']) * len(s['sigmas_deg']))} configurations × "
                       f"{len(s['alphas'])} α × {len(s['sigmas_deg'])} σ "
                       f"(signed Σ ΔL/ΣL = {100 * bias:+.1f} %); by roughness {by_a}; by size {by_s}.")
    rc = m.get("render_check") or []
    if rc:
        z = [abs(r["render"] - r["quadrature"]) / max(r["se"], 1e-300) for r in rc]
        rel = max(r["se"] / r["quadrature"] for r in rc)
        out.insert(0, f"The specular reference (Mitsuba BSDF.eval integrated over the emitter) agrees with Mitsuba's "
                      f"rendered radiance in all {len(rc)} shape × α × configuration checks: max |z| = {max(z):.2f} "
                      f"(render standard errors ≤ {100 * rel:.2f} % of L).")
    out += tube_findings(m)
    t = load_table()
    out.append(f"LTC table ({t.size}×{t.size}, fitted by scripts/fit_ltc.py): fit error ∫|E·D − f cos|/E mean "
               f"{t.l1_error.mean():.3f}, median {np.median(t.l1_error):.3f}, max {t.l1_error.max():.3f} (at grazing "
               "view, mid roughness).")
    return out


def tube_findings(m: dict[str, Any]) -> list[str]:
    """Karis's tube light and its variants vs Mitsuba: by roughness, length and axis orientation."""
    rows = [r for r in m["rows"] if r["shape"] == "tube" and TUBE in r["techniques"]]
    if not rows:
        return []
    s = m["settings"]
    names = [TUBE, *(n for n in (TUBE_UNNORMALIZED,) if n in rows[0]["techniques"]), *TUBE_VARIANTS]
    ref = sum(r["ref"] for r in rows)

    def val(r: dict[str, Any], n: str) -> float:
        return r["tube_variants"][n] if n in TUBE_VARIANTS else r["techniques"][n]

    parts = []
    for n in names:
        signed = sum(val(r, n) - r["ref"] for r in rows) / ref
        by_a = ", ".join(f"{100 * tube_rel_error([r for r in rows if r['alpha'] == a], n)['value']:.1f}"
                         for a in s["alphas"])
        by_l = ", ".join(f"{100 * tube_rel_error([r for r in rows if r['sigma_deg'] == x], n)['value']:.1f}"
                         for x in s["sigmas_deg"])
        by_ax = ", ".join(f"{ax} {100 * tube_rel_error([r for r in rows if r['axis'] == ax], n)['value']:.1f}"
                          for ax in TUBE_AXES)
        parts.append(f"{n}: {100 * tube_rel_error(rows, n)['value']:.1f} % (signed {100 * signed:+.1f} %; by α "
                     f"{by_a} %; by length {by_l} %; {by_ax} %)")
    lengths = ", ".join(f"{2 * math.tan(math.radians(x)):.2f}" for x in s["sigmas_deg"])
    p_best, err_best = best_line_power(rows)
    return [f"Tube lights (capsule of radius {TUBE_RADIUS:.3f}, length ℓ = {lengths} at unit distance; α = "
            f"{', '.join(f'{a:g}' for a in s['alphas'])}; {len(rows)} configurations) vs Mitsuba, Σ|ΔL|/ΣL: "
            + "; ".join(parts) + f". Over powers p of the line factor (α/α′_line)^p on a 0.05 grid in [0, 2], "
            f"Σ|ΔL|/ΣL is smallest at p = {p_best:.2f} ({100 * err_best:.1f} %): Karis's p = 1 over-darkens these "
            "tubes on aggregate, p = 0 over-brightens them."]


def best_line_power(rows: list[dict[str, Any]]) -> tuple[float, float]:
    """(p, Σ|ΔL|/ΣL) minimising the error of L(p) = L_no_line · (L_tube / L_no_line)^p — the tube technique with its
    line factor raised to p — over p ∈ {0, 0.05, …, 2} (per row L_tube / L_no_line is the line factor itself)."""
    ref = np.array([r["ref"] for r in rows])
    base = np.array([r["tube_variants"]["no_line"] for r in rows])
    factor = np.array([r["techniques"][TUBE] for r in rows]) / np.maximum(base, 1e-300)
    ps = np.round(np.arange(0.0, 2.0 + 1e-9, 0.05), 2)
    errs = [float(np.sum(np.abs(base * factor ** p - ref)) / ref.sum()) for p in ps]
    i = int(np.argmin(errs))
    return float(ps[i]), errs[i]


def section(m: dict[str, Any], ctx: Any) -> Section:
    s = m["settings"]
    techs = m["techniques"]
    rows = []
    for shape in SHAPES:
        for a in s["alphas"]:
            for sg in s["sigmas_deg"]:
                sel = [r for r in m["rows"] if r["shape"] == shape and r["alpha"] == a and r["sigma_deg"] == sg]
                cells = []
                for t in techs:
                    if t in sel[0]["techniques"]:
                        v = rel_error(sel, t)
                        cells.append(f"{100 * v['value']:.2f} ± {100 * v['uncertainty']:.2f} %")
                    else:
                        cells.append("—")
                rows.append([shape, f"{a:g}", f"{sg:g}°", *cells])
    table = Table(["shape", "α (–)", "σ (°)", *(col(t, "%") for t in techs)], rows,
                  "Σ|L − L_ref| / Σ L_ref over the configurations (θ_v, θ_l, Δφ) "
                  f"= {', '.join(str(c) for c in CONFIGS)}; ± the reference quadrature. A tube's σ is the half-angle "
                  f"of its length (ℓ = 2 tan σ; radius {TUBE_RADIUS:.3f}), both axis orientations pooled.")
    rtab = Table(["shape", "α (–)", "(θ_v, θ_l, Δφ) (°)", "Mitsuba render (W/(m²·sr))", "quadrature (W/(m²·sr))",
                  "z (–)"],
                 [[r["shape"], f"{r['alpha']:g}", str(tuple(r["config"])), f"{r['render']:.5f} ± {r['se']:.5f}",
                   f"{r['quadrature']:.5f}", f"{(r['render'] - r['quadrature']) / max(r['se'], 1e-300):+.2f}"]
                  for r in m.get("render_check", [])],
                 f"The reference checked against Mitsuba's render (σ = {RENDER_SIGMA:g}°, direct integrator, "
                 f"{s['render_pixels']}² pixels × {s['render_spp']} spp).")
    p, rel = ctx.figure_path(NAME, "specular_error_vs_alpha.png")
    series = {f"{t} {shape}": [technique_metrics(m, t)[f"rel_err.{shape}.a{a:g}"]["value"] for a in s["alphas"]]
              for t in techs for shape in SHAPES if f"rel_err.{shape}" in technique_metrics(m, t)}
    plots.save_line_plot(p, s["alphas"], series, xlabel="GGX α", ylabel="Σ|ΔL| / ΣL", title="Specular area lights "
                         "vs Mitsuba", logy=True)
    p2, rel2 = ctx.figure_path(NAME, "specular_error_vs_size.png")
    series2 = {f"{t} {shape}": [technique_metrics(m, t)[f"rel_err.{shape}.s{x:g}"]["value"] for x in s["sigmas_deg"]]
               for t in techs for shape in SHAPES if f"rel_err.{shape}" in technique_metrics(m, t)}
    plots.save_line_plot(p2, s["sigmas_deg"], series2, xlabel="light half-angle σ (degrees)", ylabel="Σ|ΔL| / ΣL",
                         title="Specular area lights vs Mitsuba", logy=True)
    return Section("Specular area lights: LTC and representative point vs Mitsuba roughconductor", [
        "GGX (F = 1) under rectangle, disc, sphere and tube (capsule) emitters of half-angle σ at unit distance; "
        "reference = Mitsuba's "
        f"BSDF.eval integrated over the emitter ({s['nodes']} Gauss–Legendre nodes per axis, ± the difference to "
        f"{s['nodes'] // 2}), itself checked against Mitsuba's rendered radiance."],
        figures=[Figure(rel, "error vs roughness", 480), Figure(rel2, "error vs light size", 480)],
        tables=[rtab, table])


def techniques(m: dict[str, Any]) -> dict[str, Any]:
    return {t.name: technique_entry(t, measured(m, t.name)) for t in family("specular_arealight")
            if t.name in m["techniques"]}


def sections(m: dict[str, Any], ctx: Any) -> list[Section]:
    return [section(m, ctx)]


def data(m: dict[str, Any]) -> dict[str, Any]:
    """``experiments.arealights.specular``: every measurement of the part, its settings included."""
    return {"specular": m}
