"""Experiment ``arealights``: disc and sphere lights — every ``arealight`` technique against Mitsuba.

Ground truth, in two steps (the reference is validated before it judges anything):

1. Mitsuba: ``sphere`` and ``disk`` area emitters seen by a small receiver disc with an
   ``irradiancemeter`` (:mod:`validate.scenes.area_lights`, :mod:`validate.reference.area_irradiance`)
   at normals 0°–180° from the light. The closed-form cap irradiance (Snyder 1996 [3]; Lagarde & de
   Rousiers 2014 [4], :mod:`validate.local_models.sphere_cap`) must agree within the Monte Carlo
   uncertainty (Student-t/Šidák test) — and the same test must reject a 2 % scale error (power).
2. The validated closed form is then the reference for dense sweeps (thousands of angles, no noise).

Every registered ``arealight`` technique (built-ins: zonal SH of order 2/4/8, inverse square, OpenGL
attenuation, the exact cap; plug-ins alike) is called through the family on every scene whose shape it
supports (meta ``shapes``): a row in the technique table, a curve in the α and d/r sweeps, an entry
``techniques[<name>]`` with every metric ± uncertainty, and a claim per declared threshold.

Specular part (:mod:`.arealights_specular`): every ``specular_arealight`` technique (LTC, Karis's representative
point for spheres and tubes, plug-ins) against Mitsuba's GGX ``roughconductor`` integrated over rectangle, disc,
sphere and tube (capsule) emitters (:mod:`validate.reference.area_specular_render`), by roughness and light size
(a tube's: its length).

Error normalisations (unit radiance; :mod:`.arealights_compute`): ``flux`` = |E′ − E| / Φ with Φ =
2π(1 − cos σ) the cap's flux (R&H's normalisation); ``peak`` = |E′ − E| / E(0); ``mitsuba_flux`` the same
against the meter. The 5 % statement ([1] eqs. 20.29–20.31, worked at α = 20°; 5 % the level [2] reports for
order-2 SH) is decided as the α range over which order-2 SH meets it: by the closed form on a 0.5° α grid,
and by long Mitsuba runs on either side (α = 25° inside, 19.5° outside).

References
  [1] Fore June, the project's seed text, ch. 20, eqs. 20.29–20.31: SH projection of a disc light of
      half-angle α and its order-2 irradiance, worked at α = 20°.
  [2] R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
      SIGGRAPH 2001, §4 (order-2 SH: "maximum error < 5 %"; the 3/32 Φ worst case, JOSA 18(10) 2001).
  [3] J. Snyder, "Area light sources for real-time graphics", MSR-TR-96-11, 1996.
  [4] S. Lagarde, C. de Rousiers, "Moving Frostbite to PBR 3.0", SIGGRAPH 2014 course, §4.7.2.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models import arealight
from ...local_models.registry import Technique
from . import compute as ac
from . import specular as asp
from .report import sections
from ..base import Claim, Context, ExperimentResult, register_experiment
from ..formatting import pct as _pct
from ..techniques import CheckResult, Measured, Stat, technique_claims, technique_entry

NAME = "arealights"
SH_THRESHOLD = 0.05  # [2]'s order-2 "maximum error < 5 %", in R&H's flux normalisation
POINT_THRESHOLD = 0.01  # "off by more than 1 %": the level at which the d/r crossing is reported (finding)
SEED_DIGITS = 1e-5  # one unit in the 6th significant digit of the seed's constants (π/2 printed 1.57079)
ALPHA20 = 20.0  # [1]'s worked example; the lower end of the α range the 5 % statement holds on
ALPHA_INSIDE, ALPHA_OUTSIDE = 25.0, 19.5  # Mitsuba decisions either side of the range's end
SCALE_ERROR = 0.02  # the reference-bias power check of the meter test
SETTINGS: dict[str, dict[str, Any]] = {
    "quick": {"alphas_deg": [1, 2, 5, 10, 15, 20, 25, 30, 45, 60], "theta_step_deg": 0.25,
              "elevation_step_deg": 5.0, "distance_ratios": 24,
              "meter_thetas_deg": [0, 30, 60, 75, 90, 105, 120, 180], "meter_passes": 16, "meter_spp": 32},
    "full": {"alphas_deg": [1, 2, 3, 4, 5, 6, 7.5, 10, 12.5, 15, 17.5, 20, 22.5, 25, 27.5, 30, 35, 40, 45, 50, 55, 60],
             "theta_step_deg": 0.05, "elevation_step_deg": 1.0, "distance_ratios": 80,
             "meter_thetas_deg": [0, 15, 30, 45, 55, 60, 65, 70, 75, 80, 85, 90, 95, 100, 105, 110, 115, 120, 125,
                                  135, 150, 180], "meter_passes": 16, "meter_spp": 32},
}
COMMON = {"meter_film": 32, "projection_nodes": 48, "scale_error": SCALE_ERROR, "range_step_deg": 0.5,
          "range_deg": (1.0, 60.0),
          # 2.1 M samples per normal at 7 normals: at α = 25° the bound z*·s is ≤ 0.45 % of Φ against a 0.66 %
          # margin; at 19.5° the zero-hit bound at θ = 180° is 0.006 % of Φ against a 0.047 % margin
          "decide": {"thetas_deg": list(range(0, 181, 30)), "passes": 16, "spp": 128}}


def settings(quick: bool) -> dict[str, Any]:
    return {**COMMON, **SETTINGS["quick" if quick else "full"]}


def _thetas(s: dict) -> np.ndarray:
    return np.arange(0.0, 180.0 + 1e-9, s["theta_step_deg"])


# -- compute -----------------------------------------------------------------------------------------
def compute(ctx: Context) -> dict[str, Any]:
    """Every number of the experiment (JSON-able)."""
    s = settings(ctx.quick)
    seed = ctx.seed % 2048
    scenes = ac.scene_table(ALPHA20)
    checks = ctx.map(lambda item: ac.reference_check(item[1][0], item[1][1], s, (seed + item[0]) % 2048),
                     list(enumerate(scenes.items())), "arealights: Mitsuba")  # independent seeds per scene
    th = _thetas(s)
    return {"settings": s, "scenes": scenes, "reference_checks": checks,
            "cap_quadrature": {"max": ac.cap_quadrature_check(np.cos(np.radians(th))),
                               "unclipped": ac.cap_quadrature_check(np.cos(np.radians(th)), unclipped=True)},
            "seed_formulas": ac.seed_check(s, ALPHA20),
            "techniques": measure_techniques(scenes, {c["name"]: c for c in checks}, th),
            "alpha_sweep": alpha_sweep(s, th), "alpha_range": alpha_range(s, th),
            "decide": {k: ac.decide_alpha(a, s, (seed + 7 + i) % 2048)
                       for i, (k, a) in enumerate((("inside", ALPHA_INSIDE), ("outside", ALPHA_OUTSIDE)))},
            "sh_vs_elevation": ac.elevation_sweep(s, (5.0, ALPHA20)),
            "point_lights": ac.distance_sweep(s, th, POINT_THRESHOLD),
            "specular": asp.compute(asp.SPECULAR["quick" if ctx.quick else "full"])}


def measure_techniques(scenes: dict, checks: dict, thetas: np.ndarray,
                       techniques: Sequence[Technique] | None = None) -> dict[str, dict[str, Any]]:
    """Per technique and supported scene: closed-form flux/peak errors and the error against Mitsuba."""
    out: dict[str, dict[str, Any]] = {}
    for tech in techniques if techniques is not None else list(arealight):
        out[tech.name] = {}
        for name, sc in scenes.items():
            if ac.supports(tech, sc["shape"]):
                out[tech.name][name] = {**ac.technique_errors(tech, sc, thetas),
                                        "mitsuba": ac.mitsuba_error(tech, sc, checks[name]) if name in checks else None}
    return out


def alpha_sweep(s: dict, thetas: np.ndarray) -> dict[str, Any]:
    """max_θ |E′ − E| / Φ vs α for every technique that handles a sphere (sin α = r/d), and the α at which
    each falls through 5 % (Brent between grid points)."""
    alphas = np.asarray(s["alphas_deg"], dtype=np.float64)
    out: dict[str, Any] = {"alpha_deg": alphas.tolist(), "errors": {}, "crossing_5pct": {}}
    for tech in arealight:
        if ac.supports(tech, "sphere"):
            errs = [ac.sphere_alpha_error(tech, a, thetas) for a in alphas]
            out["errors"][tech.name] = errs
            out["crossing_5pct"][tech.name] = ac.alpha_crossing(
                lambda a, t=tech: ac.sphere_alpha_error(t, a, thetas), alphas, np.asarray(errs), SH_THRESHOLD)
    return out


def alpha_range(s: dict, thetas: np.ndarray) -> dict[str, Any]:
    """Order-2 SH error on a fine α grid (closed form): where it meets 5 % of Φ and where not."""
    lo, hi = s["range_deg"]
    alphas = np.arange(lo, hi + 1e-9, s["range_step_deg"])
    errs = np.array([ac.sphere_alpha_error("sh_order2", a, thetas) for a in alphas])
    inside = alphas >= ALPHA20 - 1e-9
    below = alphas[~inside][-1]
    # closed-form uncertainty relative to Φ: CAP_QUADRATURE_TOLERANCE·π sin²α / (2π(1 − cos α)) ≤ tolerance
    return {"alpha_deg": alphas.tolist(), "order2": errs.tolist(), "uncertainty": ac.CAP_QUADRATURE_TOLERANCE,
            "inside_max": float(errs[inside].max()), "outside_min": float(errs[~inside].min()),
            "below_deg": float(below), "with_below_max": float(errs[alphas >= below - 1e-9].max()),
            "with_end_min": float(errs[alphas <= ALPHA20 + 1e-9].min()),
            "crossing_deg": ac.alpha_crossing(lambda a: ac.sphere_alpha_error("sh_order2", a, thetas),
                                              alphas, errs, SH_THRESHOLD)}


# -- claims ------------------------------------------------------------------------------------------
def claims(m: dict[str, Any]) -> list[Claim]:
    return [*_reference_claims(m), *_range_claims(m), *_technique_claims(m), *asp.claims(m["specular"])]


def _reference_claims(m: dict[str, Any]) -> list[Claim]:
    sf, cq = m["seed_formulas"], m["cap_quadrature"]
    out = [Claim("arealights.seed_sh.projection",
                 "the seed's disc SH formulas (L00, L10, L20 and the order-2 irradiance polynomial, α = 1°…60°, and "
                 "its α = 20° numbers) equal a numerical projection of the cap", "max |seed − numerical|", SEED_DIGITS,
                 sf["max_deviation"], sf["quadrature_uncertainty"],
                 source="Fore June ch. 20 eqs. 20.29–20.31 print 6 significant digits (π/2 as 1.57079, "
                        "truncated): a correct formula is within one unit of the 6th digit, 1e-5 × factors ≤ 1; "
                        "uncertainty = change of the projection when its nodes are doubled"
                 ).with_power("the l = 2 band's sign flipped (L20 → −L20)", sf["band2_flipped_deviation"]),
           Claim("arealights.cap.quadrature", "closed-form cap irradiance (float32 drjit) = brute-force quadrature",
                 "max |E − E_quad| / (π sin²σ)", ac.CAP_QUADRATURE_TOLERANCE, cq["max"], 0.0, unit="%",
                 source="float32 rounding: measured 8.8e-7 over sin²σ = 0.01…0.9; 1e-5 leaves an 11× margin"
                 ).with_power("horizon clamp dropped (π sin²σ max(cos θ, 0) everywhere, the point-light form)",
                              cq["unclipped"])]
    for c in m["reference_checks"]:
        t = c["closed_test"]
        out.append(Claim(f"arealights.cap.mitsuba.{c['name']}",
                         f"{c['name']} (σ = {c['sigma_deg']:.1f}°): closed-form cap irradiance = Mitsuba's irradiance "
                         "meter within its uncertainty",
                         f"max |z| over {len(c['theta_deg'])} normals (Student t, {c['passes'] - 1} dof → z)",
                         t["critical_z"], t["max_abs_z"], 0.0,
                         source=f"Šidák-corrected two-sided test (Šidák 1967), family-wise α = {ac.ALPHA:g}; the "
                                "Monte Carlo uncertainty is inside z"
                         ).with_power(f"closed form scaled by {1 + SCALE_ERROR:g} (a {SCALE_ERROR:.0%} reference bias)",
                                      c["scaled_test"]["max_abs_z"]))
    return out


def _range_claims(m: dict[str, Any]) -> list[Claim]:
    r, d = m["alpha_range"], m["decide"]
    src = ("Fore June ch. 20 eqs. 20.29–20.31 (order-2 SH of a disc, worked at α = 20°) against Ramamoorthi & "
           "Hanrahan 2001 §4's order-2 level 'max error < 5 %', in R&H's flux normalisation")
    lo, hi = m["settings"]["range_deg"]
    inside, outside = d["inside"], d["outside"]
    return [
        Claim("arealights.sh2.five_percent.range", f"order-2 SH of a disc light meets 5 % of Φ for every α in "
              f"[{ALPHA20:g}°, {hi:g}°] (closed form, α step {m['settings']['range_step_deg']:g}°)",
              "max over α of max_θ |E_2 − E| / Φ", SH_THRESHOLD, r["inside_max"], r["uncertainty"], unit="%",
              source=src + "; uncertainty = the closed form's float32 tolerance"
              ).with_power(f"range extended to the neighbouring α = {r['below_deg']:g}°", r["with_below_max"]),
        Claim("arealights.sh2.five_percent.below", f"… and misses it for every α in [{lo:g}°, {r['below_deg']:g}°] "
              "(closed form): the range ends between the grid points", "min over α of max_θ |E_2 − E| / Φ",
              SH_THRESHOLD, r["outside_min"], r["uncertainty"], comparison=">", unit="%", source=src
              ).with_power(f"range extended to the neighbouring α = {ALPHA20:g}°", r["with_end_min"]),
        Claim("arealights.sh2.five_percent.mitsuba_inside",
              f"sphere light with sin α = r/d, α = {ALPHA_INSIDE:g}° (inside the range): order-2 SH within 5 % of Φ "
              f"of Mitsuba at every meter normal ({inside['samples_per_normal']:,} samples each)",
              "max_n |E_2 − m_n| / Φ (+ Šidák bound)", SH_THRESHOLD, inside["value"],
              inside["upper"] - inside["value"], unit="%",
              source=src + "; bound = z*·s or the zero-hit bound per normal"
              ).with_power(f"the same test at α = {ALPHA_OUTSIDE:g}° (outside the range)", outside["value"],
                           outside["upper"] - outside["value"]),
        Claim("arealights.sh2.five_percent.mitsuba_outside",
              f"sphere light, α = {ALPHA_OUTSIDE:g}° (just outside): order-2 SH misses 5 % of Φ against Mitsuba at "
              f"some meter normal ({outside['samples_per_normal']:,} samples each)",
              "max_n |E_2 − m_n| / Φ (− Šidák bound)", SH_THRESHOLD, outside["value"],
              outside["value"] - outside["lower"], comparison=">", unit="%", source=src
              ).with_power(f"the same test at α = {ALPHA_INSIDE:g}° (inside the range)", inside["value"],
                           inside["value"] - inside["lower"]),
    ]


def technique_measured(per_scene: dict[str, Any]) -> dict[str, Measured]:
    """Worst over scenes of every metric, ± uncertainty, with the power perturbation 'error × 1.5'."""
    out: dict[str, Measured] = {}
    for metric in ("flux.max", "flux.mean", "peak.max", "peak.mean", "mitsuba_flux.max"):
        vals = []
        for v in per_scene.values():
            if metric == "mitsuba_flux.max":
                if v.get("mitsuba"):
                    vals.append((v["mitsuba"]["value"], v["mitsuba"]["uncertainty"]))
            else:
                vals.append((v[metric], v[metric.split(".")[0] + ".uncertainty"]))
        if vals:
            val, unc = max(vals)
            out[metric] = Measured(val, unc, 1.5 * val, "error × 1.5")
    return out


def _technique_claims(m: dict[str, Any]) -> list[Claim]:
    out: list[Claim] = []
    for tech in arealight:
        per = m["techniques"].get(tech.name, {})
        if tech.thresholds and per:
            out += technique_claims(NAME, tech, technique_measured(per), scope=f"worst over {', '.join(per)}")
    return out


# -- findings ----------------------------------------------------------------------------------------


def findings(m: dict[str, Any]) -> list[str]:
    f = [_reference_finding(c) for c in m["reference_checks"]]
    bad = [c["name"] for c in m["reference_checks"] if not c["closed_test"]["consistent"]]
    if bad:
        f.insert(0, f"WARNING: Mitsuba and the closed-form cap disagree on {', '.join(bad)}: the reference is not "
                    "validated, so the judgements below that rest on it are void until this is resolved.")
    f.append(_range_finding(m))
    f += _sweep_findings(m)
    return f + asp.findings(m["specular"])


def _reference_finding(c: dict[str, Any]) -> str:
    return (f"{c['name']}: Mitsuba's irradiance meter ({c['samples_per_normal']:,} samples per normal) agrees with the "
            f"closed-form cap irradiance (max |z| = {c['closed_test']['max_abs_z']:.2f} < "
            f"{c['closed_test']['critical_z']:.2f}) and rejects the unclipped π sin²σ cos θ near the horizon "
            f"(max |z| = "
            f"{c['unclipped_test']['max_abs_z']:.1f}) and a {SCALE_ERROR:.0%} scale error (max |z| = "
            f"{c['scaled_test']['max_abs_z']:.1f}).")


def _range_finding(m: dict[str, Any]) -> str:
    r, d = m["alpha_range"], m["decide"]
    x = r["crossing_deg"]
    where = f"α ≥ {x:.2f}°" if x is not None else "no crossing on the grid"
    return (f"Order-2 SH of a disc light meets 5 % of Φ (max_θ |E_2 − E| / Φ, Φ = 2π(1 − cos α)) exactly for "
            f"{where} up to {m['settings']['range_deg'][1]:g}° (closed form): {_pct(r['inside_max'])} at α = "
            f"{ALPHA20:g}°, {_pct(r['outside_min'])} at {r['below_deg']:g}°; the worst normals are θ = 0° and 180° "
            f"(the errors there are equal, E_2(1) − E_2(−1) = π sin²α = E(0)). Mitsuba decides both sides: "
            f"{_pct(d['inside']['value'])} (bound {_pct(d['inside']['upper'])}) at α = {ALPHA_INSIDE:g}°, "
            f"{_pct(d['outside']['value'])} (bound {_pct(d['outside']['lower'])}) at {ALPHA_OUTSIDE:g}°. At α = "
            f"{ALPHA20:g}° itself the margin (0.012 % of Φ) is below what a meter can resolve at θ = 0°.")


def _sweep_findings(m: dict[str, Any]) -> list[str]:
    sw, pts, sf = m["alpha_sweep"], m["point_lights"], m["seed_formulas"]
    f = []
    for name, a in sw["crossing_5pct"].items():
        if a is not None:
            f.append(f"{name}: exceeds 5 % of Φ for sphere/disc half-angles below α = {a:.1f}° (α grid "
                     f"{sw['alpha_deg'][0]:g}°…{sw['alpha_deg'][-1]:g}°).")
    f.append(f"The seed's disc SH formulas match a numerical projection to {sf['max_deviation']:.1e} (α = 20° "
             f"polynomial: {', '.join(f'{v:.7g}' for v in sf['alpha20_polynomial'])} vs the seed's "
             f"{', '.join(f'{v:g}' for v in sf['alpha20_seed'])}).")
    q, qd = pts["crossing_inverse_square_sphere"], pts["crossing_inverse_square_disc_normal_incidence"]
    if q is not None:
        f.append("Inverse-square point light for a sphere light (I = π r² L, the sphere's power / 4π): exact wherever "
                 "the sphere is wholly above the horizon; its worst-normal error relative to the normal-incidence "
                 f"irradiance exceeds 1 % for d/r < {q:.1f}.")
    if qd is not None:
        f.append(f"For a disc light facing the receiver, inverse square overestimates even at normal incidence, by "
                 f"r²/d², which exceeds 1 % for d/r < {qd:.2f}; OpenGL's attenuation with (a, b, c) = (r², 0, 1) "
                 "makes that case exact (on the axis, above the horizon).")
    f.append("Disc-for-sphere substitution: a sphere subtends exactly the cap with sin α = r/d, so the substitution is "
             "exact and only the SH truncation of that disc remains; tan α = r/d instead (a disc of the same radius) "
             f"underestimates by r²/(r² + d²): {_pct(1 / 5)} at d/r = 2, {_pct(1 / 101)} at d/r = 10.")
    return f


# -- run ---------------------------------------------------------------------------------------------
@register_experiment(NAME, "Disc and sphere lights: SH, point-light shortcuts and the exact cap vs Mitsuba",
                     "every arealight technique vs α, elevation and d/r; the 5 % range of order-2 SH", order=30)
def run(ctx: Context) -> ExperimentResult:
    m = compute(ctx)
    entries = {tech.name: technique_entry(tech, {k: {"value": v.value, "uncertainty": v.uncertainty}
                                                 for k, v in technique_measured(m["techniques"][tech.name]).items()},
                                          scenes=m["techniques"][tech.name])
               for tech in arealight if m["techniques"].get(tech.name)}
    entries.update(asp.entries(m["specular"]))
    return ExperimentResult(
        name=NAME, title="Disc and sphere lights vs Mitsuba",
        summary=("Every registered area-light technique — zonal SH of order 2, 4 and 8, the inverse-square and "
                 "OpenGL point-light shortcuts, the exact horizon-clipped cap irradiance, and plug-ins — judged by "
                 "Mitsuba's irradiance meter on sphere and disc emitters (after the closed form is shown to agree "
                 "with it), and the α range over which order-2 SH meets 5 % of the light's flux."),
        claims=claims(m), findings=findings(m), sections=sections(m, ctx), techniques=entries,
        data={k: v for k, v in m.items() if k not in ("settings", "techniques")}, settings=m["settings"])


# -- validate.testing --------------------------------------------------------------------------------
def check_arealight(fn: Callable[..., Any] | str, scenes: Sequence[str] | None = None,
                    shapes: Sequence[str] = ("sphere", "disc"), name: str = "candidate",
                    theta_step_deg: float = 0.25) -> CheckResult:
    """Measure an area-light technique (a function of the ``arealight`` contract, or a registered name)
    against the exact cap irradiance on the experiment's scenes (default: all three, those of ``shapes``).

    Returns a :class:`CheckResult` with, per scene, ``flux`` (|E′ − E| / Φ) and ``peak`` (|E′ − E| / E(0)) as
    mean and max over θ ∈ [0°, 180°] ± the closed form's tolerance; e.g. ``r.flux.max < 0.05``."""
    if isinstance(fn, Technique) or isinstance(fn, str):
        tech = fn if isinstance(fn, Technique) else arealight[fn]
    elif callable(fn):
        tech = Technique(name, "arealight", fn, name, meta={"shapes": tuple(shapes)})
    else:
        raise ValidateError(f"check_arealight: {fn!r} is not callable, a Technique or a registered name")
    table = ac.scene_table(ALPHA20)
    chosen = {k: v for k, v in table.items() if (scenes is None or k in scenes) and ac.supports(tech, v["shape"])}
    th = np.arange(0.0, 180.0 + 1e-9, theta_step_deg)
    per = measure_techniques(chosen, {}, th, [tech])[tech.name]
    return CheckResult(tech.name, "arealight", {
        sc: {metric: Stat(v[f"{metric}.mean"], v[f"{metric}.max"], v[f"{metric}.uncertainty"],
                          v[f"{metric}.uncertainty"]) for metric in ("flux", "peak")} for sc, v in per.items()})


__all__ = ["NAME", "check_arealight", "claims", "compute", "findings", "run", "settings"]
