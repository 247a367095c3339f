"""``lights`` compute step: the reference renders, every technique on them, the attenuation, stand-in and
grid sweeps (:mod:`.sweeps`) and the closed-form and linearity checks; numbers and images only."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models import light as family
from ...metrics import shadow_error as se
from ...reference import light_render as lr
from ...scenes import light_scenes as ls
from ...scenes.latlong import luminance
from ..base import Context, settings_json
from . import image_metrics as lm
from . import sweeps as sw
from .settings import Settings

SINGLES = ("point", "spot", "directional", "rectangle", "disk", "sphere")
SUM_LIGHTS = ("point", "spot", "directional", "rectangle")
SLOPE_FROM_N = 4  # claim 3: the slope is fitted over n ≥ 4 (the asymptotic range of the h² term)


@dataclass
class Measurements:
    """``data``: JSON-able numbers; ``images``: arrays for the report (not written to results.json)."""

    settings: Settings
    data: dict[str, Any] = field(default_factory=dict)
    images: Settings = field(default_factory=dict)
    measured: dict[str, dict[str, Any]] = field(default_factory=dict)  # technique → metric → Measured


# -- references ------------------------------------------------------------------------------------------
def scenes(s: Settings) -> dict[str, tuple[ls.LightScene, int, int]]:
    """name → (scene, spp, passes) of every reference render."""
    w, h = s.width, s.height
    out = {}
    for kind in SINGLES:
        delta = kind in ("point", "spot", "directional")
        out[kind] = (ls.light_scene((kind,), w, h), s.delta_spp if delta else s.area_spp,
                     s.delta_passes if delta else s.area_passes)
    for kind in SUM_LIGHTS:  # the delta lights again, with the rectangle's shape present (it casts shadows)
        if kind not in ls.AREA_KINDS:
            out[f"sum_{kind}"] = (ls.light_scene((kind,), w, h, blockers=("rectangle",)), s.delta_spp,
                                  s.delta_passes)
    out["all"] = (ls.light_scene(SUM_LIGHTS, w, h), s.sum_spp, s.sum_passes)
    out["lamp"] = (ls.light_scene(("lamp",), w, h), s.area_spp, s.area_passes)
    out["ground_rectangle"] = (ls.light_scene(("rectangle",), w, h, occluders=False), s.ground_spp,
                               s.ground_passes)
    return out


def light_mapping(light: ls.Light, s: Settings, spot_exponent: float) -> dict[str, Any]:
    """What a technique receives: the light plus the experiment's choices (range, fitted f, grid n)."""
    m = light.as_mapping()
    m.update({"point": {"range": s.range}, "spot": {"exponent": spot_exponent}}.get(light.kind, {}))
    if light.kind in ls.AREA_KINDS:
        m["grid"] = s.technique_grid
    return m


def _canonical(value: Any) -> str:
    """A light-mapping value as an exact string (arrays: dtype, shape and every element's repr)."""
    if isinstance(value, np.ndarray):
        return f"{value.dtype}{value.shape}{[repr(x) for x in value.ravel().tolist()]}"
    if isinstance(value, (list, tuple)):
        return f"{type(value).__name__}{[_canonical(x) for x in value]}"
    return repr(value)


class Frame:
    """One render's valid pixels: G-buffer, reference and the shadow-ray test of its geometry."""

    def __init__(self, scene: ls.LightScene, ref: lr.LightRender):
        self.scene, self.ref, self.valid = scene, ref, ref.valid
        v = ref.valid
        self.position, self.normal, self.albedo = ref.position[v], ref.normal[v], ref.albedo[v]
        self.radiance, self.uncertainty = ref.radiance[v], ref.uncertainty[v]
        self.passes = ref.pass_images[:, v]  # (P, N, 3)
        self.visible = lr.shadow_tester(scene)
        self._irradiance: dict[tuple[str, tuple[tuple[str, str], ...]], np.ndarray] = {}

    def irradiance(self, tech: Any, light_map: dict[str, Any]) -> np.ndarray:
        """``tech`` (a light technique or its name) on this frame's G-buffer with its shadow rays, memoised: a
        technique is a deterministic function of its light mapping, the receivers and the scene, so a second call
        with an equal mapping (the technique table and the grid sweep both evaluate the shadowed grid at the
        technique's n) returns the first call's E (a copy) instead of tracing its shadow rays again."""
        name = tech if isinstance(tech, str) else tech.name
        key = (name, tuple(sorted((k, _canonical(v)) for k, v in light_map.items())))
        if key not in self._irradiance:
            self._irradiance[key] = family.call(tech, light_map, self.position, self.normal, visible=self.visible)
        return self._irradiance[key].copy()

    def shade(self, irradiance: np.ndarray) -> np.ndarray:
        return self.albedo / math.pi * irradiance[:, None]

    def image(self, values: np.ndarray) -> np.ndarray:
        out = np.full(self.valid.shape + values.shape[1:], np.nan)
        out[self.valid] = values
        return out


def render_cost(scene: ls.LightScene, spp: int, passes: int) -> int:
    """A render's relative cost for scheduling: samples traced, pixels × spp × passes."""
    return scene.camera.width * scene.camera.height * spp * passes


def render_frames(ctx: Context, s: Settings) -> dict[str, Frame]:
    """Every reference render (``ctx.map``: in this process or on the Dask workers), the costliest first so that
    two workers do not wait on one long render at the end; each render is seeded alone, so the order changes no
    number."""
    items = sorted(scenes(s).items(), key=lambda it: -render_cost(*it[1]))
    refs = ctx.map(lambda it: lr.render_lights(it[1][0], it[1][1], it[1][2], s.seed), items, "lights: renders")
    done = {name: ref for (name, _), ref in zip(items, refs, strict=True)}
    return {name: Frame(sc[0], done[name]) for name, sc in scenes(s).items()}


# -- techniques ----------------------------------------------------------------------------------------------
def evaluate_techniques(frames: dict[str, Frame], s: Settings, m: Measurements) -> None:
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
            e = f.irradiance(tech, light_mapping(f.scene.lights[0], s, spot_f))
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
def attenuation(s: Settings, frames: dict[str, Frame]) -> dict[str, Any]:
    """E/E_inv² over distance for every point technique; scale-fitted error over the scene's distances."""
    d = np.asarray(s.distances)
    curves = sw.attenuation_curves(d, s.range)
    f = frames["point"]
    dist = np.linalg.norm(f.position - np.asarray(f.scene.lights[0].position), axis=1)
    lo, hi = float(dist.min()), float(dist.max())
    ds = np.geomspace(lo, hi, 64)
    scene_curves = sw.attenuation_curves(ds, s.range)
    out: dict[str, Any] = {"distances": d.tolist(), "scene_distance_range": [lo, hi], "techniques": {}}
    for name, ratio in curves.items():
        k, err = sw.best_scale_error(scene_curves[name])
        at = {f"{x:g} m": float(np.interp(x, d, ratio) - 1.0) for x in (0.5, 1.0, 2.0, 5.0, 10.0)}
        out["techniques"][name] = {"ratio": ratio.tolist(), "relative_error_at": at, "best_scale": k,
                                   "best_scale_max_error": err}
    return out


def grid_unshadowed(frames: dict[str, Frame], s: Settings) -> dict[str, Any]:
    """Unshadowed n×n grid (midpoint and corner rules) vs Lambert's formula over the bare ground."""
    g = frames["ground_rectangle"]
    rect = g.scene.lights[0]
    exact = lr.rectangle_irradiance(rect, g.position, g.normal)
    ns = list(s.grid_ns)
    mid = sw.grid_errors(rect, g.position, g.normal, exact, ns, 0.5)
    corner = sw.grid_errors(rect, g.position, g.normal, exact, ns, 0.0)
    return {"n": ns, "midpoint_max_rel": mid, "corner_max_rel": corner,
            "midpoint_slope": sw.loglog_slope(ns, mid, SLOPE_FROM_N),
            "corner_slope": sw.loglog_slope(ns, corner, SLOPE_FROM_N)}


def grid_shadowed(frames: dict[str, Frame], s: Settings) -> dict[str, Any]:
    """Shadowed n×n grid by region (lit / penumbra / umbra, as in ``shadows``) against the fine grid
    n_ref × n_ref (noise-free self-convergence), and the fine grid against Mitsuba's render (z test)."""
    out: dict[str, Any] = {"n": list(s.grid_ns), "reference_n": s.grid_reference}
    for kind in ls.AREA_KINDS:
        f = frames[kind]
        light = f.scene.lights[0]
        ref_img = f.shade(family.call("area_grid_shadowed", dict(light.as_mapping(), grid=s.grid_reference),
                                      f.position, f.normal, visible=f.visible))
        v_ref = sw.visible_fraction(light, f.position, f.normal, f.visible, s.visibility_side)
        rows: dict[str, list[float]] = {"lit": [], "penumbra": [], "umbra": [], "total": []}
        for n in out["n"]:
            e = f.irradiance("area_grid_shadowed", dict(light.as_mapping(), grid=n))
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


def model_sum(frames: dict[str, Frame], s: Settings) -> dict[str, Any]:
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


def compute(ctx: Context, s: Settings) -> Measurements:
    """Every reference render, every technique on it, the sweeps and the consistency checks."""
    m = Measurements(settings_json(s))
    frames = render_frames(ctx, s)
    m.data["spot"] = spot_profile()
    evaluate_techniques(frames, s, m)
    m.data["attenuation"] = attenuation(s, frames)
    m.data["standin"] = sw.standin_sweep({k: ls.STANDARD_LIGHTS[k] for k in ls.AREA_KINDS}, np.asarray(s.ratios),
                                         s.polar_deg, s.tilt_deg, s.standin_xtol)
    m.data["grid"] = grid_unshadowed(frames, s)
    m.data["grid_shadowed"] = grid_shadowed(frames, s)
    m.data["closed_form"] = closed_form_check(frames)
    m.data["linearity"] = linearity(frames, m)
    m.data["model_sum"] = model_sum(frames, s)
    m.data["lamp"] = lamp_comparison(frames, m)
    m.data["references"] = {k: f.ref.settings() for k, f in frames.items()}
    m.images["references"] = {k: f.ref.radiance for k, f in frames.items()}
    return m


