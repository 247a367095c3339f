"""bpy-built scenes: a white Lambertian sphere lit only by a shared probe, in Blender and Mitsuba from one description.

The scene is the ``sh9`` experiment's path-traced cross-check (:mod:`validate.reference.pathtrace`): the unit sphere,
reflectance 1, lit only by the environment, an orthographic camera whose film spans the sphere, a box pixel filter
over the footprint; its Mitsuba render (``render_lambertian_sphere``, cached) is the per-pixel truth, and the
footprint-averaged quadrature E/π (``quadrature_sphere``) the irradiance truth of R&H's measure.

Blender gets the same description (:func:`job`): a smooth UV sphere (:data:`SEGMENTS` × :data:`RINGS`), a Diffuse
BSDF of roughness 0 (Lambert), an orthographic camera of scale 2 placed as Mitsuba's (the suite's y-up frame carried
into Blender's z-up one by the rotation :func:`to_blender`, (x, y, z) ↦ (z, x, y)), and a world texture resampled
from Mitsuba's own envmap (``emitter.eval``) at the texel centres of Blender's equirectangular mapping (Cycles
``direction_to_equirectangular``: u = ½ − atan2(y, x)/2π, top row +z) at :data:`ENV_UPSAMPLE` × the probe's
resolution — so both renderers see one radiance function, whatever the two conventions for texel centres (Mitsuba
reads row i at θ = πi/(H − 1)). A frame error in this chain moves the lit side of the sphere: the claims' power
check (the truth's image mirrored left–right) catches it.

EEVEE's world diffuse lighting is the world light probe's spherical harmonics (L1, de-ringed; Blender PRs #110110,
#121303) plus, above ``World.sun_threshold`` (default 10; 0 disables it), the excess extracted into a sun light
(``sun_angle``), and the indirect clamp ``SceneEEVEE.clamp_surface_indirect`` (default 10; 0 disables it; "used by
ray-tracing and light-probes"). Blender 5.0.1 has no property named ``clamp_world``: these two, read by
introspection of ``bpy.types.World`` and ``SceneEEVEE``, are its world clamps. :data:`VARIANTS` turns them on and off.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...local_models import irradiance as irradiance_family
from ...local_models.render import blender as bl
from ...metrics.irradiance_error import irradiance_errors
from ...metrics.pixel_z import interior_mask, judge
from ...reference import pathtrace
from ...scenes.environment import Environment
from ...stats import cross_fitted_z, mean_z_bound, standardized_mean

BIAS_SIGMAS = pathtrace.BIAS_SIGMAS  # |mean z̃| / sd(z̃) ≤ 4/√N per channel (reference.pathtrace)

SEGMENTS, RINGS = 256, 128  # Blender's UV sphere: normal interpolation error ≈ (π/128)²/8 ≈ 8·10⁻⁵ rad²
ENV_UPSAMPLE = 2  # Blender's world texture: this many texels per probe texel along each axis
ORTHO_SCALE = 2.0  # the orthographic film spans [−1, 1]² (Mitsuba's sensor: the sphere fills the image)
TECHNIQUES = ("sh1", "sh1_geomerics", "sh9")  # the suite's own techniques beside EEVEE
# EEVEE's world settings per variant: (World attributes, SceneEEVEE attributes)
VARIANTS: dict[str, tuple[dict[str, float], dict[str, float]]] = {
    "default": ({}, {}),  # sun_threshold 10, clamp_surface_indirect 10 (Blender's defaults)
    "no_sun": ({"sun_threshold": 0.0}, {}),  # no sun extraction: the whole world in the probe's SH
    "no_clamp": ({}, {"clamp_surface_indirect": 0.0}),
    "no_sun_no_clamp": ({"sun_threshold": 0.0}, {"clamp_surface_indirect": 0.0}),
}


def to_blender(d: np.ndarray) -> np.ndarray:
    """Suite (y-up) → Blender (z-up) direction: (x, y, z) ↦ (z, x, y), a rotation (det +1)."""
    d = np.asarray(d, np.float64)
    return np.stack([d[..., 2], d[..., 0], d[..., 1]], axis=-1)


def from_blender(d: np.ndarray) -> np.ndarray:
    d = np.asarray(d, np.float64)
    return np.stack([d[..., 1], d[..., 2], d[..., 0]], axis=-1)


def blender_texel_directions(height: int, width: int) -> np.ndarray:
    """(H, W, 3) Blender-world directions of the texel centres of Blender's equirectangular map (row 0 = top)."""
    u = (np.arange(width) + 0.5) / width
    v = 1.0 - (np.arange(height) + 0.5) / height  # Blender's v runs up; row 0 is the top
    phi = np.pi * (1.0 - 2.0 * u)  # atan2(y, x) = π (1 − 2u)
    el = (v - 0.5) * np.pi
    ce = np.cos(el)[:, None]
    return np.stack(np.broadcast_arrays(ce * np.cos(phi)[None, :], ce * np.sin(phi)[None, :],
                                        np.sin(el)[:, None]), axis=-1)


def world_texture(env: Environment) -> np.ndarray:
    """(H′, W′, 3) float32 radiance for Blender's world: Mitsuba's envmap evaluated at Blender's texel centres."""
    import mitsuba as mi

    from ...backend import init
    from ...scenes.mitsuba_eval import eval_emitter

    init()
    h, w = env.height * ENV_UPSAMPLE, env.width * ENV_UPSAMPLE
    emitter = mi.load_dict(env.mitsuba_emitter())
    d = from_blender(blender_texel_directions(h, w)).reshape(-1, 3)
    return eval_emitter(emitter, d).reshape(h, w, 3).astype(np.float32)


def write_exr(path: Path, rgb: np.ndarray) -> None:
    import OpenEXR

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": np.ascontiguousarray(rgb, np.float32)}) as f:
        f.write(str(path))


def camera_matrix(view: tuple[float, float]) -> list[list[float]]:
    """Blender's camera ``matrix_world`` (row-major) for Mitsuba's sensor of ``view`` (pathtrace.camera_to_world):
    local X = −left, Y = up′, Z = −forward (Blender's camera looks down −Z), at the same origin."""
    m = np.array(pathtrace.camera_to_world(view).matrix, dtype=np.float64).reshape(4, 4)
    left, up, fwd, origin = (to_blender(m[:3, k]) for k in range(4))
    out = np.eye(4)
    out[:3, 0], out[:3, 1], out[:3, 2], out[:3, 3] = -left, up, -fwd, origin
    return out.tolist()


@dataclass(frozen=True)
class WorldScene:
    """One world-lit sphere: a probe seen from one view."""

    env: Environment
    view: tuple[float, float]

    @property
    def name(self) -> str:
        return f"world_{self.env.name}_v{self.view[0]:g}_{self.view[1]:g}"


def job(ws: WorldScene, exr: Path, engine: bl.BlenderEngine, resolution: int, samples: int, seeds: tuple[int, ...],
        out: Path, variant: str = "default") -> bl.Job:
    """The Blender job of one world-lit sphere (the texture's path is left out of the cache key: its digest is in)."""
    world, eevee = VARIANTS[variant] if engine.engine != "CYCLES" else ({}, {})
    desc = {"kind": "world_sphere", "segments": SEGMENTS, "rings": RINGS, "albedo": 1.0, "ortho_scale": ORTHO_SCALE,
            "camera": camera_matrix(ws.view), "filter_px": 1.0, "world": dict(world), "eevee": dict(eevee),
            "env_exr": str(exr)}
    return bl.Job("", str(out), engine.engine, resolution, samples, seeds, scene=desc)


def texture(env: Environment) -> tuple[np.ndarray, str]:
    """:func:`world_texture`, cached on the environment's digest; and the texture's content hash."""
    from ...reference.cache import lookup, store

    parts = {"env": env.digest, "upsample": ENV_UPSAMPLE, "mapping": "blender_equirect_v1"}
    hit = lookup("blender_world_texture", parts)
    tex = hit["texture"] if hit is not None else world_texture(env)
    if hit is None:
        store("blender_world_texture", parts, {"texture": tex})
    return tex, hashlib.sha256(np.ascontiguousarray(tex, np.float32).tobytes()).hexdigest()


def footprint_normals(render: pathtrace.SphereRender, k: int = pathtrace.FOOTPRINT_NODES
                      ) -> tuple[np.ndarray, np.ndarray]:
    """(N, k², 3) unit normals at the Gauss–Legendre nodes of each masked pixel, and the (k²,) weights."""
    r = render.resolution
    x, w = pathtrace.footprint_nodes(k)
    rows, cols = np.nonzero(render.mask)
    u = (cols[:, None, None] + x[None, None, :]) / r
    v = (rows[:, None, None] + x[None, :, None]) / r
    u, v = np.broadcast_arrays(u, v)
    n, _ = pathtrace.film_to_normals(u, v, render.view)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return n.reshape(len(rows), k * k, 3), (w[:, None] * w[None, :]).reshape(-1)


def technique_sphere(env: Environment, render: pathtrace.SphereRender) -> dict[str, np.ndarray]:
    """Per technique of :data:`TECHNIQUES`: footprint-averaged E′ (N, 3) on the masked pixels (as the truth)."""
    n, w = footprint_normals(render)
    out = {}
    for name in TECHNIQUES:
        if name not in irradiance_family:
            continue
        e = irradiance_family.call(name, env.radiance, n.reshape(-1, 3))
        out[name] = (e.reshape(n.shape[0], -1, 3) * w[None, :, None]).sum(axis=1)
    return out


def rh_errors(e_ref: np.ndarray, e: np.ndarray, flux: np.ndarray, unc: np.ndarray) -> dict[str, float]:
    """R&H's measure (``flux_luminance``, :mod:`validate.metrics.irradiance_error`): mean and max of
    |Y(E′) − Y(E)| / Φ_Y over the pixels, ± from the truth's uncertainty."""
    st = irradiance_errors(e_ref, e, flux, unc)["flux_luminance"]
    return {"mean": st.mean, "max": st.max, "mean_uncertainty": st.mean_uncertainty,
            "max_uncertainty": st.max_uncertainty}


def flux_luminance_bound_check(errs: dict[str, float]) -> bool:
    """R&H 2001's SH9 statement, "< 1 % on average, < 5 % at worst" of Φ, as a boolean on the measured numbers."""
    return errs["mean"] < 0.01 and errs["max"] < 0.05


def half_sigma(img: np.ndarray) -> np.ndarray:
    return np.spacing(np.abs(img).astype(np.float16)).astype(np.float64) / math.sqrt(12.0)


__all__ = ["WorldScene", "WorldResult", "VARIANTS", "TECHNIQUES", "job", "texture", "judge_world", "world_texture",
           "write_exr", "camera_matrix", "technique_sphere", "rh_errors", "to_blender", "from_blender",
           "blender_texel_directions"]


@dataclass
class WorldResult:
    """One probe's world-lit sphere: Cycles judged per pixel against Mitsuba, EEVEE and the techniques by R&H's
    measure against the quadrature."""

    probe: str
    view: tuple[float, float]
    flux_luminance: float
    cycles: dict  # judgement, power, mirrored, energy, frames, spp, rh
    eevee: dict  # variant → {"samples", "rh", "energy", "frame_s"}
    techniques: dict  # technique → rh
    mitsuba: dict  # spp, passes
    # mean over the judged pixels of each renderer over the footprint-averaged quadrature (± from its standard error
    # and the quadrature's): "mitsuba" on the footprint mask, "cycles" on Cycles' interior mask
    quadrature: dict = field(default_factory=dict)


def energy(img: np.ndarray, se: np.ndarray, tm: np.ndarray, ts: np.ndarray) -> tuple[float, float]:
    """mean(img) / mean(truth) over the given pixels (flattened), ± from both standard errors."""
    a, b, n = float(img.mean()), float(tm.mean()), img.size
    ua, ub = math.sqrt(float((se**2).sum())) / n, math.sqrt(float((ts**2).sum())) / n
    r = a / b
    return r, r * math.hypot(ua / a, ub / b)


def bias(frames: np.ndarray, truth: np.ndarray, mask: np.ndarray, scale: float = 1.0) -> float:
    """max over channels of |mean z̃| / sd(z̃) over ``mask``: z̃ the cross-fitted z (:func:`validate.stats.
    cross_fitted_z`) of ``scale`` × Blender's frames (F, R, R, 3) against the truth's passes (P, R, R, 3), each pixel's
    difference from one half of the passes over the standard error of the other half, so centred under H₀ however
    skewed the passes (the bias test of :func:`validate.reference.pathtrace.compare`)."""
    z = cross_fitted_z(scale * frames[:, mask], truth[:, mask])
    return float(np.abs(standardized_mean(z)).max())


def cycles_numbers(frames: np.ndarray, truth: Any, mask: np.ndarray, power_scale: float) -> dict[str, Any]:
    """Cycles' passes (F, R, R, 4) against Mitsuba's (``truth``: ``mean``, ``stderr``, ``passes``, ``images``) on
    ``mask``: the claims' numbers — acceptance, the truth mirrored left–right and flipped upside down, the bias test
    (:func:`bias`), each with Cycles × ``power_scale`` where it is the power check — and the energy ratio."""
    f = frames.astype(np.float64)
    img = f[..., :3].mean(axis=0)
    se = f[..., :3].std(axis=0, ddof=1) / math.sqrt(len(f))
    sig = np.sqrt(truth.stderr**2 + se**2)
    dof = truth.passes - 1
    text = "none (the UV sphere's normals within 10⁻⁴ rad of the sphere's)"
    return {"frames": len(f), "judgement": judge(img, truth.mean, sig, dof, mask, 0.0, text),
            "power": judge(img * power_scale, truth.mean, sig, dof, mask, 0.0, text),
            "mirrored": judge(img, truth.mean[:, ::-1], sig[:, ::-1], dof, mask & mask[:, ::-1], 0.0, text),
            "flipped": judge(img, truth.mean[::-1], sig[::-1], dof, mask & mask[::-1], 0.0, text),
            "bias": bias(f[..., :3], truth.images, mask),
            "bias_power": bias(f[..., :3], truth.images, mask, power_scale),
            "bias_limit": mean_z_bound(int(mask.sum()), BIAS_SIGMAS),
            "energy": energy(img[mask], se[mask], truth.mean[mask], truth.stderr[mask])}


def judge_world(ws: WorldScene, render: pathtrace.SphereRender, cycles: np.ndarray | None,
                eevee: dict[str, tuple[int, np.ndarray, list[float]]], power_scale: float) -> WorldResult:
    """``cycles``: (F, R, R, 4) frames; ``eevee``: variant → (samples, (1, R, R, 4) frames, frame seconds)."""
    env = ws.env
    q, uq = pathtrace.quadrature_sphere(env, render)
    hit = render.mask
    flux = env.total_flux()
    m = hit
    e_ref, u_ref = np.pi * q[m], np.pi * uq[m]
    out = WorldResult(env.name, ws.view, float(0.2126 * flux[0] + 0.7152 * flux[1] + 0.0722 * flux[2]), {}, {},
                      {name: rh_errors(e_ref, e, flux, u_ref) for name, e in technique_sphere(env, render).items()},
                      {"spp": render.spp_per_pass, "passes": render.passes})
    out.quadrature["mitsuba"] = energy(render.mean[m], render.stderr[m], q[m], uq[m])
    if cycles is not None:
        f = cycles.astype(np.float64)
        img, cov = f[..., :3].mean(axis=0), f[..., 3].min(axis=0)
        se = f[..., :3].std(axis=0, ddof=1) / math.sqrt(len(f))
        mask = interior_mask(hit, cov)
        out.cycles = {**cycles_numbers(cycles, render, mask, power_scale),
                      "rh": rh_errors(e_ref, np.pi * img[m], flux, u_ref)}
        out.quadrature["cycles"] = energy(img[mask], se[mask], q[mask], uq[mask])
    for variant, (samples, frames, frame_s) in eevee.items():
        img = frames[0, ..., :3].astype(np.float64)
        uh = np.pi * half_sigma(img[m])
        out.eevee[variant] = {"samples": samples, "frame_s": frame_s,
                              "rh": rh_errors(e_ref, np.pi * img[m], flux, np.sqrt(u_ref**2 + uh**2)),
                              "energy": energy(img[m], half_sigma(img[m]), q[m], uq[m])}
    return out
