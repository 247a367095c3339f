"""``engines`` report sections: tables (and the face-size plots) from the measurements alone."""

from __future__ import annotations

from typing import Any

from ...figures import plots
from ...local_models import irradiance
from ...local_models.irradiance.engines.worker import package_version
from ...stats import measured_json
from ..base import Context, Figure, NotRun, Section, Table
from ..formatting import col, pct, pm
from ..techniques import error_stats_measured, technique_entry
from .claims import K_MAX, eligible
from .compute import BABYLON_CLAMP, Measurements, engine_techniques

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
        tables.append(Table(["environment", "largest face texel (W/(m²·sr))", "reference ± (%)"]
                            + [col(n, "%") for n in names], rows,
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
    return Table(["environment", "face flux error (–)", f"faces > {BABYLON_CLAMP:g}?"]
                 + [f"{n}: |E − E_SH9(faces)|/Φ (–)" for n in names] + ["polynomial vs lobe-twice model (–)"], rows,
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
    return Table(["environment", "largest map texel (W/(m²·sr))", "largest face texel (W/(m²·sr))",
                  "flux removed by the clamp (%)", "babylon_sh, clamp (%)", "babylon_sh, no clamp (%)",
                  "texels > 65504 (count)", "three_sh half-float finite?", "half vs float32 |ΔE|/Φ (–)"], rows,
                 f"Babylon's per-channel clamp at {BABYLON_CLAMP:g} (flux-normalised luminance error, mean / max) and "
                 "three.js with half-float faces.")


def own_faces_table(m: Measurements) -> Table | None:
    """Per environment and engine: the suite's texel-averaged faces against the engine's own panorama → cube path
    (largest texel, Babylon's clamp, flux-normalised luminance max error ± the reference's uncertainty, and
    their difference)."""
    rows = []
    for env, r in m.environments.items():
        for name, o in r.get("own_faces", {}).items():
            suite = r["techniques"][name]["errors"]["flux_luminance"]
            own = o["errors"]["flux_luminance"]
            d = o["difference"]["flux_luminance"]
            rows.append([env, name, f"{r['max_face_texel']:.4g}", f"{o['max_face_texel']:.4g}",
                         ("yes" if r["above_clamp"] else "no") + " / " + ("yes" if o["above_clamp"] else "no"),
                         pct(o["clamp_share"]), pm(suite["max"], suite["max_uncertainty"]),
                         pm(own["max"], own["max_uncertainty"]), pm(d["max"], d["max_uncertainty"]),
                         pm(d["mean"], d["mean_uncertainty"]), f"{o['vs_suite_faces']:.3g}",
                         f"{o['face_flux_error']:.2g}", f"{o['faces_deviation']:.2g}"])
    if not rows:
        return None
    return Table(["environment", "engine", col("largest texel, suite faces", "W/(m²·sr)"),
                  col("largest texel, own faces", "W/(m²·sr)"), col(f"> {BABYLON_CLAMP:g}? suite / own", "–"),
                  col("flux the clamp removes, own faces", "%"), col("max error, suite faces", "%"),
                  col("max error, own faces", "%"), col("max error own − suite", "%"),
                  col("mean error own − suite", "%"), col("|E_own − E_suite| / Φ", "–"),
                  col("own faces' flux error", "–"), col("|E − E_SH9(own faces)| / Φ", "–")], rows,
                 "Flux-normalised luminance error (max over normals ± the reference's uncertainty; the difference ± "
                 "the sum of both). Own faces: Babylon's PanoramaToCubeMapTools (its code) and three.js's "
                 "fromEquirectangularTexture shader (transcribed; three has no CPU path).")


def sweep_section(m: Measurements, ctx: Context) -> Section:
    tables, figs = [], []
    for env, s in m.sweeps.items():
        rows = []
        for i, size in enumerate(s["sizes"]):
            rows.append([size, f"{s['max_face_texel'][i]:.4g}", pct(s["clamp_share"][i])]
                        + [f"{pct(t['mean'][i])} / {pct(t['max'][i])} ({t['faces_deviation'][i]:.2g})"
                           for t in s["techniques"].values()])
        tables.append(Table(["face size N (texels)", "largest texel (W/(m²·sr))", "clamped flux (%)"]
                            + [col(n, "%") for n in s["techniques"]], rows,
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
    if m.unavailable is not None:
        return []
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
    own = own_faces_table(m)
    if own is not None:
        out.append(Section("Each engine's own faces (issue 21 item 5)", [
            "A user hands the engine the panorama, not the suite's faces. Babylon's HDRCubeTexture path converts it "
            "with PanoramaToCubeMapTools.ConvertPanoramaToCubemap — one nearest panorama pixel per face texel, taken "
            "at the texel's corner — and three.js renders it with fromEquirectangularTexture (bilinear at texel "
            "centres, GPU only, transcribed here). Both then project with their own code as above. Each engine's "
            "frame is measured from its own pipeline (a panorama holding its directions) and the normals mapped "
            "into it."], tables=[own]))
    if m.sweeps:
        out.append(sweep_section(m, ctx))
    return out




def techniques(m: Measurements) -> dict[str, Any]:
    """``experiments.engines.techniques.<name>``: every metric ± uncertainty per environment, the departure
    from the SH9 of its own faces, and the same metrics with band 1's sign flipped (the power check)."""
    out: dict[str, Any] = {}
    if m.unavailable is not None:
        return out
    names = {n for r in m.environments.values() for n in r["techniques"]}
    for name in [t.name for t in irradiance if t.name in names]:
        tech = irradiance[name]
        per_env = {e: r["techniques"][name] for e, r in m.environments.items() if name in r["techniques"]}
        out[name] = technique_entry(
            tech, {e: {k: error_stats_measured(v) for k, v in t["errors"].items()} for e, t in per_env.items()},
            faces_deviation={e: t["faces_deviation"] for e, t in per_env.items()},
            band1_flipped={e: {k: measured_json(error_stats_measured(v)) for k, v in t["errors_band1_flipped"].items()}
                           for e, t in per_env.items()},
            engine=tech.meta.get("engine"), face_size=tech.meta.get("face_size"))
    return out


def _errs(m: Measurements, env: str) -> str:
    r = m.environments[env]["techniques"]
    focus = ["sh9"] + [t.name for t in engine_techniques()]
    fl = {name: r[name]["errors"]["flux_luminance"] for name in focus if name in r}
    return "; ".join(f"{name} {pct(st['mean'])} / {pct(st['max'])}" for name, st in fl.items())


def named_findings(m: Measurements) -> list[str]:
    out = []
    roles: dict[str, list[str]] = {}
    for role, env in m.named.items():
        roles.setdefault(env, []).append(role.replace("_", " "))
    for env, names in roles.items():
        r = m.environments[env]
        out.append(f"{env} ({' and '.join(names)}; largest face texel {r['max_face_texel']:.4g} at N = "
                   f"{r['face_size']}): flux-normalised luminance error mean / max — {_errs(m, env)}.")
    return out


def clamp_findings(m: Measurements) -> list[str]:
    above = [e for e, r in m.environments.items() if r["above_clamp"] and "babylon_sh_unclamped" in r]
    if not above:
        return [f"No face texel exceeds Babylon's clamp ({BABYLON_CLAMP:g}) at N = {m.settings.face_size} on any "
                "environment here, so the clamp changed nothing."]
    out = []
    for e in above:
        r = m.environments[e]
        with_c = r["techniques"].get("babylon_sh", {}).get("errors", {}).get("flux_luminance")
        without = r["babylon_sh_unclamped"]["flux_luminance"]
        if with_c:
            out.append(f"{e}: Babylon's clamp at {BABYLON_CLAMP:g} removes {pct(r['clamp_share'])} of the faces' "
                       f"luminance flux (largest texel {r['max_face_texel']:.4g}); babylon_sh's error is "
                       f"{pct(with_c['mean'])} mean / {pct(with_c['max'])} max with it and {pct(without['mean'])} / "
                       f"{pct(without['max'])} without it.")
    for env, s in m.sweeps.items():
        if any(c > 0 for c in s["clamp_share"]):
            shares = ", ".join(f"N = {n}: {pct(c)}" for n, c in zip(s["sizes"], s["clamp_share"], strict=True))
            out.append(f"{env}: the clamped share depends on the face size ({shares}) — a larger cube puts the sun "
                       "in fewer, brighter texels (Babylon.js PR 13809 notes the same dependence).")
    return out


def polynomial_findings(m: Measurements) -> list[str]:
    tech = next((t for t in engine_techniques() if t.meta.get("path") == "polynomial"), None)
    if tech is None:
        return []
    rows = [(e, r["techniques"][tech.name]["errors"]["flux_luminance"], r["techniques"]["sh9"]["errors"]
             ["flux_luminance"]) for e, r in m.environments.items()
            if tech.name in r["techniques"] and "sh9" in r["techniques"]]
    if not rows:
        return []
    worst = max(rows, key=lambda x: x[1]["max"])
    return [f"Babylon's spherical-polynomial path (useSphericalHarmonics = false) applies the cosine lobe twice: "
            f"bands 1 and 2 come out × 2/3 and × 1/4. Its flux-normalised luminance error reaches "
            f"{pct(worst[1]['mean'])} mean / {pct(worst[1]['max'])} max on {worst[0]} where SH9 has "
            f"{pct(worst[2]['mean'])} / {pct(worst[2]['max'])}; the default path (preScaledHarmonics) is correct."]


def precision_findings(m: Measurements) -> list[str]:
    out = []
    three = [t for t in engine_techniques() if t.meta.get("path") == "getIrradianceAt"]
    for tech in three:
        envs = eligible(m, tech)
        dev = max(m.environments[e]["techniques"][tech.name]["faces_deviation"] for e in envs)
        out.append(f"{tech.name}: its r⁻³ texel weights (solid angle approximated at the texel centre, ρ(N = "
                   f"{m.settings.face_size}) = {m.rho:.3g}) move E by at most {dev:.3g} Φ from the exact SH9 of the "
                   "same faces; Babylon integrates the exact solid angle.")
    half = [(e, r) for e, r in m.environments.items() if "half_finite" in r]
    if half:
        finite = [r["half_deviation"] for _, r in half if r["half_finite"]]
        bad = [e for e, r in half if not r["half_finite"]]
        out.append(f"Half-float faces (HalfFloatType): three.js departs from its float32 result by at most "
                   f"{max(finite, default=0.0):.3g} Φ (half precision 2⁻¹¹ on each texel bounds it by "
                   f"{2.0 ** -11 * K_MAX:.3g} Φ)" + (f"; texels above 65504 overflow to ∞ and the SH is not finite on "
                                                     f"{', '.join(bad)}." if bad else
                                                     "; no face texel exceeded 65504 here."))
    face = max(m.environments.items(), key=lambda kv: kv[1]["face_flux_error"])
    out.append(f"The faces carry the map's flux to within {face[1]['face_flux_error']:.2g} (worst: {face[0]}).")
    out += sh9_findings(m)
    return out


def sh9_findings(m: Measurements) -> list[str]:
    """How far each engine lands from the suite's sh9, and how much of that the faces themselves explain."""
    parts = []
    for t in engine_techniques():
        envs = [e for e in eligible(m, t) if "sh9_deviation" in m.environments[e]["techniques"][t.name]]
        if not envs:
            continue
        worst = max(envs, key=lambda e: m.environments[e]["techniques"][t.name]["sh9_deviation"])
        r = m.environments[worst]
        faces = r.get("faces_vs_sh9")
        extra = f" (the exact SH9 of the same faces is already {faces:.3g} Φ away)" if faces is not None else ""
        parts.append(f"{t.name} {r['techniques'][t.name]['sh9_deviation']:.3g} Φ on {worst}{extra}")
    if not parts:
        return []
    return ["Largest departure from the suite's own sh9 (projection of the lat-long map) below the clamp: "
            + "; ".join(parts) + f". Where the faces explain it, it is the cube's texel size (90°/N = "
            f"{90 / m.settings.face_size:.2g}° at N = {m.settings.face_size}): a small source lands on one texel "
            "centre."]


def own_faces_findings(m: Measurements) -> list[str]:
    """Issue 21 item 5, both ways: which environments trip Babylon's clamp on each face source, and what each
    engine's error is on its own faces against the suite's."""
    out = []
    for name in [t.name for t in engine_techniques()]:
        own = {e: r["own_faces"][name] for e, r in m.environments.items() if name in r.get("own_faces", {})}
        if not own:
            continue
        diffs = {e: o["difference"]["flux_luminance"] for e, o in own.items()}
        worse = [e for e, d in diffs.items() if d["max"] - d["max_uncertainty"] > 0]
        better = [e for e, d in diffs.items() if d["max"] + d["max_uncertainty"] < 0]
        top = max(diffs, key=lambda e: diffs[e]["max"])
        line = (f"Issue 21 item 5 (\"the suite reports the engine better than the engine is\"): {name} on its own "
                f"faces has a larger max flux-normalised luminance error than on the suite's on {len(worse)} of "
                f"{len(own)} environments and a smaller one on {len(better)} (beyond the reference's uncertainty); "
                f"the largest rise is {pm(diffs[top]['max'], diffs[top]['max_uncertainty'])} on {top} "
                f"({pct(m.environments[top]['techniques'][name]['errors']['flux_luminance']['max'])} → "
                f"{pct(own[top]['errors']['flux_luminance']['max'])}).")
        if m.environments and "babylon" in name:
            suite_above = [e for e in own if m.environments[e]["above_clamp"]]
            own_above = [e for e, o in own.items() if o["above_clamp"]]
            line += (f" Babylon's 4096 clamp triggers on {len(suite_above)} environment(s) with the suite's faces "
                     f"({', '.join(suite_above) or 'none'}) and on {len(own_above)} with its own "
                     f"({', '.join(own_above) or 'none'})")
            parts = [f"{e}: {pct(own[e]['clamp_share'])} of the flux removed, max error "
                     f"{pct(own[e]['errors']['flux_luminance']['max'])} with the clamp vs "
                     f"{pct(own[e]['errors_unclamped']['flux_luminance']['max'])} without" for e in own_above]
            line += (": " + "; ".join(parts) + ".") if parts else "."
            suite_parts = [f"{e} {pct(m.environments[e]['babylon_sh_unclamped']['flux_luminance']['max'])} → "
                           f"{pct(m.environments[e]['techniques'][name]['errors']['flux_luminance']['max'])}"
                           for e in suite_above if "babylon_sh_unclamped" in m.environments[e]]
            if suite_parts:
                line += (" On the suite's texel-averaged faces the clamp moves the max error (without → with) "
                         + "; ".join(suite_parts) + ".")
        out.append(line)
        ratios = {e: o["face_flux_ratio"] for e, o in own.items() if "face_flux_ratio" in o}
        if ratios:
            lo, hi = min(ratios, key=ratios.get), max(ratios, key=ratios.get)
            out.append(f"{name}'s own faces point-sample the panorama, so a source smaller than a cube texel "
                       f"(90°/{m.settings.face_size} = {90 / m.settings.face_size:.2g}° at N = "
                       f"{m.settings.face_size}) is hit or missed: their luminance flux ranges from "
                       f"{ratios[lo]:.3g} × the map's ({lo}, largest own-face texel "
                       f"{own[lo]['max_face_texel']:.4g}) to {ratios[hi]:.3g} × ({hi}); the suite's faces keep the "
                       f"flux to within {max(r['face_flux_error'] for r in m.environments.values()):.2g}.")
    return out


def findings(m: Measurements) -> list[str]:
    if m.unavailable is not None:
        return [f"The engines did not run: {m.unavailable}."]
    return (named_findings(m) + polynomial_findings(m) + clamp_findings(m) + precision_findings(m)
            + own_faces_findings(m))


def not_run(m: Measurements) -> list[NotRun]:
    """Without Node or the npm engines, three.js's and Babylon.js's SH code does not run (the faces are checked)."""
    if m.unavailable is None:
        return []
    return [NotRun("three.js, Babylon.js (SH lighting code)", m.unavailable, "python -m validate setup --engines")]


def summary(m: Measurements) -> str:
    if m.unavailable is not None:
        return f"Skipped: {m.unavailable}. Only the cube faces the engines would receive were checked."
    return ("three.js r187 and Babylon.js 9.35 compute SH irradiance with their own unmodified code, run headless "
            f"in Node on float32 cube faces (N = {m.settings.face_size}) rendered from the lat-long radiance the "
            "reference integrates; each engine's error under every metric beside the suite's SH9, the engine "
            "against the exact SH9 of its own faces, Babylon's 4096 clamp, half-float faces, the face size.")


def data(m: Measurements) -> dict[str, Any]:
    """``experiments.engines``'s own keys (only the faces and the reason when no engine ran)."""
    if m.unavailable is not None:
        return {"skipped": m.unavailable, "environments": m.environments}
    return {"environments": m.environments, "face_size_sweep": m.sweeps, "named": m.named,
            "versions": {"three": package_version("three"), "@babylonjs/core": package_version("babylon")},
            "skipped_inputs": [list(s) for s in m.skipped]}


__all__ = ["data", "findings", "not_run", "sections", "summary", "techniques"]
