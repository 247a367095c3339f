"""Numbers of the ``listings`` experiment: the seeds' listings run as printed, the printed equations, Mitsuba.

Parts (each a dict of plain numbers in :class:`Measurements`):

* ``transcription`` (GL only): per runnable listing, ``rel`` = max |GLSL − Python| / max |Python| over
  random receivers (the float64 transcription of the same listing and host state);
* ``cook_torrance``: per Mitsuba ``roughconductor`` (Beckmann α), every reading of Ganovelli's eq.
  6.60–6.66 (:mod:`validate.local_models.brdf.ganovelli_cook_torrance`), the suite's existing
  ``cook_torrance_printed`` and the corrected ``cook_torrance``: ``energy_ratio`` = Σ w Y(q) / Σ w Y(q_ref)
  and ``rel_l1`` = Σ w |Y(q) − Y(q_ref)| / Σ w Y(q_ref) over the (l, v) grid of
  :func:`validate.scenes.brdf_scenes.brdf_grid` (Y luminance, q the cosine-weighted BRDF); uncertainty
  = |value(n) − value(n/2)| (quadrature);
* ``point``: receivers on the plane y = 0 under a point light; E_ref from Mitsuba's point emitter
  (:func:`validate.reference.point_emitter.point_irradiance`, float32, deterministic); per technique the
  ratio E/E_ref (min, max over receivers with E_ref > 10⁻³ max) and rel_l1 = Σ|E − E_ref|/Σ E_ref;
* ``falloff``: Fore June's eq. 20.47 as printed and as coded, against the exact on-axis irradiance of a
  Lambertian disc E(d) = πLr²/(r² + d²) (:func:`validate.reference.uberlight_render.disc_on_axis_irradiance`)
  with α = 2, M = πL = E(0), K = πLr²/d₀² (the far field), d₀ = 2r; and the one-sided slopes at d₀ with the
  book's own values (M, K, d₀, α) = (2, 1, 1, 1);
* ``uberlight_book``: Fore June's listing with Figure 20-17's values on the projector scene's sphere
  (coordinates centred on it, in units of its radius; the light at centre + r·(1, 1, 2), aimed at the
  centre) against Mitsuba's projector carrying exactly the listing's superellipse mask;
  ``orange``: Listings 12.6/12.7 against the projector of the ``uberlight`` experiment's shape. Errors are
  |L − L_ref|/peak over the compared pixels (max, mean), raw (the unit map of the module ``report``) and
  after the least-squares scale; uncertainty = the largest per-pixel standard error / peak;
* ``hemisphere``: the Red Book's "actual analytic function" a(θ) against the exact fraction (1 + cos θ)/2;
* ``redbook_values``: white-furnace albedo of Blinn–Phong with the Red Book's suggested Shininess 20,
  Strength 10 and a white base colour.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...local_models import family
from ...local_models.brdf import ganovelli_cook_torrance as gct
from ...local_models.brdf import usc420_phong as usc
from ...local_models.brdf.classic_brdfs import cook_torrance, cook_torrance_printed
from ...local_models.light import ganovelli_lamps as g6
from ...local_models.light import redbook_lights as rb
from ...local_models.listings import diffuse_listings as dl
from ...local_models.listings import fore_june_uberlight as fj
from ...local_models.listings.runner import GL_SKIPPED, gl_status, unit
from ...local_models.uberlight import fore_june_falloff as ff
from ...local_models.uberlight import orange_uberlight as ou
from ...local_models.uberlight.orange_book import NO_DISTANCE_SHAPING, superellipse_shape_np
from ...reference import brdf_render as br
from ...reference import uberlight_render as ur
from ...reference.point_emitter import point_irradiance
from ...scenes import brdf_scenes as bs
from ...scenes import uberlight_scenes as us
from ...scenes.latlong import luminance
from ..base import Context
from .settings import Settings

POINT_LIGHT = {"type": "point", "position": np.array([0.4, 1.5, -0.3]), "intensity": 10.0}
SPOT_LIGHT = {"type": "spot", "position": np.array([0.4, 1.5, -0.3]), "intensity": 10.0,
              "direction": np.array([0.0, -1.0, 0.0]), "cutoff_angle": 40.0, "exponent": 4.0}
PROJECTOR_SHAPE = {"width": 0.35, "height": 0.25, "width_edge": 0.1, "height_edge": 0.1, "roundness": 1.0}
# the uberlight experiment's projector shape with soft edges 0.1 (the Orange Book prints no values; a hard edge
# would leave the bilinear texture blend of Mitsuba's projector at the edge pixels, a property of the reference)
INTENSITY = 50.0  # W sr⁻¹ on the projector's axis
MASK_FRACTION = 1e-3


@dataclass
class Measurements:
    settings: Settings
    gl: dict[str, Any]
    transcription: dict[str, Any] = field(default_factory=dict)
    cook_torrance: dict[str, Any] = field(default_factory=dict)
    point: dict[str, Any] = field(default_factory=dict)
    falloff: dict[str, Any] = field(default_factory=dict)
    uberlight_book: dict[str, Any] = field(default_factory=dict)
    barndoor_book: dict[str, Any] = field(default_factory=dict)
    orange: dict[str, Any] = field(default_factory=dict)
    hemisphere: dict[str, Any] = field(default_factory=dict)
    redbook_values: dict[str, Any] = field(default_factory=dict)


# -- GLSL vs Python ------------------------------------------------------------------------------------------
def _receivers(s: Settings) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(s.seed)
    n = s.receivers
    sphere = unit(rng.normal(size=(n, 3)))
    plane = np.c_[rng.uniform(-2, 2, n), np.zeros(n), rng.uniform(-2, 2, n)]
    normals = unit(rng.normal(size=(n, 3)) + [0.0, 1.5, 0.0])
    lv = np.abs(rng.normal(size=(2, n, 3)))
    return {"sphere": sphere, "plane": plane, "normals": normals, "l": unit(lv[0] * [1, 1, 1]),
            "v": unit(lv[1] * [1, 1, 1]), "random": rng.normal(size=(n, 3))}


def _pairs(r: dict[str, np.ndarray]) -> dict[str, tuple[Any, Any]]:
    """listing → (python(), glsl()) closures over the receivers."""
    up = np.tile([0.0, 1.0, 0.0], (len(r["plane"]), 1))
    lum = us.Luminaire("projector")
    olight = {"position": np.asarray(lum.position), "axes": lum.frame(), "intensity": INTENSITY, **NO_DISTANCE_SHAPING,
              **PROJECTOR_SHAPE}
    views = unit(np.asarray(us.Camera().origin) - r["plane"])
    mat = {"albedo": 0.5, "ks": 0.3}
    nz = np.tile([0.0, 0.0, 1.0], (len(r["l"]), 1))
    prm = {"albedo": 0.6, "ks": 0.4, "phong_exponent": 20.0}
    d = np.array([0.3, -1.0, 0.2])
    out: dict[str, tuple[Any, Any]] = {
        name: (lambda nm=name: dl.python(nm, r["random"], r["normals"], 0.7),
               lambda nm=name: dl.glsl(nm, r["random"], r["normals"], 0.7)) for name in dl.NAMES}
    out["forejune_20_5"] = (lambda: fj.python(r["sphere"]), lambda: fj.glsl(r["sphere"]))
    out["orange_12_6_12_7"] = (lambda: ou.python(olight, r["plane"], up, views, mat),
                               lambda: ou.glsl(olight, r["plane"], up, views, mat))
    out["ganovelli_6_3_6_4"] = (lambda: g6.python_directional(d, 3.0, r["normals"]),
                                lambda: g6.glsl_directional(d, 3.0, r["plane"], r["normals"]))
    out["ganovelli_6_9"] = (lambda: g6.python_lamp(POINT_LIGHT["position"], 10.0, r["plane"], r["normals"]),
                            lambda: g6.glsl_lamp(POINT_LIGHT["position"], 10.0, r["plane"], r["normals"]))
    for name, lm, spot in (("redbook_7_4", POINT_LIGHT, False), ("redbook_7_5", SPOT_LIGHT, True),
                           ("redbook_7_6", POINT_LIGHT, False)):
        out[name] = (lambda lm=lm, sp=spot: rb.python(lm, r["plane"], r["normals"], sp),
                     lambda nm=name, lm=lm: rb.glsl(nm, lm, r["plane"], r["normals"]))
    from ...local_models.brdf.classic_brdfs import phong

    out["usc420_l11"] = (lambda: phong(prm, nz, r["l"], r["v"]), lambda: usc.phong_usc420_glsl(prm, nz, r["l"], r["v"]))
    return out


def transcription_checks(s: Settings) -> dict[str, Any]:
    """rel = max |GLSL − Python| / max |Python| per listing; perturbed = the same with Python × (1 + 10⁻⁴)."""
    out: dict[str, Any] = {}
    for name, (py, gl) in _pairs(_receivers(s)).items():
        a, b = np.asarray(py(), dtype=np.float64), np.asarray(gl(), dtype=np.float64)
        scale = float(np.max(np.abs(a)))
        out[name] = {"rel": float(np.max(np.abs(a - b)) / scale), "max_abs": float(np.max(np.abs(a - b))),
                     "scale": scale, "perturbed": float(np.max(np.abs(a * (1 + 1e-4) - b)) / scale), "n": int(len(a))}
    return out


# -- Cook–Torrance readings ----------------------------------------------------------------------------------
def _ct_rows(params: dict[str, Any], lights: np.ndarray, views: np.ndarray, w: np.ndarray,
             ref: np.ndarray) -> dict[str, dict[str, float]]:
    n = np.tile([0.0, 0.0, 1.0], (len(lights), 1))
    qs = {k: gct.reading(params, n, lights, views, k) for k in gct.READINGS}
    qs["cook_torrance_printed (suite)"] = cook_torrance_printed(params, n, lights, views)
    qs["cook_torrance (corrected)"] = cook_torrance(params, n, lights, views)
    yr = luminance(ref)
    return {k: {"energy_ratio": float(np.sum(w * luminance(q)) / np.sum(w * yr)),
                "rel_l1": float(np.sum(w * np.abs(luminance(q) - yr)) / np.sum(w * yr))} for k, q in qs.items()}


def cook_torrance_readings(s: Settings) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for a in s.ct_alphas:
        mat = bs.conductor(a)
        rows = []
        for g in (s.brdf_grid, s.brdf_grid // 2):
            lights, views, w = bs.brdf_grid(g, g)
            rows.append(_ct_rows(mat.params, lights, views, w, br.eval_bsdf(mat.bsdf, lights, views)))
        out[f"{a:g}"] = {k: {m: v for m, v in rows[0][k].items()} | {
            "uncertainty_energy": abs(rows[0][k]["energy_ratio"] - rows[1][k]["energy_ratio"]),
            "uncertainty_rel_l1": abs(rows[0][k]["rel_l1"] - rows[1][k]["rel_l1"])} for k in rows[0]}
    return out


# -- point lights --------------------------------------------------------------------------------------------
def point_comparison(s: Settings, gl_ok: bool) -> dict[str, Any]:
    t = np.linspace(-s.plane_half, s.plane_half, s.plane_nodes)
    xx, zz = np.meshgrid(t, t)
    pts = np.c_[xx.ravel(), np.zeros(xx.size), zz.ravel()]
    nrm = np.tile([0.0, 1.0, 0.0], (len(pts), 1))
    ref = point_irradiance(POINT_LIGHT["position"], POINT_LIGHT["intensity"], pts, nrm)
    keep = ref > MASK_FRACTION * ref.max()
    fam = family("light")
    runs: dict[str, Any] = {
        "point_inverse_square (corrected)": lambda: fam.call("point_inverse_square", POINT_LIGHT, pts, nrm),
        "point_usc420_a1b1c0 (printed)": lambda: fam.call("point_usc420_a1b1c0", POINT_LIGHT, pts, nrm),
        "ganovelli_6_9 (" + ("GLSL" if gl_ok else "Python transcription") + ")":
            (lambda: g6.glsl_lamp(POINT_LIGHT["position"], 10.0, pts, nrm)) if gl_ok
            else (lambda: g6.python_lamp(POINT_LIGHT["position"], 10.0, pts, nrm)),
        "ganovelli_6_9 with r = |p − x| (corrected)":
            lambda: g6.python_lamp(POINT_LIGHT["position"], 10.0, pts, nrm) / g6.LAMP_FACTOR,
        "redbook_7_4 (" + ("GLSL" if gl_ok else "Python transcription") + ")":
            (lambda: rb.glsl("redbook_7_4", POINT_LIGHT, pts, nrm)) if gl_ok
            else (lambda: rb.python(POINT_LIGHT, pts, nrm, False)),
        "redbook_7_4, k_q = 1.01 (power)": lambda: rb.python(dict(POINT_LIGHT, attenuation=(0.0, 0.0, 1.01)), pts, nrm,
                                                              False)}
    out: dict[str, Any] = {"receivers": int(keep.sum()), "reference": "Mitsuba point emitter (float32)"}
    for name, fn in runs.items():
        e = np.asarray(fn(), dtype=np.float64)
        ratio = e[keep] / ref[keep]
        out[name] = {"ratio_min": float(ratio.min()), "ratio_max": float(ratio.max()),
                     "max_rel": float(np.max(np.abs(ratio - 1.0))),
                     "rel_l1": float(np.sum(np.abs(e[keep] - ref[keep])) / np.sum(ref[keep]))}
    return out


# -- Fore June falloff ---------------------------------------------------------------------------------------
def falloff_comparison(s: Settings) -> dict[str, Any]:
    r, lrad = 1.0, 1.0 / math.pi
    d = np.linspace(20.0 * r / s.falloff_nodes, 20.0 * r, s.falloff_nodes)
    exact = ur.disc_on_axis_irradiance(d, lrad, r)
    d0 = 2.0 * r
    m, k = math.pi * lrad, math.pi * lrad * r * r / d0 ** 2
    out: dict[str, Any] = {"d0_over_r": d0 / r, "alpha": 2.0, "M": m, "K": k}
    for form, fn in (("printed", ff.falloff_printed), ("listing", ff.falloff_listing)):
        v = fn(d, k, m, d0, 2.0)
        rel = np.abs(v / exact - 1.0)
        lo, hi = ff.slopes_at_d0(k, m, d0, 2.0, form)
        out[form] = {"max_rel": float(rel.max()), "max_rel_near": float(rel[d < d0].max()),
                     "at_d_small": float(fn(np.array([1e-3 * r]), k, m, d0, 2.0)[0] / m), "slope_inner": lo,
                     "slope_outer": hi, "slope_mismatch": abs(lo - hi) / abs(hi)}
        bl, bh = ff.slopes_at_d0(1.0, 2.0, 1.0, 1.0, form)
        out[form]["book_slopes"] = [bl, bh]
        out[form]["book_limit_at_0"] = float(fn(np.array([1e-4]), 1.0, 2.0, 1.0, 1.0)[0])
    return out


# -- the überlight listings against the projector ------------------------------------------------------------
def _projector_ref(scene: us.UberScene, mask: np.ndarray, s: Settings) -> ur.UberRender:
    return ur.render(scene, ur.projector_texture(mask, INTENSITY, s.fov_deg), 1, 2, s.seed)


def _errors(model: np.ndarray, ref: np.ndarray, unc: np.ndarray, peak: float) -> dict[str, float]:
    k = float(model @ ref / (model @ model)) if model @ model > 0 else 1.0
    return {"max_rel": float(np.max(np.abs(model - ref)) / peak),
            "mean_rel": float(np.mean(np.abs(model - ref)) / peak),
            "scaled_max_rel": float(np.max(np.abs(k * model - ref)) / peak),
            "scaled_mean_rel": float(np.mean(np.abs(k * model - ref)) / peak), "scale": k,
            "uncertainty": float(unc.max() / peak)}


def book_scene(s: Settings) -> tuple[us.UberScene, np.ndarray, float]:
    """The projector at sphere centre + r·(1, 1, 2) aimed at the centre; (scene, centre, radius)."""
    c, r = np.asarray(us.SPHERE["center"], dtype=np.float64), float(us.SPHERE["radius"])
    pos = c + r * np.asarray(fj.BOOK["lightPos"][:3])
    lum = us.Luminaire("projector", position=tuple(pos), target=tuple(c), fov_deg=s.fov_deg)
    return us.UberScene(lum, us.Camera(width=s.projector_size[0], height=s.projector_size[1]), True,
                        "listings_forejune_book"), c, r


def book_mask(scene: us.UberScene, s: Settings) -> np.ndarray:
    """The listing's superEllipseShape at the projector's texel directions (in the listing's light frame)."""
    x, y = ur.texel_directions(s.texture, s.fov_deg)
    f = scene.luminaire.frame()
    dirs = x[..., None] * f[0] + y[..., None] * f[1] + f[2]
    lc = dirs.reshape(-1, 3) @ fj.rotation(fj.BOOK["lightPos"]).T
    return fj.super_ellipse_shape(lc, fj.BOOK).reshape(x.shape)


def uberlight_book(s: Settings, gl_ok: bool) -> dict[str, Any]:
    scene, c, r = book_scene(s)
    ref = _projector_ref(scene, book_mask(scene, s), s)
    on_sphere = ref.valid & (np.abs(np.linalg.norm(ref.position - c, axis=-1) - r) < 1e-3 * r)
    lit = on_sphere & (ref.radiance > 0)
    q = (ref.position[on_sphere] - c) / r
    u = dict(fj.BOOK, eyePos=(*((np.asarray(scene.camera.origin) - c) / r), 1.0))
    rgb = (fj.glsl(q, u) if gl_ok else fj.python(q, u))[:, :3].astype(np.float64)
    t = fj.terms(q, u)
    lp = np.asarray(u["lightPos"][:3])
    dist = np.linalg.norm(q - lp, axis=1)
    cos = np.maximum(np.sum(unit(q) * unit(lp - q), axis=1), 0.0)
    shape = fj.super_ellipse_shape((q - lp) @ fj.rotation(lp).T, u)
    unit_map = ref.albedo[on_sphere] / math.pi * INTENSITY / r ** 2  # K = 1 at d0 = 1 (one radius) ≙ I₀/r²
    models = {"as printed (GLSL)" if gl_ok else "as printed (Python transcription)": luminance(rgb),
              "light term only (diffuse: shape × zones × falloff × n·l)": t["diffuse"],
              "shape × n·l / d² (the projector's physics: pipeline check)": shape * cos / dist ** 2}
    rad, unc = ref.radiance[on_sphere], ref.uncertainty[on_sphere]
    peak = float(rad.max())
    out: dict[str, Any] = {"pixels": int(on_sphere.sum()), "lit_pixels": int(lit.sum()), "peak": peak,
                           "zones_zero": int(np.sum((t["attenuation"] == 0) & (rad > 0))), "models": {}}
    for name, val in models.items():
        out["models"][name] = _errors(unit_map * val, rad, unc, peak)
    depth = np.abs(((q - lp) @ fj.rotation(lp).T)[:, 2])
    out["depth_range"] = [float(depth[rad > 0].min()), float(depth[rad > 0].max())] if (rad > 0).any() else [0, 0]
    return out


def axis_rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues: the rotation by ``angle`` about the unit ``axis`` (3 × 3)."""
    u = unit(np.asarray(axis, dtype=np.float64))
    k = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def listing_world(scene: us.UberScene) -> np.ndarray:
    """Q: scene directions → the listing's world, a rotation about the light axis (which keeps lightPos) that
    turns the listing's light x axis (row 0 of :func:`fore_june_uberlight.rotation`) onto the luminaire's x
    (left) axis, so the barn door's hole and the listing's superellipse share their axes."""
    lp = np.asarray(fj.BOOK["lightPos"][:3])
    rx, left = fj.rotation(lp)[0], scene.luminaire.frame()[0]
    u = unit(lp)
    theta = math.atan2(float(u @ np.cross(left, rx)), float(left @ rx))
    return axis_rotation(u, -theta)


def barndoor_book(s: Settings, gl_ok: bool) -> dict[str, Any]:
    """Fore June's listing (Figure 20-17's values) against a physical barn door of the same beam: a disc of radius
    r_d behind a superellipse hole (roundness d = 0.8) at depth h whose edge centres are the book's
    (a + A)/2, (b + B)/2 in tan space and whose penumbra 2 r_d (1 − h/Z)/h is the book's A − a at the sphere's
    nearest depth Z (uberlight_scenes)."""
    c, r = np.asarray(us.SPHERE["center"], dtype=np.float64), float(us.SPHERE["radius"])
    u0 = fj.BOOK
    lp = np.asarray(u0["lightPos"][:3])
    h, z = s.barndoor_depth, r * (float(np.linalg.norm(lp)) - 1.0)
    rd = h * (u0["A"] - u0["a"]) / 2.0 / (1.0 - h / z)
    lum = us.Luminaire("barndoor", position=tuple(c + r * lp), target=tuple(c), radius=rd, depth=h,
                       aperture=(h * (u0["a"] + u0["A"]) / 2.0, h * (u0["b"] + u0["B"]) / 2.0),
                       radiance=INTENSITY / (math.pi * rd * rd), aperture_roundness=u0["d"])
    scene = us.UberScene(lum, us.Camera(width=s.projector_size[0], height=s.projector_size[1]), True,
                         "listings_forejune_barndoor")
    ref = ur.render(scene, None, s.barndoor_spp, s.barndoor_passes, s.seed)
    on = ref.valid & (np.abs(np.linalg.norm(ref.position - c, axis=-1) - r) < 1e-3 * r)
    qm = listing_world(scene)
    q = (ref.position[on] - c) @ qm.T / r
    u = dict(u0, eyePos=(*((np.asarray(scene.camera.origin) - c) @ qm.T / r), 1.0))
    rgb = (fj.glsl(q, u) if gl_ok else fj.python(q, u))[:, :3].astype(np.float64)
    t = fj.terms(q, u)
    dist = np.linalg.norm(q - lp, axis=1)
    cos = np.maximum(np.sum(unit(q) * unit(lp - q), axis=1), 0.0)
    shape = fj.super_ellipse_shape((q - lp) @ fj.rotation(lp).T, u)
    unit_map = ref.albedo[on] / math.pi * INTENSITY / r ** 2
    rad, unc = ref.radiance[on], ref.uncertainty[on]
    peak = float(rad.max())
    models = {"as printed (GLSL)" if gl_ok else "as printed (Python transcription)": luminance(rgb),
              "light term only (diffuse: shape × zones × falloff × n·l)": t["diffuse"],
              "the listing's shape × n·l / d² (edge shape only)": shape * cos / dist ** 2}
    return {"pixels": int(on.sum()), "peak": peak, "disc_radius": rd, "depth": h, "aperture": list(lum.aperture),
            "spp": s.barndoor_spp, "passes": s.barndoor_passes,
            "models": {k: _errors(unit_map * v, rad, unc, peak) for k, v in models.items()}}


def orange_comparison(s: Settings, gl_ok: bool) -> dict[str, Any]:
    scene = us.projector_scene(s.projector_size[0], s.projector_size[1], s.fov_deg)
    x, y = ur.texel_directions(s.texture, s.fov_deg)
    ref = _projector_ref(scene, superellipse_shape_np(PROJECTOR_SHAPE, x, y, np.ones_like(x)), s)
    v = ref.valid
    pos, nrm, alb = ref.position[v], ref.normal[v], ref.albedo[v]
    views = unit(np.asarray(scene.camera.origin) - pos)
    vis = ur.visibility(scene, pos, nrm)
    lum = scene.luminaire
    light = {"position": np.asarray(lum.position), "axes": lum.frame(), "intensity": INTENSITY, **NO_DISTANCE_SHAPING,
             **PROJECTOR_SHAPE}
    mat = {"albedo": alb, "ks": 0.0}
    listing = (ou.glsl if gl_ok else ou.python)(light, pos, nrm, views, mat) * vis
    d2 = np.sum((pos - lum.position) ** 2, axis=1)
    rad, unc = ref.radiance[v], ref.uncertainty[v]
    peak = float(rad.max())
    return {"pixels": int(v.sum()), "peak": peak, "runs": "GLSL" if gl_ok else "Python transcription",
            "models": {"as printed (no falloff)": _errors(listing, rad, unc, peak),
                       "× 1/d² (corrected)": _errors(listing / d2, rad, unc, peak)}}


# -- closed forms --------------------------------------------------------------------------------------------
def hemisphere_fraction() -> dict[str, Any]:
    theta = np.linspace(0.0, math.pi, 18001)
    printed = np.where(theta <= math.pi / 2, 1.0 - 0.5 * np.sin(theta), 0.5 * np.sin(theta))
    exact = 0.5 * (1.0 + np.cos(theta))
    diff = np.abs(printed - exact)
    i = int(np.argmax(diff))
    return {"max_abs": float(diff.max()), "at_deg": float(np.degrees(theta[i])),
            "area_printed": float(np.trapezoid(printed, theta)), "area_exact": float(np.trapezoid(exact, theta))}


def redbook_values() -> dict[str, Any]:
    dirs, w = bs.hemisphere_quadrature(256, 64)
    n = np.tile([0.0, 0.0, 1.0], (len(dirs), 1))
    v = np.tile([0.0, 0.0, 1.0], (len(dirs), 1))
    params = {"albedo": 1.0, "ks": 10.0, "exponent": 20.0}
    q = family("brdf").call("blinn_phong", params, n, dirs, v)[:, 0]
    spec = family("brdf").call("blinn_phong", dict(params, albedo=0.0), n, dirs, v)[:, 0]
    return {"albedo_normal": float(np.sum(w * q)), "specular_albedo_normal": float(np.sum(w * spec)),
            "shininess": 20.0, "strength": 10.0}


def compute(ctx: Context, s: Settings) -> Measurements:
    ok, why = gl_status()
    m = Measurements(s, {"available": ok, ("renderer" if ok else "reason"): why, "skipped": list(GL_SKIPPED)})
    if ok:
        m.transcription = transcription_checks(s)
    m.cook_torrance = cook_torrance_readings(s)
    m.point = point_comparison(s, ok)
    m.falloff = falloff_comparison(s)
    m.uberlight_book = uberlight_book(s, ok)
    m.barndoor_book = barndoor_book(s, ok)
    m.orange = orange_comparison(s, ok)
    m.hemisphere = hemisphere_fraction()
    m.redbook_values = redbook_values()
    return m


__all__ = ["Measurements", "compute"]
