"""``engines`` report sections: tables (and the face-size plots) from the measurements alone."""

from __future__ import annotations

from ..base import Context, Figure, Section, Table
from .claims import Measurements
from .compute import BABYLON_CLAMP
from ..formatting import pct

METRICS = ("flux_luminance", "flux_rgb", "relative", "peak")


def _names(m: Measurements) -> list[str]:
    names: list[str] = []
    for r in m.environments.values():
        names += [n for n in r["techniques"] if n not in names]
    return names


def metric_tables(m: Measurements) -> list[Table]:
    """One table per metric: environment × technique, mean / max; the reference's uncertainty (the same
    for every technique of a row) in its own column."""
    names = _names(m)
    tables = []
    for metric in METRICS:
        rows = []
        for env, r in m.environments.items():
            sts = [r["techniques"].get(n, {}).get("errors", {}).get(metric) for n in names]
            unc = max((st["max_uncertainty"] for st in sts if st), default=0.0)
            rows.append([env, f"{r['max_face_texel']:.4g}", f"± {pct(unc)}"]
                        + ["—" if st is None else f"{pct(st['mean'])} / {pct(st['max'])}" for st in sts])
        tables.append(Table(["environment", "largest face texel", "reference ±"] + names, rows,
                            f"{metric}: mean / max over normals; every registered irradiance technique."))
    return tables


def decomposition_table(m: Measurements) -> Table:
    names = [n for n in _names(m) if n != "sh9"]
    rows = []
    for env, r in m.environments.items():
        rows.append([env, f"{r['face_flux_error']:.2g}", "yes" if r["above_clamp"] else "no"]
                    + [f"{r['techniques'][n]['faces_deviation']:.3g}" if n in r["techniques"] else "—" for n in names]
                    + [f"{r['polynomial_double_lobe_deviation']:.3g}" if "polynomial_double_lobe_deviation" in r
                       else "—"])
    return Table(["environment", "face flux error", f"faces > {BABYLON_CLAMP:g}"]
                 + [f"{n}: |E − E_SH9(faces)|/Φ" for n in names] + ["polynomial vs lobe-twice model"], rows,
                 "Each engine against the exact-solid-angle SH9 of the very faces it received (max over normals and "
                 "channels, fraction of Φ).")


def clamp_table(m: Measurements) -> Table:
    rows = []
    for env, r in m.environments.items():
        if "babylon_sh_unclamped" not in r or "babylon_sh" not in r["techniques"]:
            continue
        a = r["techniques"]["babylon_sh"]["errors"]["flux_luminance"]
        b = r["babylon_sh_unclamped"]["flux_luminance"]
        rows.append([env, f"{r['max_map_texel']:.4g}", f"{r['max_face_texel']:.4g}", pct(r["clamp_share"]),
                     f"{pct(a['mean'])} / {pct(a['max'])}", f"{pct(b['mean'])} / {pct(b['max'])}",
                     f"{r['half_overflow_texels']}" if "half_overflow_texels" in r else "—",
                     ("finite" if r["half_finite"] else "NOT finite") if "half_finite" in r else "—",
                     f"{r['half_deviation']:.3g}" if r.get("half_deviation") is not None else "—"])
    return Table(["environment", "largest map texel", "largest face texel", "flux removed by the clamp",
                  "babylon_sh (clamp)", "babylon_sh (no clamp)", "texels > 65504", "three_sh half-float",
                  "half vs float32 |ΔE|/Φ"], rows,
                 f"Babylon's per-channel clamp at {BABYLON_CLAMP:g} (flux-normalised luminance error, mean / max) and "
                 "three.js with half-float faces.")


def sweep_section(m: Measurements, ctx: Context) -> Section:
    from ...report import plots

    tables, figs = [], []
    for env, s in m.sweeps.items():
        rows = []
        for i, size in enumerate(s["sizes"]):
            rows.append([size, f"{s['max_face_texel'][i]:.4g}", pct(s["clamp_share"][i])]
                        + [f"{pct(t['mean'][i])} / {pct(t['max'][i])} ({t['faces_deviation'][i]:.2g})"
                           for t in s["techniques"].values()])
        tables.append(Table(["face size N", "largest texel", "clamped flux"] + list(s["techniques"]), rows,
                            f"{env}: flux-normalised luminance error mean / max "
                            "(departure from the faces' exact SH9)."))
        path, rel = ctx.figure_path("engines", f"{env}_face_size.png")
        sh9 = m.environments.get(env, {}).get("techniques", {}).get("sh9")
        plots.save_line_plot(path, s["sizes"], {n: t["max"] for n, t in s["techniques"].items()},
                             xlabel="cube face size N", ylabel="max |ΔY(E)| / Φ_Y", title=f"{env}: error vs face size",
                             logx=True, percent=True,
                             hlines={"sh9 (lat-long map)": sh9["errors"]["flux_luminance"]["max"]} if sh9 else None)
        figs.append(Figure(rel, f"{env}: max flux-normalised error against the face size", 360))
    return Section("Cube face size", [
        "Each engine path at several face sizes on the named probes (fewer normals than the main table). Three.js's "
        "r⁻³ texel weights converge as N⁻²; Babylon's clamp acts on texel values, so its effect depends on N."],
        figures=figs, tables=tables)


def sections(m: Measurements, ctx: Context) -> list[Section]:
    tables = metric_tables(m)
    out = [
        Section("Engines beside SH9", [
            "three.js (LightProbeGenerator + getIrradianceAt) and Babylon.js (both shader paths) run headless in "
            f"Node on float32 cube faces of N = {m.settings.face_size} rendered from the same lat-long radiance the "
            "reference integrates; the suite's own sh9 (projection of the lat-long map) beside them. Errors against "
            f"the reference at {m.settings.normals} normals, every metric of README § Metrics."], tables=tables),
        Section("Where each engine departs, and why", [
            "Each engine against the exact SH9 of the faces it received separates the engine's own arithmetic "
            "(weights, clamp, shader) from the SH9 truncation and from the face rendering."],
            tables=[decomposition_table(m)]),
        Section("Babylon's 4096 clamp and half-float faces", [], tables=[clamp_table(m)]),
    ]
    if m.sweeps:
        out.append(sweep_section(m, ctx))
    return out


__all__ = ["sections"]
