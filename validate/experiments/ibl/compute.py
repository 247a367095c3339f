"""Experiment ``ibl``, part 2: the measurements (numbers and images only; no claims, no prose).

* the reference irradiance quadrature at every normal needed (sweep, claim, cube texels, G-buffers);
* the diffuse-map resolution sweep and the SH-vs-convolution comparison;
* every ``irradiance`` technique and the irradiance maps on the rendered Lambertian sphere;
* every ``specular`` technique on every BRDF case it supports, against Mitsuba's renders;
* the mixing shader against ``blendbsdf``; the dented sphere (occlusion).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from functools import partial
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...geometry import cube_texel_directions
from ...local_models import irradiance, specular
from ...local_models.irradiance import irradiance_map as im
from ...local_models.irradiance import sh as shm
from ...local_models.registry import Technique
from ...local_models.specular import prefiltered_specular as ps
from ...metrics import image_error as ie
from ...metrics.flip import FlipResult, flip_hdr
from ...metrics.irradiance_error import irradiance_errors
from ...reference import ibl_render as rr
from ...reference.irradiance import reference_irradiance
from ...scenes import latlong
from ...scenes.environment import Environment
from ...scenes.ibl_scenes import (
    ALBEDO,
    ANGLE_BINS,
    BLEND_EXPONENT,
    BLEND_WEIGHT,
    CAMERA_OFFSET_DEG,
    DENT_CAMERA_OFFSET_DEG,
    PHONG_PLUGIN,
    RENDER_ENV,
    BrdfCase,
    brdf_cases,
    key_direction,
    make_environment,
    random_rotation,
)
from ...stats import t_to_z
from ..base import Background, Context
from . import reference_checks as chk
from .khronos.compute import compute_khronos
from .reference_checks import Chi2Check, ZCheck
from .settings import NAME, Settings


def judged(fam: Any) -> list[Technique]:
    """The family's techniques this experiment judges (:meth:`~validate.local_models.registry.Family.judged_by`:
    every technique plus those registered for ``ibl`` only) that can run here (a technique's ``unavailable``
    callable returns None; the others are this experiment's ``not_run``)."""
    return [t for t in fam.judged_by(NAME) if not (callable(t.meta.get("unavailable")) and t.meta["unavailable"]())]


MAP_MAX_ERROR = 0.01  # the sweep's criterion (see claims.DIFFUSE_MAP_SOURCE)
CRATER_AO = 0.95  # "crater" pixels: cosine-weighted visibility below 0.95


@dataclass
class Scene:
    """The environments, the rendered one, its cameras and the render jobs (name → spec)."""

    envs: dict[str, Environment]
    render_env: Environment
    sphere_cam: rr.Camera
    dent_cam: rr.Camera
    jobs: dict[str, rr.RenderSpec]


def build_scene(st: Settings, seed: int) -> Scene:
    """Cameras 6° off the key light (front sphere) and 60° off it (diffuse and dented spheres); jobs for
    every BRDF case, its normal-incidence crop (Phong), the mixing-shader blend and the dented sphere."""
    envs = {name: make_environment(name, st.env_scale) for name in st.sweep_envs}
    render_env = envs[RENDER_ENV]
    key = key_direction(render_env)
    sphere_cam = rr.camera_towards(key, CAMERA_OFFSET_DEG, st.size)
    dent_cam = rr.camera_towards(key, DENT_CAMERA_OFFSET_DEG, st.size)
    axis = np.asarray(dent_cam.direction) + 0.5 * key
    dent = rr.DentSpec(depth=0.7, width_deg=50.0, axis=tuple(float(x) for x in axis / np.linalg.norm(axis)))

    def spec(shape: str, bsdf: dict, cam: rr.Camera, depth: int = 2) -> rr.RenderSpec:
        return rr.RenderSpec(shape, bsdf, cam, spp=st.spp, passes=st.passes, seed=seed, max_depth=depth, dent=dent)

    grey = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [ALBEDO] * 3}}
    jobs = {"diffuse": spec("sphere", grey, dent_cam), "dented": spec("dented", grey, dent_cam),
            "dented_full": spec("dented", grey, dent_cam, st.interreflection_depth)}
    ni_cam = replace(sphere_cam, size=st.ni_size)
    for case in brdf_cases(st.exponents, st.alphas):
        jobs[case.key] = spec("sphere", case.bsdf, sphere_cam)
        if case.model == "phong":
            jobs[case.key + "_ni"] = replace(spec("sphere", case.bsdf, ni_cam), spp=st.ni_spp,
                                             crop_deg=ps.NORMAL_INCIDENCE_DEG)
    jobs["blend"] = spec("sphere", {"type": "blendbsdf", "weight": BLEND_WEIGHT, "bsdf_0": grey,
                                    "bsdf_1": {"type": PHONG_PLUGIN, "exponent": BLEND_EXPONENT}}, sphere_cam)
    return Scene(envs, render_env, sphere_cam, dent_cam, jobs)


def render_all(ctx: Any, scene: Scene) -> dict[str, rr.Render]:
    """Every job rendered (or read from the cache); the front-sphere renders must share one G-buffer."""
    renders = {name: rr.render(scene.render_env, sp)
               for name, sp in ctx.progress(list(scene.jobs.items()), "ibl: Mitsuba renders")}
    front = next(r for r in renders.values() if r.spec.camera == scene.sphere_cam)
    for name, r in renders.items():
        if r.spec.camera == scene.sphere_cam and not (
                np.array_equal(r.mask, front.mask) and np.array_equal(r.normal[r.mask], front.normal[front.mask])):
            raise ValidateError(f"ibl: render {name} does not share the sphere G-buffer")
    return renders


def masked_image(render: rr.Render, values: np.ndarray) -> np.ndarray:
    """Per-pixel values (K, 3) of the render's mask pixels → an (S, S, 3) image, NaN elsewhere."""
    out = np.full(render.mask.shape + (3,), np.nan)
    out[render.mask] = values
    return out



@dataclass
class Comparison:
    """One approximation against one render: image, error maps, statistics per view-angle band."""

    label: str
    group: str
    parameter: str
    approx: np.ndarray
    rel: ie.RelativeError
    flip: FlipResult
    bands: list[ie.ImageErrorStats]

    def row(self) -> dict:
        return {"group": self.group, "approximation": self.label, "parameter": self.parameter,
                **self.rel.stats.to_json(), "flip_mean": self.flip.mean, "bands": [b.to_json() for b in self.bands]}


def flip(reference: np.ndarray, approx: np.ndarray, mask: np.ndarray, enabled: bool = True) -> FlipResult:
    """HDR-FLIP of the masked pixels, or a NaN placeholder when the settings skip it (quick runs)."""
    if enabled:
        return flip_hdr(reference, approx, mask, negatives="clamp")
    return FlipResult(np.full(mask.shape, np.nan), float("nan"), {"skipped": "quick settings"})


def compare(render: rr.Render, approx: np.ndarray, label: str, group: str, parameter: str,
            reference: np.ndarray | None = None, with_flip: bool = True) -> Comparison:
    """Relative error, FLIP (unless ``with_flip`` is False) and view-angle bands of ``approx`` (S, S, 3)
    against the render (or a noise-free ``reference`` image on the render's pixels)."""
    ref = render.mean if reference is None else reference
    se = render.stderr_y if reference is None else np.zeros(ref.shape[:2])
    rel = ie.relative_error(ref, se, approx, render.mask)
    theta = np.degrees(np.arccos(np.clip(np.nan_to_num(render.cos_view, nan=-1.0), -1.0, 1.0)))
    bands = [ie.summarize(rel, render.mask & (theta >= lo) & (theta < hi))
             for lo, hi in zip(ANGLE_BINS[:-1], ANGLE_BINS[1:], strict=True)]
    return Comparison(label, group, parameter, approx, rel, flip(ref, approx, render.mask, with_flip), bands)


@dataclass
class References:
    """Quadrature irradiance (E, δ) per environment and per set of normals."""

    normals: dict[str, np.ndarray]
    values: dict[str, dict[str, tuple[np.ndarray, np.ndarray]]]

    def __call__(self, env: str, part: str) -> tuple[np.ndarray, np.ndarray]:
        return self.values[env][part]


def reference_all(ctx: Any, st: Settings, scene: Scene, renders: dict[str, rr.Render]) -> References:
    """One quadrature per environment at every normal any part needs (the rendered environment also at
    the G-buffer normals of the diffuse, dented and front spheres)."""
    parts = {"test": latlong.fibonacci_sphere(st.test_normals),
             "claim": latlong.fibonacci_sphere(st.claim_normals) @ random_rotation(ctx.seed).T,
             "texels": cube_texel_directions(st.sh_face).reshape(-1, 3)}
    gbuf = {k: renders[j].normal[renders[j].mask] for k, j in (("sphere", "diffuse"), ("dent", "dented"),
                                                                ("front", "blend"))}
    values: dict[str, dict[str, tuple[np.ndarray, np.ndarray]]] = {}
    for name, env in ctx.progress(list(scene.envs.items()), "ibl: reference irradiance"):
        p = dict(parts, **(gbuf if env is scene.render_env else {}))
        ref = reference_irradiance(env, np.concatenate(list(p.values())))
        out, k = {}, 0
        for pk, pv in p.items():
            out[pk] = (ref.irradiance[k:k + len(pv)], ref.uncertainty[k:k + len(pv)])
            k += len(pv)
        values[name] = out
    return References(parts, values)


# ---------------------------------------------------------------------------------------------
# Diffuse maps against the quadrature
# ---------------------------------------------------------------------------------------------

def map_sweep(env: Any, ref_e: np.ndarray, ref_u: np.ndarray, normals: np.ndarray, nodes: im.EnvironmentNodes,
              st: Settings) -> dict:
    """Peak-normalised error of cube and lat-long irradiance maps at every resolution of the sweep."""
    flux = env.total_flux()
    out: dict = {}
    for kind, sizes in (("cube", st.faces), ("latlong", st.heights)):
        rows: dict[str, list] = {k: [] for k in ("size", "max", "max_uncertainty", "mean", "texels", "relative_max")}
        for n in sizes:
            build = im.compute_irradiance_cube if kind == "cube" else im.compute_irradiance_latlong
            e = irradiance_errors(ref_e, build(env.radiance, n, nodes, needed=normals).lookup(normals), flux, ref_u)
            for k, v in (("size", n), ("max", e["peak"].max), ("max_uncertainty", e["peak"].max_uncertainty),
                         ("mean", e["peak"].mean), ("relative_max", e["relative"].max),
                         ("texels", 6 * n * n if kind == "cube" else 2 * n * n)):
                rows[k].append(v)
        out[kind] = rows
    return out


def smallest_passing(sweeps: dict[str, dict], kind: str) -> int | None:
    """Smallest size whose max error + uncertainty < 1 % on every environment of the sweep."""
    sizes = next(iter(sweeps.values()))[kind]["size"]
    for k, n in enumerate(sizes):
        if all(s[kind]["max"][k] + s[kind]["max_uncertainty"][k] < MAP_MAX_ERROR for s in sweeps.values()):
            return int(n)
    return None


@dataclass
class MapCheck:
    """Worst peak-normalised error of the cube map of face ``face`` on the claim normals."""

    face: int
    max: float
    uncertainty: float
    env: str


def map_check(scene: Scene, refs: References, nodes: dict[str, im.EnvironmentNodes], face: int) -> MapCheck:
    worst = MapCheck(face, -1.0, 0.0, "")
    normals = refs.normals["claim"]
    for name, env in scene.envs.items():
        e_ref, e_u = refs(name, "claim")
        m = im.compute_irradiance_cube(env.radiance, face, nodes[name], needed=normals)
        e = irradiance_errors(e_ref, m.lookup(normals), env.total_flux(), e_u)["peak"]
        if e.max + e.max_uncertainty > worst.max + worst.uncertainty:
            worst = MapCheck(face, e.max, e.max_uncertainty, name)
    return worst


def sh_vs_convolution(scene: Scene, refs: References, nodes: dict[str, im.EnvironmentNodes], face: int,
                      flip_band: int | None = None, conv_maps: dict[str, np.ndarray] | None = None
                      ) -> dict[str, tuple[float, float]]:
    """max |Y(E_SH9 map) − Y(E_conv map)| / Φ_Y per environment at the cube texels, with the uncertainty
    (the convolution map's deviation from the quadrature + the quadrature's own). ``flip_band`` = 1
    negates the l = 1 coefficients (the power check: one SH band's sign flipped). ``conv_maps``: the
    convolution maps' texels (6·face², 3) per environment when already built (:func:`convolution_texels`)."""
    conv_maps = convolution_texels(scene, nodes, face) if conv_maps is None else conv_maps
    out = {}
    for name, env in scene.envs.items():
        conv = conv_maps[name]
        coeffs = shm.project_environment(env.radiance, 2).copy()
        if flip_band is not None:
            coeffs[flip_band ** 2:(flip_band + 1) ** 2] *= -1.0
        sh_map = im.irradiance_cube_from_sh(coeffs, face).faces.reshape(-1, 3).astype(np.float64)
        e_ref, e_u = refs(name, "texels")
        phi_y = float(latlong.luminance(env.total_flux()))
        y_conv = latlong.luminance(conv)
        diff = float(np.max(np.abs(latlong.luminance(sh_map) - y_conv))) / phi_y
        unc = (float(np.max(np.abs(y_conv - latlong.luminance(e_ref)))) + float(np.max(latlong.luminance(e_u)))) / phi_y
        out[name] = (diff, unc)
    return out


def convolution_texels(scene: Scene, nodes: dict[str, im.EnvironmentNodes], face: int) -> dict[str, np.ndarray]:
    """Every texel (6·face², 3) of each environment's convolution cube map (float64), built once for both
    :func:`sh_vs_convolution` calls (test and power check)."""
    return {name: im.compute_irradiance_cube(env.radiance, face, nodes[name]).faces.reshape(-1, 3).astype(np.float64)
            for name, env in scene.envs.items()}


@dataclass
class DiffuseMaps:
    sweeps: dict[str, dict]
    face: int | None
    height: int | None
    claim_face: int
    check: MapCheck
    check_smaller: MapCheck | None  # the next smaller face on the same normals (power check)
    sh: dict[str, tuple[float, float]]
    sh_flipped: dict[str, tuple[float, float]]
    nodes: dict[str, im.EnvironmentNodes] = field(repr=False)


def diffuse_maps(ctx: Any, st: Settings, scene: Scene, refs: References) -> DiffuseMaps:
    nodes = {name: im.environment_nodes(env.radiance) for name, env in scene.envs.items()}
    sweeps = {name: map_sweep(env, *refs(name, "test"), refs.normals["test"], nodes[name], st)
              for name, env in ctx.progress(list(scene.envs.items()), "ibl: map sweep")}
    face, height = smallest_passing(sweeps, "cube"), smallest_passing(sweeps, "latlong")
    claim_face = face if face is not None else st.faces[-1]
    k = st.faces.index(claim_face)
    smaller = map_check(scene, refs, nodes, st.faces[k - 1]) if k > 0 else None
    conv = convolution_texels(scene, nodes, st.sh_face)
    return DiffuseMaps(sweeps, face, height, claim_face, map_check(scene, refs, nodes, claim_face), smaller,
                       sh_vs_convolution(scene, refs, nodes, st.sh_face, conv_maps=conv),
                       sh_vs_convolution(scene, refs, nodes, st.sh_face, flip_band=1, conv_maps=conv), nodes)


# ---------------------------------------------------------------------------------------------
# Rendered spheres: irradiance techniques and maps, specular techniques
# ---------------------------------------------------------------------------------------------

@dataclass
class DiffuseRender:
    maps: list[Comparison]  # the irradiance maps (cube claim face, cube 4², lat-long)
    techniques: dict[str, Comparison]  # every registered irradiance technique
    consistency: ie.RelativeError  # Mitsuba's Lambertian sphere vs ρ/π × quadrature
    quadrature_bound: float  # Σ ρ/π Y(δ) / Σ Y(R): the quadrature's own uncertainty, as a bias bound


def diffuse_render(st: Settings, scene: Scene, renders: dict[str, rr.Render], refs: References,
                   maps: DiffuseMaps) -> DiffuseRender:
    dif = renders["diffuse"]
    n_d = dif.normal[dif.mask]
    rad, nodes = scene.render_env.radiance, maps.nodes[scene.render_env.name]
    e_q, e_qu = refs(scene.render_env.name, "sphere")
    consistency = ie.relative_error(dif.mean, dif.stderr_y, masked_image(dif, ALBEDO / np.pi * e_q), dif.mask)
    q_bound = float(np.sum(ALBEDO / np.pi * latlong.luminance(e_qu)) / np.sum(consistency.y_ref[dif.mask]))
    ll_h = maps.height if maps.height is not None else 64
    built = {f"cube {maps.claim_face}²": im.compute_irradiance_cube(rad, maps.claim_face, nodes, needed=n_d),
             "cube 4²": im.compute_irradiance_cube(rad, 4, nodes, needed=n_d),
             f"lat-long {ll_h}×{2 * ll_h}": im.compute_irradiance_latlong(rad, ll_h, nodes, needed=n_d)}
    comps = [compare(dif, masked_image(dif, im.shade_lambert(m, n_d, ALBEDO)), label, "Lambertian",
                     f"ρ = {ALBEDO:g}", with_flip=st.flip) for label, m in built.items()]
    techs = {tech.name: compare(dif, masked_image(dif, ALBEDO / np.pi * irradiance.call(tech, rad, n_d)),
                                tech.name, "Lambertian", f"ρ = {ALBEDO:g}", with_flip=st.flip)
             for tech in judged(irradiance)}
    return DiffuseRender(comps, techs, consistency, q_bound)


def supports(tech: Technique, model: str) -> bool:
    """Does a specular technique declare BRDF ``model`` (meta ``brdf=(...)``; none declared: every model)?"""
    models = tech.meta.get("brdf")
    return models is None or model in tuple(models)


def shade_specular(tech: Technique | str, render: rr.Render, radiance: np.ndarray, brdf: dict) -> np.ndarray:
    """The technique's outgoing radiance at the render's pixels, as an image (S, S, 3)."""
    n, v = render.normal[render.mask], render.view[render.mask]
    return masked_image(render, specular.call(tech, radiance, brdf, n, v))


@dataclass
class SpecularRun:
    """Per technique and BRDF case: the whole-sphere comparison and (Phong) the normal-incidence crop."""

    cases: list[BrdfCase]
    comparisons: dict[str, dict[str, Comparison]]  # technique → case key → comparison
    normal_incidence: dict[str, dict[str, ie.RelativeError]]  # technique → phong case key → crop error


def specular_run(ctx: Any, st: Settings, scene: Scene, renders: dict[str, rr.Render]) -> SpecularRun:
    rad = scene.render_env.radiance
    cases = brdf_cases(st.exponents, st.alphas)
    comps: dict[str, dict[str, Comparison]] = {}
    crops: dict[str, dict[str, ie.RelativeError]] = {}
    for tech in ctx.progress(judged(specular), "ibl: specular techniques"):
        comps[tech.name], crops[tech.name] = {}, {}
        for case in (c for c in cases if supports(tech, c.model)):
            r = renders[case.key]
            comps[tech.name][case.key] = compare(r, shade_specular(tech, r, rad, case.brdf), tech.name, case.group,
                                                 case.label, with_flip=st.flip)
            if case.key + "_ni" in renders:
                rc = renders[case.key + "_ni"]
                crops[tech.name][case.key] = ie.relative_error(rc.mean, rc.stderr_y,
                                                               shade_specular(tech, rc, rad, case.brdf), rc.mask)
    return SpecularRun(cases, comps, crops)


@dataclass
class MixShader:
    """The seed's mixing shader vs ``blendbsdf``. By linearity its luminance-weighted bias must equal the
    bias its ingredients predict: [(1−w)ρ/π Σ(Y(E_map) − Y(E_quad)) + w Σ(Y(P_map) − Y(R_phong))] / Σ Y(R),
    R_phong the separate Phong render at the same pixels."""

    comparison: Comparison
    bias: float  # Σ (Y(A) − Y(R)) / Σ Y(R)
    predicted: float
    sigma: float  # standard error of bias − predicted (blend and Phong renders, independent)
    allowance: float  # the quadrature's own uncertainty, (1−w)ρ/π Σ Y(δ) / Σ Y(R)
    dof: int
    bias_unlit: float  # the bias with DiffusePercent = 0.9 (power check)

    def z(self, bias: float | None = None) -> float:
        b = self.bias if bias is None else bias
        excess = max(abs(b - self.predicted) - self.allowance, 0.0)
        return float(abs(t_to_z(np.array(excess / self.sigma), self.dof)))


def mix_shader(st: Settings, scene: Scene, renders: dict[str, rr.Render], refs: References,
               maps: DiffuseMaps) -> MixShader:
    blend, phong = renders["blend"], renders[f"phong_{BLEND_EXPONENT:g}"]
    nb, vb = blend.normal[blend.mask], blend.view[blend.mask]
    rad = scene.render_env.radiance
    e_map = im.compute_irradiance_cube(rad, maps.claim_face, maps.nodes[scene.render_env.name], needed=nb).lookup(nb)
    p_map = specular.call("phong_prefiltered", rad, {"model": "phong", "exponent": BLEND_EXPONENT}, nb, vb)
    base = (1 - BLEND_WEIGHT) * ALBEDO

    def shade(diffuse_percent: float) -> np.ndarray:
        return ps.mix_shader(base, diffuse_percent, BLEND_WEIGHT, e_map / np.pi, p_map)

    comp = compare(blend, masked_image(blend, shade(1.0)), "mixing shader", "blend",
                   f"w = {BLEND_WEIGHT:g}, s = {BLEND_EXPONENT:g}", with_flip=st.flip)
    Y = latlong.luminance
    total = float(np.sum(Y(blend.mean[blend.mask])))
    e_q, e_u = refs(scene.render_env.name, "front")
    pred = (base / np.pi * np.sum(Y(e_map) - Y(e_q)) + BLEND_WEIGHT * np.sum(Y(p_map) - Y(phong.mean[phong.mask])))
    sig_p = BLEND_WEIGHT * np.sqrt(np.sum(phong.stderr_y[phong.mask] ** 2)) / total
    unlit = float(np.sum(Y(shade(0.9)) - Y(blend.mean[blend.mask])) / total)
    return MixShader(comp, comp.rel.stats.bias, float(pred / total),
                     float(np.hypot(comp.rel.stats.bias_uncertainty, sig_p)),
                     float(base / np.pi * np.sum(Y(e_u)) / total), st.passes - 1, unlit)


@dataclass
class Concave:
    data: dict[str, Any]
    images: dict[str, np.ndarray]
    ao: np.ndarray
    errors: dict[str, np.ndarray]


def concave(st: Settings, scene: Scene, renders: dict[str, rr.Render], refs: References,
            maps: DiffuseMaps) -> Concave:
    """The dented sphere: the map, the exact unoccluded irradiance and AO × map against Mitsuba's direct
    lighting and its inter-reflections, over all pixels and in the crater (AO < 0.95)."""
    dr_, df_ = renders["dented"], renders["dented_full"]
    ao, _ = rr.ambient_occlusion(scene.render_env, scene.jobs["dented"], st.ao_samples)
    nd = dr_.normal[dr_.mask]
    rad = scene.render_env.radiance
    dmap = im.compute_irradiance_cube(rad, maps.claim_face, maps.nodes[scene.render_env.name], needed=nd)
    l_map = masked_image(dr_, im.shade_lambert(dmap, nd, ALBEDO))
    l_unocc = masked_image(dr_, ALBEDO / np.pi * refs(scene.render_env.name, "dent")[0])
    l_ao = l_map * ao[..., None]
    crater = dr_.mask & (ao < CRATER_AO)
    exact = replace(dr_, mean=l_unocc, stderr_y=np.zeros_like(dr_.stderr_y))  # noise-free quadrature
    data: dict[str, Any] = {"crater_pixels": int(crater.sum()), "pixels": int(dr_.mask.sum())}
    errors = {}
    for label, img, ref_r in (("map vs direct render", l_map, dr_), ("unoccluded reference vs direct", l_unocc, dr_),
                              ("map vs unoccluded reference", l_map, exact), ("AO × map vs direct", l_ao, dr_),
                              ("map vs render with inter-reflections", l_map, df_),
                              ("AO × map vs inter-reflections", l_ao, df_)):
        rel = ie.relative_error(ref_r.mean, ref_r.stderr_y, img, ref_r.mask)
        data[label] = {"all": rel.stats.to_json(), "crater": ie.summarize(rel, crater).to_json(),
                       "flip": flip(ref_r.mean, img, ref_r.mask, st.flip).mean}
        errors[label] = rel.error
    tot, occ = data["map vs direct render"]["crater"]["mean"], data["unoccluded reference vs direct"]["crater"]["mean"]
    data["occlusion_share_crater"] = occ / tot if tot > 0 else float("nan")
    return Concave(data, {"direct": dr_.mean, "full": df_.mean, "map": l_map, "unoccluded": l_unocc, "ao_map": l_ao},
                   ao, errors)


@dataclass
class IblMeasurements:
    """What :func:`validate.experiments.ibl.compute` returns (numbers and images)."""

    st: Settings
    scene: Scene
    renders: Mapping[str, Any]
    maps: DiffuseMaps
    diffuse: DiffuseRender
    specular: SpecularRun
    mix: MixShader
    concave: Concave
    chi2: Chi2Check
    furnace: ZCheck
    split_constant: ZCheck
    phong_ni: dict[str, dict[str, float]]  # s → {"ratio", "ratio_u", "ratio_s"} (phong_ni in ibl.py)
    khronos: Any = None  # .khronos.compute.KhronosMeasurements: the glTF-IBL-Sampler part


def phong_ni(st: Settings, scene: Scene, renders: Mapping[str, rr.Render],
             run: SpecularRun) -> dict[str, dict[str, float]]:
    """Per Phong exponent: Σ|ΔY| of the s + 1 map (and of the same-exponent map) over the θ_v ≤ 5° crop,
    and Σσ_Y, each over Σ Y(U) of the independent bound (:func:`.chk.phong_bound`)."""
    out = {}
    for case in (c for c in run.cases if c.model == "phong"):
        rc = renders[case.key + "_ni"]
        a, b = (run.normal_incidence[t][case.key] for t in ("phong_prefiltered", "phong_prefiltered_s"))
        sel = np.isfinite(a.error) & np.isfinite(b.error)
        n, v = rc.normal[sel], rc.view[sel]
        u = chk.luminance_sum(chk.phong_bound(scene.render_env.radiance, case.brdf["exponent"], n, v))
        out[f"{case.brdf['exponent']:g}"] = {
            "ratio": float(np.sum(np.abs(a.y_app[sel] - a.y_ref[sel]))) / u,
            "ratio_s": float(np.sum(np.abs(b.y_app[sel] - b.y_ref[sel]))) / u,
            "ratio_u": float(np.sum(a.y_se[sel])) / u, "pixels": int(sel.sum())}
    return out


REFERENCE_CHECKS = ("furnace", "chi2", "split_constant")  # the costliest first


def reference_check(which: str, st: Settings) -> Chi2Check | ZCheck:
    """One of the reference BSDF checks, which depend on the settings alone: ``"chi2"``
    (:func:`.chk.phong_chi2`), ``"furnace"`` (:func:`.chk.phong_furnace`), ``"split_constant"``
    (:func:`.chk.split_sum_constant`)."""
    return {"chi2": chk.phong_chi2, "furnace": chk.phong_furnace, "split_constant": chk.split_sum_constant}[which](st)


def compute(ctx: Context, st: Settings) -> IblMeasurements:
    """Every number of the experiment (no claims, no prose). With Dask workers, the reference BSDF checks
    (:data:`REFERENCE_CHECKS`, settings alone) run there while this process does the rest; without, here
    (the same tasks in the serial run's order, the same numbers)."""
    fn = partial(reference_check, st=st)
    background = None
    if ctx.distributed:
        ctx.client()  # the cluster is started (or connected to) from the main thread
        background = Background(lambda: ctx.map(fn, list(REFERENCE_CHECKS), "ibl: reference BSDF checks"),
                                "ibl-reference-checks")
    scene = build_scene(st, ctx.seed)
    renders = render_all(ctx, scene)
    refs = reference_all(ctx, st, scene, renders)
    maps = diffuse_maps(ctx, st, scene, refs)
    spec = specular_run(ctx, st, scene, renders)
    diffuse = diffuse_render(st, scene, renders, refs, maps)
    mix, dent = mix_shader(st, scene, renders, refs, maps), concave(st, scene, renders, refs, maps)
    if background is not None:
        ni = phong_ni(st, scene, renders, spec)
        checks = dict(zip(REFERENCE_CHECKS, background.result(), strict=True))
    else:  # the order of the serial run before the checks went to the workers
        checks = {w: fn(w) for w in ("chi2", "furnace", "split_constant")}
        ni = phong_ni(st, scene, renders, spec)
    return IblMeasurements(st, scene, renders, maps, diffuse, spec, mix, dent, checks["chi2"], checks["furnace"],
                           checks["split_constant"], ni, compute_khronos(ctx, st, spec))
