"""Experiment ``lights``: the textbooks' classic lights against Mitsuba.

Scene (:mod:`validate.scenes.light_scenes`): a diffuse ground plane, a sphere and a box, lit in
turn by Mitsuba ``point``, ``spot`` and ``directional`` emitters and by ``rectangle``, ``disk`` and
``sphere`` area emitters, physical units; plus one render with point + spot + directional +
rectangle together (and the three delta lights again with the rectangle's shape present but dark,
since an area light's shape casts shadows too), the rectangle over the bare ground, and a real lamp
(a disc at the end of a black tube: a spot beam with a physical edge).

Reference (:mod:`validate.reference.light_render`): Mitsuba's direct lighting at the pixel centres,
P independent passes → mean ± standard error; the G-buffer of the same rays.

Techniques: every registered ``light`` technique (:mod:`validate.local_models.light.classic_lights`,
``light_attenuation``, ``light_grid`` and plug-ins) shades the G-buffer, L = ρ/π · E, for each
standard light it models (meta ``lights``), with the scene's own shadow rays; its image errors
(:mod:`.lights_metrics`: mean, max, bias, each ± uncertainty) go to the comparison table and to
``results.json`` at ``experiments.lights.techniques.<name>.metrics.<light>.<metric>``. Declared
thresholds (metric names ``<light>.<metric>``) become claims.

Claims (each with a power check that fails):
1. declared thresholds: inverse-square point light, Mitsuba-profile spot and directional light
   reproduce Mitsuba's renders to float32 rounding (max error < 10⁻⁴ of the mean lit radiance);
2. Lambert's closed form for the rectangle equals Mitsuba's ``rectangle`` emitter over the bare
   ground (|pooled z| < 4);
3. the n×n grid (midpoint rule) converges at the rate quadrature theory gives, O(n⁻²);
4. lights add linearly: the render with four lights equals the sum of the four single renders
   (|pooled z| < 4, and max |z| below the Šidák critical value).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models import light as family
from ...reference import light_render as lr
from ...scenes import light_scenes as ls
from ...scenes.latlong import luminance
from . import image_metrics as lm
from . import report as report
from . import sweeps as sw
from ..base import Claim, Context, ExperimentResult, register_experiment
from ..techniques import technique_claims, technique_entry

NAME = "lights"
SINGLES = ("point", "spot", "directional", "rectangle", "disk", "sphere")
SUM_LIGHTS = ("point", "spot", "directional", "rectangle")
RATE_TOLERANCE = 0.25  # claim 3: |slope + 2| < 0.25 (order 2 vs the endpoint rule's order 1; see claims)
SLOPE_FROM_N = 4  # claim 3: the slope is fitted over n ≥ 4 (the asymptotic range of the h² term)

QUICK: dict[str, Any] = {
    "width": 64, "height": 48, "delta_spp": 1, "delta_passes": 2, "area_spp": 16, "area_passes": 8,
    "sum_spp": 64, "sum_passes": 8, "ground_spp": 64, "ground_passes": 8, "technique_grid": 8,
    "grid_ns": [1, 2, 3, 4, 6, 8, 12, 16], "grid_reference": 24, "visibility_side": 12, "range": 10.0, "seed": 1234,
    "ratios": np.geomspace(0.75, 40.0, 24).tolist(), "distances": np.geomspace(0.25, 20.0, 40).tolist(),
    "polar_deg": (0.0, 30.0, 60.0), "tilt_deg": (0.0, 30.0, 60.0),
}
FULL: dict[str, Any] = dict(QUICK, width=160, height=120, area_spp=64, area_passes=16, sum_spp=256,
                            sum_passes=16, ground_spp=256, ground_passes=16, grid_ns=[1, 2, 3, 4, 5, 6, 8, 10, 12, 16],
                            grid_reference=32, visibility_side=16, ratios=np.geomspace(0.75, 40.0, 48).tolist(),
                            distances=np.geomspace(0.25, 20.0, 80).tolist(),
                            polar_deg=(0.0, 15.0, 30.0, 45.0, 60.0), tilt_deg=(0.0, 15.0, 30.0, 45.0, 60.0))


@dataclass
class Measurements:
    """``data``: JSON-able numbers; ``images``: arrays for the report (not written to results.json)."""

    settings: dict[str, Any]
    data: dict[str, Any] = field(default_factory=dict)
    images: dict[str, Any] = field(default_factory=dict)
    measured: dict[str, dict[str, Any]] = field(default_factory=dict)  # technique → metric → Measured


# -- references ------------------------------------------------------------------------------------------
def scenes(s: dict[str, Any]) -> dict[str, tuple[ls.LightScene, int, int]]:
    """name → (scene, spp, passes) of every reference render."""
    w, h = s["width"], s["height"]
    out = {}
    for kind in SINGLES:
        delta = kind in ("point", "spot", "directional")
        out[kind] = (ls.light_scene((kind,), w, h), s["delta_spp" if delta else "area_spp"],
                     s["delta_passes" if delta else "area_passes"])
    for kind in SUM_LIGHTS:  # the delta lights again, with the rectangle's shape present (it casts shadows)
        if kind not in ls.AREA_KINDS:
            out[f"sum_{kind}"] = (ls.light_scene((kind,), w, h, blockers=("rectangle",)), s["delta_spp"],
                                  s["delta_passes"])
    out["all"] = (ls.light_scene(SUM_LIGHTS, w, h), s["sum_spp"], s["sum_passes"])
    out["lamp"] = (ls.light_scene(("lamp",), w, h), s["area_spp"], s["area_passes"])
    out["ground_rectangle"] = (ls.light_scene(("rectangle",), w, h, occluders=False), s["ground_spp"],
                               s["ground_passes"])
    return out


def light_mapping(light: ls.Light, s: dict[str, Any], spot_exponent: float) -> dict[str, Any]:
    """What a technique receives: the light plus the experiment's choices (range, fitted f, grid n)."""
    m = light.as_mapping()
    m.update({"point": {"range": s["range"]}, "spot": {"exponent": spot_exponent}}.get(light.kind, {}))
    if light.kind in ls.AREA_KINDS:
        m["grid"] = s["technique_grid"]
    return m


class Frame:
    """One render's valid pixels: G-buffer, reference and the shadow-ray test of its geometry."""

    def __init__(self, scene: ls.LightScene, ref: lr.LightRender):
        self.scene, self.ref, self.valid = scene, ref, ref.valid
        v = ref.valid
        self.position, self.normal, self.albedo = ref.position[v], ref.normal[v], ref.albedo[v]
        self.radiance, self.uncertainty = ref.radiance[v], ref.uncertainty[v]
        self.passes = ref.pass_images[:, v]  # (P, N, 3)
        self.visible = lr.shadow_tester(scene)

    def shade(self, irradiance: np.ndarray) -> np.ndarray:
        return self.albedo / math.pi * irradiance[:, None]

    def image(self, values: np.ndarray) -> np.ndarray:
        out = np.full(self.valid.shape + values.shape[1:], np.nan)
        out[self.valid] = values
        return out


def render_frames(ctx: Context, s: dict[str, Any]) -> dict[str, Frame]:
    items = list(scenes(s).items())
    refs = ctx.map(lambda it: lr.render_lights(it[1][0], it[1][1], it[1][2], s["seed"]), items, "lights: renders")
    return {name: Frame(sc[0], ref) for (name, sc), ref in zip(items, refs, strict=True)}


# -- techniques ----------------------------------------------------------------------------------------------
def evaluate_techniques(frames: dict[str, Frame], s: dict[str, Any], m: Measurements) -> None:
    """Every registered technique on every standard light it models: image errors and an error map."""
    spot_f = m.data["spot"]["fitted_exponent"]
    for tech in family:
        if not tech.meta.get("lights"):
            raise ValidateError(f"technique '{tech.name}' (light): declare the light types it models, e.g. "
                                "@light.register(..., lights=('point',))")
        kinds = [k for k in tech.meta["lights"] if k in SINGLES]
        entry, meas = {}, {}
        for kind in kinds:
            f = frames[kind]
            e = family.call(tech, light_mapping(f.scene.lights[0], s, spot_f), f.position, f.normal,
                            visible=f.visible)
            approx = f.shade(e)
            errs = lm.measured(f.radiance, f.uncertainty, approx)
            meas.update({f"{kind}.{k}": v for k, v in errs.items()})
            entry[kind] = {k: lm.metric_json(v) for k, v in errs.items()}
            if kind == kinds[0]:
                norm = lm.image_errors(f.radiance, f.uncertainty, approx).normaliser
                m.images.setdefault("error", {})[tech.name] = (kind, f.image(
                    (luminance(approx) - luminance(f.radiance)) / norm))
        m.data.setdefault("techniques", {})[tech.name] = {"lights": kinds, "metrics": entry}
        m.measured[tech.name] = meas


# -- the questions ---------------------------------------------------------------------------------------------
def attenuation(s: dict[str, Any], frames: dict[str, Frame]) -> dict[str, Any]:
    """E/E_inv² over distance for every point technique; scale-fitted error over the scene's distances."""
    d = np.asarray(s["distances"])
    curves = sw.attenuation_curves(d, s["range"])
    f = frames["point"]
    dist = np.linalg.norm(f.position - np.asarray(f.scene.lights[0].position), axis=1)
    lo, hi = float(dist.min()), float(dist.max())
    ds = np.geomspace(lo, hi, 64)
    scene_curves = sw.attenuation_curves(ds, s["range"])
    out: dict[str, Any] = {"distances": d.tolist(), "scene_distance_range": [lo, hi], "techniques": {}}
    for name, ratio in curves.items():
        k, err = sw.best_scale_error(scene_curves[name])
        at = {f"{x:g} m": float(np.interp(x, d, ratio) - 1.0) for x in (0.5, 1.0, 2.0, 5.0, 10.0)}
        out["techniques"][name] = {"ratio": ratio.tolist(), "relative_error_at": at, "best_scale": k,
                                   "best_scale_max_error": err}
    return out


def grid_unshadowed(frames: dict[str, Frame], s: dict[str, Any]) -> dict[str, Any]:
    """Unshadowed n×n grid (midpoint and corner rules) vs Lambert's formula over the bare ground."""
    g = frames["ground_rectangle"]
    rect = g.scene.lights[0]
    exact = lr.rectangle_irradiance(rect, g.position, g.normal)
    ns = list(s["grid_ns"])
    mid = sw.grid_errors(rect, g.position, g.normal, exact, ns, 0.5)
    corner = sw.grid_errors(rect, g.position, g.normal, exact, ns, 0.0)
    return {"n": ns, "midpoint_max_rel": mid, "corner_max_rel": corner,
            "midpoint_slope": sw.loglog_slope(ns, mid, SLOPE_FROM_N),
            "corner_slope": sw.loglog_slope(ns, corner, SLOPE_FROM_N)}


def grid_shadowed(frames: dict[str, Frame], s: dict[str, Any]) -> dict[str, Any]:
    """Shadowed n×n grid by region (lit / penumbra / umbra, as in ``shadows``) against the fine grid
    n_ref × n_ref (noise-free self-convergence), and the fine grid against Mitsuba's render (z test)."""
    from ...metrics import shadow_error as se

    out: dict[str, Any] = {"n": list(s["grid_ns"]), "reference_n": s["grid_reference"]}
    for kind in ls.AREA_KINDS:
        f = frames[kind]
        light = f.scene.lights[0]
        ref_img = f.shade(family.call("area_grid_shadowed", dict(light.as_mapping(), grid=s["grid_reference"]),
                                      f.position, f.normal, visible=f.visible))
        v_ref = sw.visible_fraction(light, f.position, f.normal, f.visible, s["visibility_side"])
        rows: dict[str, list[float]] = {"lit": [], "penumbra": [], "umbra": [], "total": []}
        for n in out["n"]:
            e = family.call("area_grid_shadowed", dict(light.as_mapping(), grid=n), f.position, f.normal,
                            visible=f.visible)
            err = se.shadow_errors(ref_img, np.zeros_like(ref_img), f.shade(e), np.nan_to_num(v_ref), v_ref)
            for reg in ("lit", "penumbra", "umbra"):
                rows[reg].append(err.regions[reg].mean)
            rows["total"].append(err.total.mean)
        slopes = {reg: sw.loglog_slope(out["n"], rows[reg], SLOPE_FROM_N) if min(rows[reg]) > 0 else None
                  for reg in ("lit", "penumbra")}
        out[kind] = dict(rows, slopes=slopes, pixels={r: err.regions[r].pixels for r in ("lit", "penumbra", "umbra")},
                         mitsuba=lm.agreement(f.passes, ref_img).to_json(),
                         mitsuba_errors=lm.image_errors(f.radiance, f.uncertainty, ref_img).to_json())
    return out


def closed_form_check(frames: dict[str, Frame]) -> dict[str, Any]:
    """Lambert's rectangle formula against Mitsuba over the bare ground (and with L × 1.02, the power check)."""
    g = frames["ground_rectangle"]
    exact = lr.rectangle_irradiance(g.scene.lights[0], g.position, g.normal)
    ok = np.isfinite(exact)
    pred = g.shade(np.where(ok, exact, 0.0))
    a = lm.agreement(g.passes[:, ok], pred[ok])
    p = lm.agreement(g.passes[:, ok], 1.02 * pred[ok])
    return {"test": a.to_json(), "power": p.to_json(), "excluded_pixels": int((~ok).sum())}


def linearity(frames: dict[str, Frame], m: Measurements) -> dict[str, Any]:
    """The four-light render against the sum of the single renders, on the four-light render's pixels."""
    al = frames["all"]
    v = al.valid
    parts = [frames.get(f"sum_{k}", frames[k]).ref for k in SUM_LIGHTS]
    total = sum(r.radiance[v] for r in parts)
    var = sum(r.uncertainty[v] ** 2 for r in parts)
    total_se = math.sqrt(sum(lm.total_stderr(r.pass_images[:, v]) ** 2 for r in parts))
    a = lm.agreement(al.passes, total, np.sqrt(var), total_se)
    p = lm.agreement(al.passes, 1.02 * total, np.sqrt(var), total_se)
    unblocked = sum(frames[k].ref.radiance[v] for k in SUM_LIGHTS)  # singles without the rectangle's shadow
    q = lm.agreement(al.passes, unblocked, np.sqrt(var), total_se)
    m.images["linearity_z"] = al.image(a.z)
    return {"test": a.to_json(), "power_bias": p.to_json(), "power_unblocked": q.to_json(), "lights": list(SUM_LIGHTS)}


def model_sum(frames: dict[str, Frame], s: dict[str, Any]) -> dict[str, Any]:
    """Local models summed (inverse square + Mitsuba spot + directional + 16×16 shadowed grid) vs the render."""
    al = frames["all"]
    names = {"point": "point_inverse_square", "spot": "spot_mitsuba", "directional": "directional",
             "rectangle": "area_grid_shadowed"}
    e = np.zeros(len(al.position))
    for i, light in enumerate(al.scene.lights):
        lmap = dict(light_mapping(light, s, 1.0), grid=16)
        e += family.call(names[light.kind], lmap, al.position, al.normal, visible=lr.shadow_tester(al.scene, i))
    return lm.image_errors(al.radiance, al.uncertainty, al.shade(e)).to_json() | {"techniques": names}


def lamp_comparison(frames: dict[str, Frame], m: Measurements) -> dict[str, Any]:
    """A real lamp (disc behind an aperture) against the spot models fitted to its far-field profile, and
    against the 16×16 grid over its disc with the tube's shadow rays."""
    f = frames["lamp"]
    lamp = f.scene.lights[0]
    fit = sw.fit_lamp(*lamp.size)
    base = {"type": "spot", "position": np.asarray(lamp.position), "direction": lamp.frame()[2],
            "intensity": lamp.power * math.pi * lamp.size[0] ** 2}
    models = {"spot_cos_f": dict(base, exponent=fit["cos_f_exponent"], cutoff_angle=fit["edge_deg"]),
              "spot_mitsuba": dict(base, beam_width=fit["mitsuba_beam_deg"], cutoff_angle=fit["mitsuba_cutoff_deg"]),
              "area_grid_shadowed": dict(lamp.lamp_disc().as_mapping(), grid=16)}
    out: dict[str, Any] = {"fit": fit, "radius": lamp.size[0], "depth": lamp.size[1], "aperture": lamp.size[2],
                           "models": {}}
    m.images["lamp"] = {"Mitsuba lamp": f.ref.radiance}
    for name, lmap in models.items():
        approx = f.shade(family.call(name, lmap, f.position, f.normal, visible=f.visible))
        out["models"][name] = lm.image_errors(f.radiance, f.uncertainty, approx).to_json()
        out["models"][name]["agreement"] = lm.agreement(f.passes, approx).to_json()
        m.images["lamp"][name] = f.image(approx)
    return out


def spot_profile() -> dict[str, Any]:
    spot = ls.STANDARD_LIGHTS["spot"]
    f, rms = sw.fit_spot_exponent(spot.beam_deg, spot.cutoff_deg)
    return {"beam_deg": spot.beam_deg, "cutoff_deg": spot.cutoff_deg, "fitted_exponent": f, "fit_rms": rms}


def compute(ctx: Context) -> Measurements:
    s = QUICK if ctx.quick else FULL
    m = Measurements(dict(s))
    frames = render_frames(ctx, s)
    m.data["spot"] = spot_profile()
    evaluate_techniques(frames, s, m)
    m.data["attenuation"] = attenuation(s, frames)
    m.data["standin"] = sw.standin_sweep({k: ls.STANDARD_LIGHTS[k] for k in ls.AREA_KINDS}, np.asarray(s["ratios"]),
                                         s["polar_deg"], s["tilt_deg"])
    m.data["grid"] = grid_unshadowed(frames, s)
    m.data["grid_shadowed"] = grid_shadowed(frames, s)
    m.data["closed_form"] = closed_form_check(frames)
    m.data["linearity"] = linearity(frames, m)
    m.data["model_sum"] = model_sum(frames, s)
    m.data["lamp"] = lamp_comparison(frames, m)
    m.data["references"] = {k: f.ref.settings() for k, f in frames.items()}
    m.images["references"] = {k: f.ref.radiance for k, f in frames.items()}
    return m


# -- claims ------------------------------------------------------------------------------------------------------
def claims(m: Measurements) -> list[Claim]:
    out: list[Claim] = []
    for tech in family:
        out += technique_claims(NAME, tech, m.measured.get(tech.name, {}), unit="")
    cf = m.data["closed_form"]
    out.append(Claim(
        f"{NAME}.rectangle.closed_form", "Lambert's polygon formula = Mitsuba rectangle emitter over the bare ground "
        "(|pooled z| of Σ(render − formula) over the pixels)", "abs_pooled_z", cf["test"]["bias_bound"],
        abs(cf["test"]["pooled_z"]), 0.0,
        source="Lambert 1760 / Arvo 1994 eq. 2 (exact for a polygon above the horizon); |z| < 4 for one N(0,1) "
               "statistic (CLT over the pixels; two-sided false alarm 6·10⁻⁵)")
        .with_power("the closed form's radiance × 1.02 (a 2 % bias)", abs(cf["power"]["pooled_z"])))
    g = m.data["grid"]
    out.append(Claim(
        f"{NAME}.grid.midpoint_rate", f"n×n grid (midpoint rule) converges as n⁻²: |slope + 2| over n ≥ {SLOPE_FROM_N} "
        "(max relative error vs the closed form, bare ground)", "abs_slope_minus_order", RATE_TOLERANCE,
        abs(g["midpoint_slope"] + 2.0), 0.0,
        source="composite midpoint rule error (h²/24)∫f'' + O(h⁴) for f ∈ C² (Davis & Rabinowitz 1984 §2.2–2.3): "
               "order 2; 0.25 lies between it and the endpoint rule's order 1 with a 3× margin")
        .with_power("the left-endpoint (cell corner) rule", abs(g["corner_slope"] + 2.0)))
    lin = m.data["linearity"]
    out.append(Claim(
        f"{NAME}.sum.mean", "render with point + spot + directional + rectangle = sum of the four single renders "
        "(|pooled z|)", "abs_pooled_z", lin["test"]["bias_bound"], abs(lin["test"]["pooled_z"]), 0.0,
        source="linearity of the rendering equation in the emitted radiance (Kajiya 1986 eq. 1); |z| < 4 for one "
               "N(0,1) statistic (false alarm 6·10⁻⁵)")
        .with_power("the sum of the single renders × 1.02 (a 2 % bias)", abs(lin["power_bias"]["pooled_z"])))
    out.append(Claim(
        f"{NAME}.sum.max", "the same, every pixel: max |z| below the Šidák critical value at α = 0.01", "max_abs_z",
        lin["test"]["critical_z"], lin["test"]["max_abs_z"], 0.0,
        source="Kajiya 1986 eq. 1 (linearity); Šidák 1967 family-wise level 0.01 over the N pixels")
        .with_power("single renders without the rectangle's shape (its shadow on the other lights missed, the bug "
                    "this check caught while it was written)", lin["power_unblocked"]["max_abs_z"]))
    return out


# -- findings --------------------------------------------------------------------------------------------------
def _slope(x: float | None) -> str:
    return "n/a" if x is None else f"{x:.2f}"


def attenuation_findings(m: Measurements) -> list[str]:
    att, tech = m.data["attenuation"], m.data["techniques"]
    lo, hi = att["scene_distance_range"]
    out = []
    for name, a in att["techniques"].items():
        at = a["relative_error_at"]
        bias = tech[name]["metrics"].get("point", {}).get("bias", {}).get("value", float("nan"))
        out.append(f"{name}: E/E_(1/d²) − 1 = {at['1 m']:+.1%} at 1 m, {at['5 m']:+.1%} at 5 m, {at['10 m']:+.1%} at "
                   f"10 m; with the best single intensity scale ({a['best_scale']:.3g}×) still "
                   f"{a['best_scale_max_error']:.1%} off somewhere in the scene's {lo:.2f}–{hi:.2f} m; in the "
                   f"rendered scene its bias is {bias:+.1%}.")
    return out


def grid_findings(m: Measurements) -> list[str]:
    g, gs = m.data["grid"], m.data["grid_shadowed"]
    out = [f"n×n grid, unshadowed rectangle: max relative error {g['midpoint_max_rel'][0]:.2%} at n = 1, "
           f"{g['midpoint_max_rel'][-1]:.2e} at n = {g['n'][-1]}; slope {g['midpoint_slope']:.2f} (theory −2); "
           f"corner rule slope {g['corner_slope']:.2f} (theory −1)."]
    for kind in ls.AREA_KINDS:
        sh, sl, z = gs[kind], gs[kind]["slopes"], gs[kind]["mitsuba"]
        out.append(f"Shadowed {kind} grid against the {gs['reference_n']}² grid: penumbra mean error "
                   f"{sh['penumbra'][0]:.1%} at n = 1, {sh['penumbra'][-1]:.2%} at n = {gs['n'][-1]} (slope "
                   f"{_slope(sl['penumbra'])}), lit {sh['lit'][-1]:.2e} (slope {_slope(sl['lit'])}); the "
                   f"{gs['reference_n']}² grid vs Mitsuba: pooled z {z['pooled_z']:+.2f} (bound ±{z['bias_bound']:g}, "
                   f"relative bias {z['relative_bias']:+.2%}), max |z| {z['max_abs_z']:.2f} (critical "
                   f"{z['critical_z']:.2f}).")
    return out


def lamp_finding(lamp: dict[str, Any]) -> str:
    fit, mod = lamp["fit"], lamp["models"]
    z = mod["area_grid_shadowed"]["agreement"]
    return (f"A real lamp (disc r = {lamp['radius'] * 100:g} cm at the end of a {lamp['depth'] * 100:g} cm black tube "
            f"of radius {lamp['aperture'] * 100:g} cm, "
            f"beam edge {fit['edge_deg']:.1f}°): its far-field profile is matched by cos^f α with f = "
            f"{fit['cos_f_exponent']:.1f} (rms {fit['cos_f_rms']:.1%} of the peak) or by Mitsuba's linear spot with "
            f"beam {fit['mitsuba_beam_deg']:.1f}°, cutoff {fit['mitsuba_cutoff_deg']:.1f}° (rms "
            f"{fit['mitsuba_rms']:.1%}); rendered, the fitted cos^f spot is off by {mod['spot_cos_f']['mean']:.1%} on "
            f"average (max {mod['spot_cos_f']['max']:.0%}), the fitted linear spot by "
            f"{mod['spot_mitsuba']['mean']:.1%} "
            f"(max {mod['spot_mitsuba']['max']:.0%}), the 16² grid through the tube by "
            f"{mod['area_grid_shadowed']['mean']:.2%} ± {mod['area_grid_shadowed']['mean_uncertainty']:.2%} "
            f"(pooled z {z['pooled_z']:+.2f}).")


def findings(m: Measurements) -> list[str]:
    out = attenuation_findings(m)
    st = m.data["standin"]
    for kind in ls.AREA_KINDS:
        r = st[kind]["ratio_within_1pct"]
        out.append(f"A single point light stands in for the {kind} within 1 % (worst receiver, polar ≤ "
                   f"{max(st['polar_deg']):g}°, tilt ≤ {max(st['tilt_deg']):g}°) beyond d/size = "
                   + (f"{r:.3g}" if r is not None else "> the largest ratio swept") + " (size = largest dimension).")
    out += grid_findings(m)
    sp, tech = m.data["spot"], m.data["techniques"]
    cos_f = tech.get("spot_cos_f", {}).get("metrics", {}).get("spot", {})
    out.append(f"Mitsuba's spot (beam {sp['beam_deg']:g}°, cutoff {sp['cutoff_deg']:g}°) is best matched by cos^f α "
               f"with f = {sp['fitted_exponent']:.1f} (rms {sp['fit_rms']:.1%} of the peak over the cone)"
               + (f"; rendered, that cos^f spot is off by {cos_f['mean']['value']:.1%} on average and "
                  f"{cos_f['max']['value']:.0%} at worst (of the mean lit radiance)." if cos_f else "."))
    out.append(lamp_finding(m.data["lamp"]))
    grid = {k: tech.get(k, {}).get("metrics", {}) for k in ("area_grid", "area_grid_shadowed")}
    if all(grid.values()):
        n = m.settings["technique_grid"]
        out.append(f"The {n}×{n} grid over the scene, without its shadow rays: bias " + ", ".join(
            f"{k} {v['bias']['value']:+.1%}" for k, v in grid["area_grid"].items()) + "; with them: " + ", ".join(
            f"{k} {v['bias']['value']:+.2%} (mean {v['mean']['value']:.2%} ± {v['mean']['uncertainty']:.2%})"
            for k, v in grid["area_grid_shadowed"].items()) + ".")
    two = tech.get("point_two_sided", {}).get("metrics", {}).get("point", {})
    if two:
        out.append(f"Two-sided lighting on this closed geometry with shadow rays: max difference from Mitsuba "
                   f"{two['max']['value']:.1e} — a back face is always shadowed by its own object.")
    lin, ms = m.data["linearity"]["test"], m.data["model_sum"]
    out.append(f"Lights add linearly: pooled z = {lin['pooled_z']:+.2f} (bound ±{lin['bias_bound']:g}), max |z| = "
               f"{lin['max_abs_z']:.2f} (critical {lin['critical_z']:.2f}); the local models summed are "
               f"{ms['mean']:.2%} ± {ms['mean_uncertainty']:.2%} off on average (bias {ms['bias']:+.2%}).")
    return out


@register_experiment(NAME, "The textbooks' classic lights against physics",
                     "point, spot, directional and area lights; attenuation sets, point stand-ins, n×n grids", order=70)
def run(ctx: Context) -> ExperimentResult:
    m = compute(ctx)
    res = ExperimentResult(NAME, "The textbooks' classic lights against physics",
                           "Directional, point (inverse square and engine attenuations), spot (cos^f and Mitsuba's "
                           "profile) and area lights as n×n point grids, against Mitsuba's direct lighting.")
    res.claims = claims(m)
    res.findings = findings(m)
    res.sections = report.sections(m, ctx, NAME)
    res.settings = {k: v for k, v in m.settings.items() if k not in ("ratios", "distances")}
    res.data = {k: v for k, v in m.data.items() if k != "techniques"}
    for tech in family:
        metrics = m.data["techniques"][tech.name]["metrics"]
        res.techniques[tech.name] = technique_entry(tech, metrics, lights=m.data["techniques"][tech.name]["lights"])
    return res
