"""Numbers of the ``brdfs`` experiment: every ``brdf`` technique against Mitsuba BSDFs and the V-groove surface.

Metrics (luminance Y of the (N, 3) cosine-weighted BRDF q = f_r·cos θ_l; the reference q_ref):

* ``rel_l1.<material>`` = ∫∫ |q − q_ref| cos θ_v dω_l dω_v / ∫∫ q_ref cos θ_v dω_l dω_v — the error in the
  light reflected under uniform illumination from every direction, relative to that light. Mitsuba
  materials: Gauss–Legendre (cos θ_l, cos θ_v) × uniform Δφ grid (:func:`~validate.scenes.brdf_scenes.brdf_grid`);
  uncertainty = |value(n) − value(n/2)| (quadrature). V-groove materials: the configurations of the settings
  with equal weights; uncertainty Σ se/Σ q_ref (an upper bound on what the Monte Carlo noise can shift).
* ``max_rel.<material>`` (Mitsuba materials) = max |q − q_ref|/q_ref over grid points where q_ref > 10⁻³
  max q_ref; uncertainty 10⁻⁵ (Mitsuba's float32 evaluation: ≈ 50 operations × 2⁻²⁴).
* ``gouraud_rel_l1.l3`` / ``fragment_rel_l1.l3``: Σ_pixels |Y − Y_exact| / Σ Y_exact of the sphere tessellated
  as an icosphere of level 3 (1280 triangles), shaded per vertex and interpolated (Gouraud) or with the
  interpolated, renormalised normal per pixel (per-fragment), against the same technique evaluated with the
  smooth sphere's exact normal at each pixel (orthographic view from +z, directional light; pixels where the
  tessellated sphere is hit). Deterministic: uncertainty 0.
* ``env_rel_l1.<material>``: a unit sphere under the ``two_tone`` environment (sky above, ground below),
  Σ_pixels |Y − Y_Mitsuba| / Σ Y_Mitsuba, with Y the technique integrated over the hemisphere of each pixel's normal
  (Gauss–Legendre in cos θ × uniform φ, the map looked up bilinearly as Mitsuba's envmap does) and Y_Mitsuba the
  path-traced sphere with the material's BSDF (:func:`validate.reference.ibl_render.render`, 4 passes);
  ± = Σ se_Y / Σ Y + |value(n nodes) − value(n/2 nodes)|.
* ``plane_rel_l1.<material>``: a plane under a point light (height 1 above the origin, unit intensity) seen by an
  orthographic viewer 70° from the normal, over the 7 × 7 square of the plane centred at (−2.5, 0) (the mirror
  point is at x = −2.75): Σ|Y − Y_Mitsuba| / Σ Y_Mitsuba of L_o = I/d² · q(l(p), v), Mitsuba's BSDF.eval as the
  reference (± 10⁻⁵, float32).
* ``albedo_error.<material>`` (Mitsuba materials) = max over view angles θ_v of |W − W_ref|, where the
  white-furnace albedo W(v) = ∫ q(l, v) dω_l is the radiance seen under a unit white sky; both by the same
  quadrature (:func:`~validate.scenes.brdf_scenes.hemisphere_quadrature`); uncertainty |Δ| between n and n/2.

Power (every metric): the technique's output × 1.02, a 2 % bias (``Measured.perturbed``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache, partial
from typing import Any

import numpy as np

from ...backend import drjit_threads
from ...local_models import family
from ...local_models.brdf.common import (
    Geometry,
    cook_torrance_printed_terms,
    fresnel_exact,
    fresnel_schlick,
    frozen_copy,
    oren_nayar_full_terms,
)
from ...local_models.registry import Technique
from ...reference import brdf_render as br
from ...reference.ibl_render import register_phong_bsdf
from ...scenes import brdf_scenes as bs
from ...scenes import latlong, procedural
from ...scenes.latlong import luminance
from ..base import Context
from .settings import Settings

BIAS = 1.02
POWER_TEXT = "technique output × 1.02 (a 2 % bias)"
MASK_FRACTION = 1e-3
FLOAT32_UNCERTAINTY = 1e-5


def materials(s: Settings) -> list[bs.Material]:
    """The Mitsuba materials: coloured and mirror Beckmann conductors, GGX, a dielectric interface, diffuse,
    the modified-Phong BSDF."""
    plugin = register_phong_bsdf()
    out = [bs.conductor(a) for a in s.alphas] + [bs.conductor(a, "ggx") for a in s.ggx_alphas]
    out.append(bs.conductor(0.2, coloured=False))
    out.append(bs.dielectric_interface(0.3))
    out.append(bs.diffuse(s.albedo))
    out += [bs.modified_phong(p, plugin) for p in s.phong_exponents]
    return out


@dataclass
class Measurements:
    settings: Settings
    techniques: list[Technique]
    materials: list[str] = field(default_factory=list)
    # metrics[tech][metric] = {"value", "uncertainty", "perturbed"}
    metrics: dict[str, dict[str, dict[str, float]]] = field(default_factory=dict)
    furnace: dict[str, Any] = field(default_factory=dict)  # furnace[material][tech or "mitsuba"] = [W per view]
    sweep: dict[str, Any] = field(default_factory=dict)
    terms: dict[str, Any] = field(default_factory=dict)
    vgroove: dict[str, Any] = field(default_factory=dict)
    images: dict[str, Any] = field(default_factory=dict)
    gouraud: dict[str, Any] = field(default_factory=dict)
    env: dict[str, Any] = field(default_factory=dict)
    plane: dict[str, Any] = field(default_factory=dict)


@lru_cache(maxsize=16)
def _normals(n: int) -> np.ndarray:
    """(n, 3) copies of the local frame's normal +z, read-only (memoised by n: every grid, furnace and V-groove call
    of a size shares one)."""
    out = np.tile(np.array([0.0, 0.0, 1.0]), (n, 1))
    out.setflags(write=False)
    return out


def call(tech: Technique | str, params: dict[str, Any], lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    """A technique through the registry (contract checked), local frame."""
    return family("brdf").call(tech, params, _normals(len(lights)), lights, views)


def rel_l1(q: np.ndarray, ref: np.ndarray, w: np.ndarray) -> float:
    """Σ w |Y(q) − Y(ref)| / Σ w Y(ref)."""
    return float(np.sum(w * np.abs(luminance(q) - luminance(ref))) / np.sum(w * luminance(ref)))


def max_rel(q: np.ndarray, ref: np.ndarray) -> float:
    """max |q − ref|/ref over channels and points where ref > 10⁻³ max ref."""
    mask = ref > MASK_FRACTION * ref.max()
    return float(np.max(np.abs(q[mask] - ref[mask]) / ref[mask]))


def _entry(value: float, unc: float, perturbed: float) -> dict[str, float]:
    return {"value": float(value), "uncertainty": float(unc), "perturbed": float(perturbed)}


def grid_metrics(m: Measurements, mat: bs.Material) -> None:
    """rel_l1 and max_rel of every technique for one Mitsuba material (grid n and n/2; every technique on one grid,
    then on the other: the frozen grid arrays shared by consecutive calls)."""
    grids = [bs.brdf_grid(m.settings.grid, m.settings.grid), bs.brdf_grid(m.settings.grid // 2, m.settings.grid // 2)]
    grids = [(frozen_copy(g[0]), frozen_copy(g[1]), g[2]) for g in grids]
    refs = [br.eval_bsdf(mat.bsdf, g[0], g[1]) for g in grids]
    per_grid = [{tech.name: call(tech, mat.params, g[0], g[1]) for tech in m.techniques} for g in grids]
    for tech in m.techniques:
        q = [x[tech.name] for x in per_grid]
        e = [rel_l1(qq, r, g[2]) for qq, r, g in zip(q, refs, grids, strict=True)]
        mx = max_rel(q[0], refs[0])
        d = m.metrics.setdefault(tech.name, {})
        d[f"rel_l1.{mat.name}"] = _entry(e[0], abs(e[0] - e[1]), rel_l1(BIAS * q[0], refs[0], grids[0][2]))
        d[f"max_rel.{mat.name}"] = _entry(mx, FLOAT32_UNCERTAINTY, max_rel(BIAS * q[0], refs[0]))


def furnace_albedo(fn: Any, views_deg: tuple[float, ...], nodes: tuple[int, int]) -> np.ndarray:
    """W(θ_v) = ∫ Y(q(l, v)) dω_l for each view angle (luminance), with ``fn(lights, views) -> q``: one call over
    every view (the quadrature tiled; q is per sample, so each view's block is what a call of its own returns —
    fewer, larger calls: each has a fixed cost, a GL listing's draw and read-back), each view's sum over its own
    block as before."""
    return furnace_albedo_many({"": fn}, views_deg, nodes)[""]


def furnace_albedo_many(fns: dict[str, Any], views_deg: tuple[float, ...],
                        nodes: tuple[int, int]) -> dict[str, np.ndarray]:
    """:func:`furnace_albedo` of every ``fns[name]``, one after another on the same (frozen) lights and views."""
    dirs, w = bs.hemisphere_quadrature(*nodes)
    views = frozen_copy(np.concatenate([np.tile(bs.direction(np.radians(t), 0.0), (len(dirs), 1))
                                         for t in views_deg]))
    lights = frozen_copy(np.tile(dirs, (len(views_deg), 1)))
    k = len(dirs)
    out = {}
    for name, fn in fns.items():
        q = fn(lights, views)
        out[name] = np.asarray([float(np.sum(w * luminance(q[i * k:(i + 1) * k]))) for i in range(len(views_deg))])
    return out


def furnace_metrics(m: Measurements, mat: bs.Material) -> None:
    """White-furnace albedo of Mitsuba and every technique at the material's parameters; albedo_error."""
    s = m.settings
    half = (s.furnace[0] // 2, s.furnace[1] // 2)
    ref = [furnace_albedo(lambda lt, vw: br.eval_bsdf(mat.bsdf, lt, vw), s.furnace_views_deg, n)
           for n in (s.furnace, half)]
    entry: dict[str, Any] = {"mitsuba": ref[0].tolist()}
    fns = {tech.name: partial(call, tech, mat.params) for tech in m.techniques}
    both = [furnace_albedo_many(fns, s.furnace_views_deg, n) for n in (s.furnace, half)]
    for tech in m.techniques:
        w = [x[tech.name] for x in both]
        entry[tech.name] = w[0].tolist()
        err, err_half = np.max(np.abs(w[0] - ref[0])), np.max(np.abs(w[1] - ref[1]))
        m.metrics[tech.name][f"albedo_error.{mat.name}"] = _entry(err, abs(err - err_half),
                                                                  np.max(np.abs(BIAS * w[0] - ref[0])))
    m.furnace[mat.name] = entry


def energy_sweep(m: Measurements) -> None:
    """Albedo at normal incidence and at 60° vs roughness (mirror F = 1, k_s = 1): every technique and
    Mitsuba's roughconductor (Beckmann) at the Walter-equivalent α."""
    s = m.settings
    views = (0.0, 60.0)
    out: dict[str, Any] = {"alpha": list(s.sweep_alphas),
                           "blinn_exponent": [bs.blinn_exponent(a) for a in s.sweep_alphas],
                           "views_deg": list(views), "mitsuba": [], "techniques": {t.name: [] for t in m.techniques}}
    for a in s.sweep_alphas:
        mat = bs.conductor(a, coloured=False)
        params = {**mat.params, "ks": 1.0}
        out["mitsuba"].append(furnace_albedo(lambda lt, vw, b=mat.bsdf: br.eval_bsdf(b, lt, vw), views,
                                             s.furnace).tolist())
        per = furnace_albedo_many({t.name: partial(call, t, params) for t in m.techniques}, views, s.furnace)
        for tech in m.techniques:
            out["techniques"][tech.name].append(per[tech.name].tolist())
    m.sweep = out


# Term-by-term path from the corrected microfacet BRDF to Ganovelli's printed Cook–Torrance
TERM_STEPS: tuple[tuple[str, dict[str, str]], ...] = (
    ("corrected: exact F(v·h), Smith G, 4(n·l)(n·v)",
     {"fresnel": "exact", "geometry": "smith", "denominator": "walter"}),
    ("+ Schlick F(v·h)", {"fresnel": "schlick_vh", "geometry": "smith", "denominator": "walter"}),
    ("+ Schlick F(n·l) (as printed)", {"fresnel": "schlick_nl", "geometry": "smith", "denominator": "walter"}),
    ("+ V-cavity G", {"fresnel": "schlick_nl", "geometry": "vcavity", "denominator": "walter"}),
    ("+ no 4 in the denominator = as printed", {"fresnel": "schlick_nl", "geometry": "vcavity",
                                                "denominator": "printed"}),
)


def term_analysis(m: Measurements, mats: list[bs.Material]) -> None:
    """rel_l1 and reflected-energy ratio vs Mitsuba of each step of :data:`TERM_STEPS` (Beckmann materials), and
    the Fresnel terms alone on the dielectric material: weighted error of Schlick(n·l) and Schlick(v·h) against
    the exact F(v·h)."""
    lights, views, w = bs.brdf_grid(m.settings.grid, m.settings.grid)
    g = Geometry(_normals(len(lights)), lights, views)
    out: dict[str, Any] = {"steps": [s for s, _ in TERM_STEPS], "materials": {}}
    for mat in mats:
        if mat.params.get("distribution") != "beckmann" or "alpha" not in mat.bsdf:
            continue
        ref = br.eval_bsdf(mat.bsdf, lights, views)
        rows = []
        for _, kw in TERM_STEPS:
            q = cook_torrance_printed_terms(mat.params, g, **kw) * g.front[:, None]
            rows.append({"rel_l1": rel_l1(q, ref, w),
                         "energy_ratio": float(np.sum(w * luminance(q)) / np.sum(w * luminance(ref)))})
        out["materials"][mat.name] = rows
    diel = next((x for x in mats if x.name.startswith("dielectric")), None)
    if diel is not None:
        f0 = bs.specular_params(0.3, "beckmann", diel.params["eta"], 0.0)["ks"]
        exact = fresnel_exact(g.vh, diel.params["eta"], 0.0)[:, 0]
        lobe = luminance(br.eval_bsdf(diel.bsdf, lights, views)) * w
        for name, fx in (("schlick_nl", fresnel_schlick(g.cl, np.asarray(f0))[:, 0]),
                         ("schlick_vh", fresnel_schlick(g.vh, np.asarray(f0))[:, 0])):
            rel = np.abs(fx - exact) / exact
            out[f"fresnel_{name}"] = {"lobe_weighted_rel": float(np.sum(lobe * rel) / lobe.sum()),
                                      "max_rel": float(np.max(np.abs(fx - exact)[g.front] / exact[g.front]))}
    m.terms = out


def vgroove_metrics(m: Measurements, ctx_seed: int) -> None:
    """Every technique against the path-traced V-groove surface at each σ (luminance = the grey value)."""
    s = m.settings
    lights, views = bs.vgroove_configurations(list(s.thetas_deg), list(s.dphis_deg))
    out: dict[str, Any] = {"configs": {"lights": lights.tolist(), "views": views.tolist()}, "sigmas": {}}
    for sd in s.sigmas_deg:
        mat = bs.vgroove_material(sd, s.albedo)
        r = br.vgroove_brdf(np.radians(sd), lights, views, s.albedo, s.n_slope, s.n_orient, s.paths, s.depth,
                            ctx_seed + int(10 * sd))
        ref, se = r["value"], r["stderr"]
        unc = float(np.sum(se) / np.sum(ref))
        per: dict[str, Any] = {"reference": ref.tolist(), "stderr": se.tolist(), "techniques": {}}
        for tech in m.techniques:
            q = luminance(call(tech, mat.params, lights, views))
            e = float(np.sum(np.abs(q - ref)) / np.sum(ref))
            ep = float(np.sum(np.abs(BIAS * q - ref)) / np.sum(ref))
            m.metrics.setdefault(tech.name, {})[f"rel_l1.{mat.name}"] = _entry(e, unc, ep)
            per["techniques"][tech.name] = q.tolist()
        per["minnaert_fit"] = minnaert_fit(mat.params, lights, views, ref, s.minnaert_ks)
        per["on_terms"] = on_terms(mat.params, lights, views, ref)
        out["sigmas"][mat.name] = {"sigma_deg": sd, **per, "rel_uncertainty": unc}
    m.vgroove = out


def minnaert_fit(params: dict[str, Any], lights: np.ndarray, views: np.ndarray, ref: np.ndarray,
                 ks: tuple[float, ...]) -> dict[str, Any]:
    """Minnaert's K minimising the V-groove rel_l1 (grid search), with the albedo as given."""
    if "minnaert" not in family("brdf"):
        return {}
    errs = [float(np.sum(np.abs(luminance(call("minnaert", {**params, "minnaert_k": k}, lights, views)) - ref))
                  / np.sum(ref)) for k in ks]
    i = int(np.argmin(errs))
    return {"k": list(ks), "rel_l1": errs, "best_k": float(ks[i]), "best_rel_l1": errs[i]}


def on_terms(params: dict[str, Any], lights: np.ndarray, views: np.ndarray, ref: np.ndarray) -> dict[str, float]:
    """The full Oren–Nayar model without its inter-reflection term L₂ (power check of the ON claim), and the share
    of L₂ in the full model's light (Σ L₂ / Σ (L₁ + L₂))."""
    g = Geometry(_normals(len(lights)), lights, views)
    l1, l2 = oren_nayar_full_terms(float(params["sigma"]), np.asarray(params["albedo"], dtype=np.float64), g)
    l1, l2 = (luminance(np.broadcast_to(x * g.front[:, None], (len(lights), 3))) for x in (l1, l2))
    return {"no_l2_rel_l1": float(np.sum(np.abs(l1 - ref)) / np.sum(ref)),
            "l2_share": float(np.sum(l2) / np.sum(l1 + l2))}


def sphere_images(m: Measurements, mat: bs.Material, light_dir: tuple[float, float, float]) -> dict[str, np.ndarray]:
    """An orthographic view (from +z) of a unit sphere under a directional light of unit perpendicular
    irradiance: per pixel q(l, v) from Mitsuba and from every technique (direct light on a convex object is
    exactly the BRDF evaluation; no inter-reflection, no occlusion)."""
    n = m.settings.image
    c = (np.arange(n) + 0.5) / n * 2.0 - 1.0
    x, y = np.meshgrid(c, -c)
    inside = x * x + y * y < 1.0
    nrm = np.stack([x, y, np.sqrt(np.maximum(1.0 - x * x - y * y, 0.0))], -1)[inside]
    l = np.asarray(light_dir, dtype=np.float64) / np.linalg.norm(light_dir)
    lw, vw = np.tile(l, (len(nrm), 1)), np.tile([0.0, 0.0, 1.0], (len(nrm), 1))
    t = np.cross(nrm, np.array([0.0, 1.0, 0.0]))
    t = np.where(np.linalg.norm(t, axis=-1, keepdims=True) < 1e-6, np.array([1.0, 0.0, 0.0]), t)
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    b = np.cross(nrm, t)

    def local(d: np.ndarray) -> np.ndarray:
        return np.stack([np.sum(d * t, -1), np.sum(d * b, -1), np.sum(d * nrm, -1)], -1)

    def paint(q: np.ndarray) -> np.ndarray:
        img = np.zeros((n, n, 3))
        img[inside] = q
        return img

    out = {"mitsuba": paint(br.eval_bsdf(mat.bsdf, local(lw), local(vw)))}
    for tech in m.techniques:
        out[tech.name] = paint(family("brdf").call(tech, mat.params, nrm, lw, vw))
    return out


# Gouraud vs per-fragment shading on a tessellated sphere
GOURAUD_LEVEL = 3  # the tessellation whose errors go into every technique's metrics (1280 triangles)


def gouraud_params() -> dict[str, Any]:
    """A mixed material so that every technique lights the sphere: ρ = 0.3, k_s = 0.7, modified-Phong s = 20
    (Blinn 80, α by Walter's mapping), F = 1, σ = 0.3 rad, Minnaert K = 0.8."""
    alpha = bs.alpha_from_blinn(80.0)
    return {**bs.specular_params(alpha, "beckmann", 0.0, 1.0), "albedo": 0.3, "ks": 0.7, "phong_exponent": 20.0,
            "exponent": 80.0, "sigma": 0.3, "minnaert_k": 0.8}


@lru_cache(maxsize=8)
def _tessellated_gbuffer(level: int, size: int) -> tuple[np.ndarray, ...]:
    """(vertices, faces, exact normals, hit triangles' vertex indices, barycentrics) of the level-``level``
    icosphere seen in ``size``² pixels: the same for every technique and exponent, so built and traced once (the
    arrays are read-only)."""
    verts, faces = bs.icosphere(level)
    x, y, inside = bs.sphere_pixels(size)
    hit, prim, bary = br.mesh_gbuffer(verts, faces, x, y)
    hit &= inside.ravel()
    xs, ys = x.ravel()[hit], y.ravel()[hit]
    exact_n = np.stack([xs, ys, np.sqrt(np.maximum(1.0 - xs * xs - ys * ys, 0.0))], -1)
    out = (verts, faces, exact_n, faces[prim[hit]], bary[hit])
    for a in out:
        a.setflags(write=False)
    return out


@lru_cache(maxsize=8)
def _shading_normals(level: int, size: int) -> tuple[np.ndarray, np.ndarray]:
    """(interpolated renormalised normals, flat face normals) at the hit pixels of :func:`_tessellated_gbuffer`:
    they depend on the tessellation only, so are formed once for every technique and exponent (read-only)."""
    verts, _, _, tri, w = _tessellated_gbuffer(level, size)
    interp_n = np.sum(w[..., None] * verts[tri], axis=1)
    face_n = np.cross(verts[tri[:, 1]] - verts[tri[:, 0]], verts[tri[:, 2]] - verts[tri[:, 0]])
    face_n *= np.sign(np.sum(face_n * verts[tri[:, 0]], axis=-1, keepdims=True))
    out = (interp_n / np.linalg.norm(interp_n, axis=-1, keepdims=True),
           face_n / np.linalg.norm(face_n, axis=-1, keepdims=True))
    for a in out:
        a.setflags(write=False)
    return out


def _shade(fn: Any, light: np.ndarray, level: int, size: int) -> dict[str, np.ndarray]:
    """Per-pixel exact (smooth sphere), Gouraud and per-fragment values (luminance) of ``fn(normals, l, v)``
    over the pixels where the tessellated sphere is hit."""
    verts, faces, exact_n, tri, w = _tessellated_gbuffer(level, size)
    fragment_n, flat_n = _shading_normals(level, size)
    view = np.array([0.0, 0.0, 1.0])

    def run(n: np.ndarray) -> np.ndarray:
        return luminance(fn(n, np.tile(light, (len(n), 1)), np.tile(view, (len(n), 1))))

    vert_c = run(verts)
    return {"exact": run(exact_n), "gouraud": np.sum(w * vert_c[tri], axis=1), "fragment": run(fragment_n),
            "flat": run(flat_n), "exact_n": exact_n}


def _err(img: np.ndarray, ref: np.ndarray) -> float:
    return float(np.sum(np.abs(img - ref)) / np.sum(ref))


def gouraud_analysis(m: Measurements, light: tuple[float, float, float]) -> None:
    """(1) every technique: Gouraud and per-fragment error vs its own smooth-sphere shading, per tessellation;
    (2) the modified Phong vs Mitsuba's modphong render of the smooth sphere, per exponent and tessellation."""
    s = m.settings
    ldir = np.asarray(light, dtype=np.float64) / np.linalg.norm(light)
    params = gouraud_params()
    triangles = [20 * 4 ** lv for lv in s.gouraud_levels]
    out: dict[str, Any] = {"levels": list(s.gouraud_levels), "triangles": triangles, "techniques": {},
                           "exponents": {}}
    for tech in m.techniques:
        rows = {"gouraud": [], "fragment": []}
        for lv in s.gouraud_levels:
            r = _shade(lambda n, lt, vw, t=tech: family("brdf").call(t, params, n, lt, vw), ldir, lv, s.gouraud_image)
            for kind in rows:
                rows[kind].append(_err(r[kind], r["exact"]))
            if lv == GOURAUD_LEVEL:
                for kind in rows:
                    e, ep = _err(r[kind], r["exact"]), _err(BIAS * r[kind], r["exact"])
                    m.metrics.setdefault(tech.name, {})[f"{kind}_rel_l1.l{lv}"] = _entry(e, 0.0, ep)
        out["techniques"][tech.name] = rows
    plugin = register_phong_bsdf()
    for sp in s.gouraud_exponents:
        bsdf = {"type": plugin, "exponent": sp, "reflectance": 1.0}
        p = {"albedo": 0.0, "ks": 1.0, "phong_exponent": sp}
        rows = {"gouraud": [], "fragment": [], "flat": []}
        for lv in s.gouraud_levels:
            r = _shade(lambda n, lt, vw, p=p: call_world("phong_normalized", p, n, lt, vw), ldir, lv, s.gouraud_image)
            ref = luminance(br.eval_bsdf_world(bsdf, r["exact_n"], np.tile(ldir, (len(r["exact_n"]), 1)),
                                               np.tile([0.0, 0.0, 1.0], (len(r["exact_n"]), 1))))
            for kind in rows:
                rows[kind].append(_err(r[kind], ref))
        out["exponents"][f"{sp:g}"] = rows
    m.gouraud = out


def call_world(tech: str, params: dict[str, Any], normals: np.ndarray, lights: np.ndarray,
               views: np.ndarray) -> np.ndarray:
    """A technique through the registry with world-space normals; zeros when it is not registered."""
    if tech not in family("brdf"):
        return np.zeros((len(normals), 3))
    return family("brdf").call(tech, params, normals, lights, views)


# Spheres under an environment
ENV_MATERIALS = ("conductor_beckmann_a0.5", "diffuse_r0.8")
ENV_CHUNK = 1 << 17  # (pixel, direction) pairs per technique call


def _frames(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    a = np.where(np.abs(n[:, 1:2]) > 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
    t = np.cross(n, a)
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    return t, np.cross(n, t)


def env_radiance_local(fn: Any, radiance: np.ndarray, normals: np.ndarray, views: np.ndarray,
                       nodes: int) -> np.ndarray:
    """L_o(n, v) = Σ_m w_m L(ω_m) q(ω_m, v; n) over a Gauss–Legendre (cos θ) × uniform φ grid of ``nodes`` × 2·nodes
    directions on the hemisphere about each normal, L by Mitsuba's bilinear envmap lookup; (P, 3)."""
    return env_radiance_many({"": fn}, radiance, normals, views, nodes)[""]


def env_radiance_many(fns: dict[str, Any], radiance: np.ndarray, normals: np.ndarray, views: np.ndarray,
                      nodes: int) -> dict[str, np.ndarray]:
    """:func:`env_radiance_local` of every ``fns[name]`` at once: each chunk's directions and map lookups are made
    once and shared by the techniques (they depend on the normals only), the sums as in the single form.

    A chunk's (pixel, direction) pairs are laid out direction-major (row j·k + i = direction j of pixel i): the
    techniques are evaluated per pair, so each pair's q is the same number in any order, and the sum over the
    directions is then numpy's reduction over the leading axis of a C-contiguous (m, k, 3) array, which adds the
    rows one after the other in order j = 0, 1, …, m − 1 — the same additions, in the same order, as the sum over
    axis 1 of the pixel-major (k, m, 3) form (a reduction over a middle axis is also sequential; there the inner
    loop runs over 3 numbers, here over 3k)."""
    local, w = bs.hemisphere_quadrature(nodes, 2 * nodes)
    t, b = _frames(normals)
    out = {name: np.zeros((len(normals), 3)) for name in fns}
    m = len(local)
    per = max(1, ENV_CHUNK // m)
    for s0 in range(0, len(normals), per):
        sl = slice(s0, s0 + per)
        k = len(normals[sl])
        d_full = (local[:, None, :1] * t[None, sl] + local[:, None, 1:2] * b[None, sl]
                  + local[:, None, 2:3] * normals[None, sl])
        nrep, vrep = np.empty((m, k, 3)), np.empty((m, k, 3))
        nrep[...], vrep[...] = normals[None, sl], views[None, sl]  # row j·k + i: pixel i's normal and view
        # shared by the techniques: none may write into them (frozen with their base, so that the brdf techniques'
        # GeometryDr converts them to drjit once per chunk: common._packed_directions)
        for a in (nrep, d_full, vrep):
            a.setflags(write=False)
        nrep, d, vrep = nrep.reshape(-1, 3), d_full.reshape(-1, 3), vrep.reshape(-1, 3)
        lrad = latlong.bilinear_lookup(radiance, d).reshape(m, k, 3)
        # w·(q·L) summed over the directions: the products formed into one scratch array per chunk, reused by every
        # technique (no fresh (m, k, 3) temporaries per call)
        scratch = np.empty((m, k, 3))
        for name, fn in fns.items():
            q = fn(nrep, d, vrep)
            np.multiply(q.reshape(m, k, 3), lrad, out=scratch)
            np.multiply(w[:, None, None], scratch, out=scratch)
            out[name][sl] = np.sum(scratch, axis=0)
    return out


def env_analysis(m: Measurements, mats: list[bs.Material], render_threads: int | None = None) -> None:
    """Every technique on a sphere under ``two_tone`` vs Mitsuba's path-traced sphere, per material; the renders
    on ``render_threads`` drjit threads when given (:func:`~validate.backend.drjit_threads`)."""
    from ...reference import ibl_render as ir
    s = m.settings
    env = procedural.two_tone()
    cam = ir.camera_towards(np.array([0.0, 0.3, 1.0]), 0.0, s.env_image)
    out: dict[str, Any] = {}
    env_mats = [x for x in mats if x.name in ENV_MATERIALS]
    with drjit_threads(render_threads):
        renders = {mat.name: ir.render(env, ir.RenderSpec("sphere", mat.bsdf, cam, spp=s.env_spp, passes=4,
                                                          seed=11))
                   for mat in env_mats}

    def pixels(name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        r = renders[name]
        mask = r.mask.reshape(-1)
        return mask, r.normal.reshape(-1, 3)[mask], r.view.reshape(-1, 3)[mask]

    # The materials' spheres share the camera and the shape, so their pixels (mask, normals, views) are the same
    # arrays: their directions and map lookups are then made once for both (env_radiance_many), every sum as
    # in a pass of its own; a material whose pixels differ gets a pass of its own.
    groups: list[list[bs.Material]] = []
    for mat in env_mats:
        g = next((g for g in groups if all(np.array_equal(a, b) for a, b in zip(pixels(g[0].name), pixels(mat.name),
                                                                                   strict=True))), None)
        if g is None:
            groups.append([mat])
        else:
            g.append(mat)
    per_nodes: dict[str, list[dict[str, np.ndarray]]] = {}
    for g in groups:
        _, n, v = pixels(g[0].name)
        fns = {f"{mat.name}\0{t.name}": partial(family("brdf").call, t, mat.params) for mat in g for t in m.techniques}
        both = [env_radiance_many(fns, env.radiance, n, v, k) for k in (s.env_nodes, s.env_nodes // 2)]
        for mat in g:
            per_nodes[mat.name] = [{t.name: x[f"{mat.name}\0{t.name}"] for t in m.techniques} for x in both]
    for mat in env_mats:
        r = renders[mat.name]
        mask, _, _ = pixels(mat.name)
        ref = luminance(r.mean.reshape(-1, 3)[mask])
        noise = float(np.sum(r.stderr_y.reshape(-1)[mask]) / np.sum(ref))
        images: dict[str, Any] = {"mitsuba": r.mean}
        for tech in m.techniques:
            vals = [x[tech.name] for x in per_nodes[mat.name]]
            e = [_err(luminance(x), ref) for x in vals]
            m.metrics.setdefault(tech.name, {})[f"env_rel_l1.{mat.name}"] = _entry(
                e[0], noise + abs(e[0] - e[1]), _err(BIAS * luminance(vals[0]), ref))
            img = np.full((s.env_image * s.env_image, 3), np.nan)
            img[mask] = vals[0]
            images[tech.name] = img.reshape(s.env_image, s.env_image, 3)
        out[mat.name] = {"images": images, "reference_noise": noise}
    m.env = out


# A plane under a point light (highlight shape)
PLANE_MATERIAL = "mirror_beckmann_a0.2"
PLANE_VIEW_DEG = 70.0
PLANE_HALF = 3.5
PLANE_CENTRE = 2.5  # the window is centred at x = −2.5 (the mirror point is at x = −tan 70° = −2.75)
PROFILE_REACH = 40.0  # half-length of the 1-D profiles through the peak (plane units; light height 1)
PROFILE_SAMPLES = 8001


def _plane_geometry(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(lights (P, 3), views (P, 3), squared distances (P,)) for points on the plane z = 0, light at (0, 0, 1)."""
    to_light = np.array([0.0, 0.0, 1.0]) - points
    d2 = np.sum(to_light * to_light, -1)
    views = np.tile(bs.direction(np.radians(PLANE_VIEW_DEG), np.pi), (len(points), 1))
    return to_light / np.sqrt(d2)[:, None], views, d2


def highlight_elongation(fn: Any, peak: np.ndarray) -> float:
    """Width at half maximum of the highlight along the view's azimuth (x) over its width across it (y), from 1-D
    profiles of Y(p) = ``fn(points)`` through ``peak`` (±PROFILE_REACH, PROFILE_SAMPLES samples): 1 = round."""
    t = np.linspace(-PROFILE_REACH, PROFILE_REACH, PROFILE_SAMPLES)
    widths = []
    for axis in (0, 1):
        pts = np.tile(np.array([peak[0], peak[1], 0.0]), (len(t), 1))
        pts[:, axis] += t
        y = fn(pts)
        widths.append(float(np.sum(y >= 0.5 * y.max()) * (t[1] - t[0])))
    return widths[0] / widths[1]


def plane_analysis(m: Measurements, mats: list[bs.Material]) -> None:
    """Every technique on a plane under a point light vs Mitsuba's BSDF at the same (l, v): images, rel_l1 and
    the highlight's elongation (x/y widths at half maximum)."""
    mat = next((x for x in mats if x.name == PLANE_MATERIAL), None)
    if mat is None:
        return
    size = m.settings.image
    c = (np.arange(size) + 0.5) / size * 2.0 * PLANE_HALF - PLANE_HALF
    px, py = np.meshgrid(c - PLANE_CENTRE, -c)
    p = np.stack([px.ravel(), py.ravel(), np.zeros(px.size)], -1)
    lights, views, d2 = _plane_geometry(p)

    def shade(f: Any) -> Any:
        return lambda pts: luminance(f(*_plane_geometry(pts)[:2]) / _plane_geometry(pts)[2][:, None])

    def mitsuba(lt: np.ndarray, vw: np.ndarray) -> np.ndarray:
        return br.eval_bsdf(mat.bsdf, lt, vw)

    ref = (mitsuba(lights, views) / d2[:, None]).reshape(size, size, 3)
    out: dict[str, Any] = {"images": {"mitsuba": ref}, "elongation": {}}
    out["elongation"]["mitsuba"] = highlight_elongation(shade(mitsuba), p[int(np.argmax(luminance(ref)))])
    for tech in m.techniques:
        img = (call(tech, mat.params, lights, views) / d2[:, None]).reshape(size, size, 3)
        e = _err(luminance(img), luminance(ref))
        m.metrics.setdefault(tech.name, {})[f"plane_rel_l1.{mat.name}"] = _entry(
            e, FLOAT32_UNCERTAINTY, _err(BIAS * luminance(img), luminance(ref)))
        out["images"][tech.name] = img
        if img.max() > 0:
            fn = shade(lambda lt, vw, t=tech: call(t, mat.params, lt, vw))
            out["elongation"][tech.name] = highlight_elongation(fn, p[int(np.argmax(luminance(img)))])
    m.plane = out



LIGHT_DIR = (0.5, 0.6, 0.62)  # the sphere images' light direction (world, viewer at +z)


def compute(ctx: Context, s: Settings) -> Measurements:
    """Every technique on every Mitsuba material (grid and furnace), the term-by-term Cook–Torrance path,
    the energy sweep, the V-groove surfaces and the sphere images.

    drjit runs on one thread meanwhile (:func:`~validate.backend.drjit_threads`): the kernels here (the techniques,
    Mitsuba's BSDF evaluations and ray queries of the V-groove tracer) are elementwise, each output lane computed by
    the same instructions whatever thread runs it, so the numbers do not depend on the count; on this suite's
    CPU-bound runs (both cores busy with the experiment lanes) a second pool thread adds CPU time (its launches,
    hand-offs and idle waiting: measured, the environment quadrature's techniques 39.6 s of CPU on two threads,
    28.6 s on one, the same arrays) without finishing sooner. Mitsuba's path-traced renders accumulate samples into
    pixels by atomic adds, whose float sums may follow the threads' order, so they keep the process's count
    (:func:`env_analysis`)."""
    import drjit as dr

    threads = dr.thread_count()
    with drjit_threads(1):
        m = Measurements(s, list(family("brdf")))
        mats = materials(s)
        m.materials = [x.name for x in mats]
        for metrics, furnace in ctx.map(partial(_material_metrics, s, m.techniques), mats,
                                        "brdfs: Mitsuba materials"):
            for name, values in metrics.items():  # tasks return their numbers (they may run on Dask workers)
                m.metrics.setdefault(name, {}).update(values)
            m.furnace.update(furnace)
        term_analysis(m, mats)
        energy_sweep(m)
        vgroove_metrics(m, ctx.seed)
        gouraud_analysis(m, LIGHT_DIR)
        env_analysis(m, mats, render_threads=threads)
        plane_analysis(m, mats)
        for mat in mats[:1] + [x for x in mats if x.name.startswith("diffuse")]:
            m.images[mat.name] = sphere_images(m, mat, LIGHT_DIR)
    return m


def _material_metrics(s: Settings, techniques: list[Technique], mat: Any) -> tuple[dict, dict]:
    """One material's grid and furnace metrics of every technique (a task: returns, never mutates; drjit on one
    thread, as in :func:`compute`)."""
    scratch = Measurements(s, techniques)
    with drjit_threads(1):
        grid_metrics(scratch, mat)
        furnace_metrics(scratch, mat)
    return scratch.metrics, scratch.furnace
