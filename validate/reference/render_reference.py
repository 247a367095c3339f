"""Mitsuba path-traced reference of a render scene, per pixel centre, with its standard error.

For every pixel whose centre ray hits the geometry (the unit sphere, or the plane that fills the image),
Mitsuba's ``path`` integrator
(``max_depth = 2``: camera ray, one bounce — exact for a lone convex sphere or a lone plane, which see nothing
but the lights and the environment; ``hide_emitters``) estimates the radiance along the *centre* ray
(x, y, +5) → −z of the orthographic camera (:mod:`validate.scenes.render_scenes`). Pixel centres, not
the pixel footprint: an engine without MSAA shades exactly one point per pixel, so this compares the
same quantity and no reconstruction filter enters.

Statistics: P independent passes of ``spp`` samples each (pass i seeded ``seed·MAX_PASSES + i``); the
per-pixel value is their mean m and its standard error s = std(passes, ddof 1)/√P (P − 1 dof) [1 §2].
A delta light (directional) with next-event estimation is noise free: s = 0 there, and the judgement
(:mod:`validate.metrics.pixel_z`) rests on the engine budget alone.

References
----------
[1] M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering*, 4th ed., §2 (Monte Carlo).
[2] W. Jakob et al., Mitsuba 3 documentation, "Custom rendering loops" (``integrator.sample``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ValidateError
from ..scenes.render_scenes import CAMERA_POSITION, RenderScene
from ..stats import mean_and_stderr
from .cache import cached

MAX_PASSES = 1024
MIN_PASSES = 4
INTEGRATOR = {"type": "path", "max_depth": 2, "hide_emitters": True}


@dataclass
class RenderReference:
    """(R, R, 3) mean radiance and standard error at pixel centres; NaN where the ray misses."""

    mean: np.ndarray
    stderr: np.ndarray
    hit: np.ndarray  # (R, R) bool: the centre ray hits the sphere
    spp: int
    passes: int
    seed: int

    @property
    def dof(self) -> int:
        return self.passes - 1


def centre_rays(scene: RenderScene) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) ray origins of the pixels whose centre ray hits the geometry, and the (R, R) hit mask."""
    x, y = scene.pixel_centres()
    hit = scene.hit_mask()
    o = np.stack([x[hit], y[hit], np.full(int(hit.sum()), CAMERA_POSITION[2])], axis=-1)
    return o, hit


def load_traced(scene_dict: dict) -> Any:
    """The Mitsuba scene of ``scene_dict`` with :data:`INTEGRATOR` (loaded once per reference, shared by its passes:
    a pass reads the scene and never changes it)."""
    import mitsuba as mi

    return mi.load_dict(dict(scene_dict, integrator=dict(INTEGRATOR)))


def centre_ray(origins: np.ndarray, spp: int, differential: bool = True) -> Any:
    """The pass's rays, ``spp`` per origin (pixel-major), direction −z (the same for every pass)."""
    import mitsuba as mi

    o = np.repeat(origins, spp, axis=0)
    p = mi.Point3f(*(mi.Float(o[:, k]) for k in range(3)))
    return (mi.RayDifferential3f if differential else mi.Ray3f)(p, mi.Vector3f(0.0, 0.0, -1.0))


def trace_pass(scene_dict: dict, origins: np.ndarray, spp: int, seed: int,
               prepared: tuple[Any, Any] | None = None) -> np.ndarray:
    """One pass: (N, 3) mean over ``spp`` samples of the radiance along each ray (direction −z); ``prepared``:
    (:func:`load_traced`, :func:`centre_ray`) of these arguments, else built here."""
    import drjit as dr
    import mitsuba as mi

    scene, ray = prepared if prepared is not None else (load_traced(scene_dict), centre_ray(origins, spp))
    n = origins.shape[0]
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(seed, n * spp)
    spec, _, _ = scene.integrator().sample(scene, sampler, ray, None, True)
    dr.eval(spec)
    rgb = np.stack([np.array(spec[k]) for k in range(3)], axis=-1).astype(np.float64)
    return rgb.reshape(n, spp, 3).mean(axis=1)


# ---------------------------------------------------------------- (b) material models: the suite's own plug-ins

BSDF_SAMPLED = "BSDF sampling only: L = weight · L_env(ω_o), one bounce (the sphere is convex)"


def register_models(scene: RenderScene) -> None:
    """Register the suite's Mitsuba plug-in that the scene's material model names (``Material.model``)."""
    if scene.material.model == "gltf":
        from .gltf_bsdf import register

        register()
    elif scene.material.model == "multiscatter":
        from .microsurface_bsdf import register as register_walk

        register_walk()


def trace_pass_bsdf_sampled(scene_dict: dict, origins: np.ndarray, spp: int, seed: int,
                            prepared: tuple[Any, Any] | None = None) -> np.ndarray:
    """One pass of :data:`BSDF_SAMPLED` for a lone convex shape under an environment: at the hit, one ``bsdf.sample``
    (weight = f cos/pdf, for the random walk its energy Π F = 1 at F₀ = 1 [Heitz et al. 2016 Algorithm 1]) and the
    environment's radiance along ω_o (the reflected ray leaves the convex sphere). Unbiased without ``eval``/``pdf``
    — the random walk's are stochastic estimates, which Mitsuba's emitter sampling and MIS would need."""
    import drjit as dr
    import mitsuba as mi

    scene, ray = prepared if prepared is not None else (load_traced(scene_dict), centre_ray(origins, spp, False))
    n = origins.shape[0]
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(seed, n * spp)
    si = scene.ray_intersect(ray)
    bs, weight = si.bsdf().sample(mi.BSDFContext(), si, sampler.next_1d(), sampler.next_2d(), si.is_valid())
    out = scene.ray_intersect(si.spawn_ray(si.to_world(bs.wo)))
    spec = dr.select(si.is_valid() & (out.is_valid() ^ True), weight * scene.environment().eval(out), 0.0)
    dr.eval(spec)
    rgb = np.stack([np.array(spec[k]) for k in range(3)], axis=-1).astype(np.float64)
    return rgb.reshape(n, spp, 3).mean(axis=1)


def render_reference(scene: RenderScene, spp: int = 64, passes: int = 8, seed: int = 0) -> RenderReference:
    """P passes of ``spp`` pixel-centre samples (module docstring); cached on the scene and settings. A material of
    model "multiscatter" (the random walk) is traced by :func:`trace_pass_bsdf_sampled`."""
    from ..backend import init

    if spp < 1:
        raise ValidateError(f"{scene.name}: spp={spp}: need at least 1 sample per pixel")
    if not MIN_PASSES <= passes <= MAX_PASSES:
        raise ValidateError(f"{scene.name}: passes={passes}: need {MIN_PASSES}..{MAX_PASSES}")
    origins, hit = centre_rays(scene)

    def compute() -> dict[str, np.ndarray]:
        init()
        register_models(scene)
        d = scene.mitsuba_dict()
        prepared = (load_traced(d), centre_ray(origins, spp, differential=not walk))
        return {"passes": np.stack([trace(d, origins, spp, seed * MAX_PASSES + i, prepared) for i in range(passes)])}

    walk = scene.material.model == "multiscatter"
    trace = trace_pass_bsdf_sampled if walk else trace_pass
    parts = {"scene": scene.key(), "spp": spp, "passes": passes, "seed": seed, "integrator": INTEGRATOR,
             "rays": "pixel centres, orthographic", **({"estimator": BSDF_SAMPLED} if walk else {})}
    p = cached("render_reference", parts, compute)["passes"]
    if not np.all(np.isfinite(p)) or p.min() < 0:
        raise ValidateError(f"{scene.name}: reference render has NaN/Inf or negative pixels")
    m, s = mean_and_stderr(p, axis=0)
    r = scene.resolution
    mean, stderr = np.full((r, r, 3), np.nan), np.full((r, r, 3), np.nan)
    mean[hit], stderr[hit] = m, s
    return RenderReference(mean, stderr, hit, spp, passes, seed)
