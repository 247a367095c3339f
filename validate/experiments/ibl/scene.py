"""Experiment ``ibl``, the scene and the Mitsuba render jobs.

Everything the experiment sweeps is in :mod:`.settings`; the BRDF cases compared with the ``specular``
family are :func:`brdf_cases` of those settings. See :mod:`validate.experiments.ibl` for the pipeline.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models.specular import prefiltered_specular as ps
from ...reference import ibl_render as rr
from ...scenes import latlong, procedural
from ...scenes.environment import Environment
from .settings import Settings

ALBEDO = 0.8  # grey Lambertian albedo of the diffuse renders
PLASTIC_RHO = 0.5  # roughplastic's default diffuse reflectance
PLASTIC_ETA = 1.49  # coat IOR (polypropylene, Mitsuba's default int_ior), over ext_ior = 1
BLEND_WEIGHT = 0.3  # blendbsdf weight of the Phong lobe in the mixing-shader render
BLEND_EXPONENT = 100.0
CAMERA_OFFSET_DEG = 6.0  # sphere camera: 6° off the key light, so the highlight sits at θ_v ≈ 3°
DENT_CAMERA_OFFSET_DEG = 60.0  # dented sphere: lit from the side
ANGLE_BINS = np.arange(0.0, 91.0, 10.0)  # view-angle bands θ_v (degrees)
RENDER_ENV = "disc_on_sky"


@dataclass(frozen=True)
class BrdfCase:
    """One BRDF the ``specular`` family is compared on: the family's mapping and Mitsuba's BSDF dict."""

    key: str  # "phong_10", "ggx_0.3", "ggx_plastic_0.3"
    label: str
    group: str
    brdf: dict
    bsdf: dict

    @property
    def model(self) -> str:
        return str(self.brdf["model"])


def brdf_cases(st: Settings) -> list[BrdfCase]:
    """Modified Phong at every exponent, GGX conductor (F = 1: Mitsuba's default) and plastic at every α."""
    cases = [BrdfCase(f"phong_{s:g}", f"s = {s:g}", "modified Phong", {"model": "phong", "exponent": s},
                      {"type": rr.PHONG_PLUGIN, "exponent": s}) for s in st.exponents]
    for a in st.alphas:
        cases.append(BrdfCase(f"ggx_{a:g}", f"α = {a:g}", "roughconductor (GGX)", {"model": "ggx", "alpha": a},
                              {"type": "roughconductor", "distribution": "ggx", "alpha": a}))
        cases.append(BrdfCase(f"ggx_plastic_{a:g}", f"α = {a:g}", "roughplastic (GGX)",
                              {"model": "ggx_plastic", "alpha": a, "eta": PLASTIC_ETA, "rho": PLASTIC_RHO},
                              {"type": "roughplastic", "distribution": "ggx", "alpha": a, "int_ior": PLASTIC_ETA,
                               "ext_ior": 1.0, "diffuse_reflectance": {"type": "rgb", "value": [PLASTIC_RHO] * 3}}))
    return cases


def make_environment(name: str, scale: int) -> Environment:
    """The sweep's procedural environments at 1/scale of their full resolution."""
    if name == "disc_on_sky":
        return procedural.disc_on_sky(256 // scale)
    if name == "two_tone":
        return procedural.two_tone(256 // scale)
    if name == "near_directional":
        return procedural.near_directional(512 // scale)
    if name.startswith("sunsky_"):
        return procedural.sunsky(float(name[len("sunsky_"):-len("deg")]), height=512 // scale, supersample=4 // scale)
    raise ValidateError(f"ibl: unknown sweep environment {name!r}")


def key_direction(env: Environment) -> np.ndarray:
    """Direction of the brightest texel (the key light)."""
    best, at = -np.inf, (0, 0)
    step = max(1, (1 << 20) // env.width)  # row blocks: no full-size luminance or directions
    for s in range(0, env.height, step):
        y = latlong.luminance(env.radiance[s:s + step])
        k = int(np.argmax(y))
        if y.flat[k] > best:
            best, at = float(y.flat[k]), (s + k // env.width, k % env.width)
    return latlong.spherical_to_direction(latlong.row_theta(env.height)[at[0]], latlong.col_phi(env.width)[at[1]])


def random_rotation(seed: int) -> np.ndarray:
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


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
    for case in brdf_cases(st):
        jobs[case.key] = spec("sphere", case.bsdf, sphere_cam)
        if case.model == "phong":
            jobs[case.key + "_ni"] = replace(spec("sphere", case.bsdf, ni_cam), spp=st.ni_spp,
                                             crop_deg=ps.NORMAL_INCIDENCE_DEG)
    jobs["blend"] = spec("sphere", {"type": "blendbsdf", "weight": BLEND_WEIGHT, "bsdf_0": grey,
                                    "bsdf_1": {"type": rr.PHONG_PLUGIN, "exponent": BLEND_EXPONENT}}, sphere_cam)
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


