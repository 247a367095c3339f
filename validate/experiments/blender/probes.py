"""bpy-built probe scenes: glossy spheres over roughness, and a Lambertian sphere on a plane lit by a volume probe.

**Glossy spheres** (:class:`GlossyScene`): the world-lit sphere of :mod:`.world` (same camera, same world texture —
Mitsuba's envmap evaluated at Blender's texel centres — same box filter over the footprint) with a white GGX
microfacet mirror of roughness r instead of Lambert. The one BSDF in both renderers:

* Blender: the Glossy BSDF node, distribution ``GGX`` (single scattering; ``MULTI_GGX`` would add the
  multiple-scattering lobe), colour white — the node applies no Fresnel, so F = 1 — and α = roughness² (Cycles
  ``bsdf_microfacet``: ``alpha = sqr(roughness)``); Cycles 5.0's masking-shadowing is Smith's height-correlated
  G₂ = 1/(1 + Λ(ω_i) + Λ(ω_o)) (``bsdf_G`` in ``kernel/closure/bsdf_microfacet.h``; Cycles ≤ 3.x used the
  separable G₁G₁).
* Mitsuba: the suite's glTF BSDF (:mod:`validate.reference.gltf_bsdf`) at baseColor 1, metallic 1: F(1) = 1, GGX D
  with α = roughness², the height-correlated V [glTF B.3.2, Heitz 2014] — the same function. Mitsuba's own
  ``roughconductor`` is *not* used: its G is the separable G₁(ω_i)G₁(ω_o).

The sphere is convex and alone, so the truth is one bounce (``path``, ``max_depth = 2``) as :mod:`.world`'s.
EEVEE reflects the world through its world sphere probe (the world captured into the sphere-probe atlas,
``World.probe_resolution``, filtered per roughness), and with a Sphere light-probe object (variant ``sphere_probe``:
``lightprobe_add(type='SPHERE')`` at the sphere's centre, influence radius :data:`SPHERE_PROBE_RADIUS`, the sphere
hidden from it, so it captures the world alone; EEVEE captures sphere probes at render) through that probe's
capture and its parallax (the default: a sphere of the influence radius around the probe; variant
``sphere_probe_far``: a custom parallax sphere of radius :data:`FAR_PARALLAX`, as near infinity as the world).

**Volume probe** (:class:`VolumeScene`): a Lambertian sphere (albedo :data:`VOLUME_ALBEDO`) resting above a
Lambertian square (the same albedo) at y = −1, lit only by the probe, seen from 30° above the horizon by an
orthographic camera of scale 4 (the whole film on the plane or the sphere). The truth is Mitsuba's path tracer with
every bounce (``max_depth`` :data:`VOLUME_DEPTH`). EEVEE renders it without a probe object (variant ``world``: the
world probe, no occlusion of the sky by the sphere but its horizon scan) and with an irradiance volume (variant
``volume``: ``lightprobe_add(type='VOLUME')`` over the scene, :data:`VOLUME_RESOLUTION` cells, baked headless by
``lightprobe_cache_bake`` before the frame; EEVEE stores L1 spherical harmonics per cell). Findings only: Blender's
manual gives no bound for either. Cycles renders the same description (variant ``cycles``: Lambert in both, its
bounces set to Mitsuba's path length, max_bounces = diffuse_bounces = max_depth − 2), a second truth judged as the
glossy spheres' (:func:`.world.cycles_numbers`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ...local_models.render import blender as bl
from ...metrics.pixel_z import interior_mask, judge
from ...reference import pathtrace
from ...reference.cache import cached
from ...scenes.environment import Environment
from ...stats import mean_and_stderr
from . import world as wd

ROUGHNESS = (0.1, 0.3, 0.6)
GLOSSY_VARIANTS = ("world", "sphere_probe", "sphere_probe_far")
SPHERE_PROBE_RADIUS = 2.5  # Blender's default influence distance (m)
# ``sphere_probe_far``'s custom parallax sphere (m): Blender 5.0 has no infinite parallax; at radius D a reflected
# ray leaving the unit sphere turns by at most asin(1/D) ≈ 0.006°, a fifteenth of half a texel of the world (0.088°)
FAR_PARALLAX = 1.0e4
VOLUME_VARIANTS = ("world", "volume")
VOLUME_ALBEDO = 0.5
VOLUME_DEPTH = 8  # Mitsuba's path length: albedo 0.5 leaves < 0.5⁷ ≈ 0.8 % of a pixel to longer paths at worst
VOLUME_VIEW = (30.0, 0.0)
VOLUME_ORTHO = 4.0
PLANE = (-1.0, 12.0)  # Blender's z (the suite's y) and the square's side: it fills the film seen from 30°
VOLUME_RESOLUTION = (8, 8, 4)  # irradiance cells along Blender's x, y, z
VOLUME_SCALE = (3.0, 3.0, 1.5)  # the volume's half extents (Blender's probe is a cube of half side 1 × scale)
VOLUME_SAMPLES = 256  # bake_samples
MODEL = "Glossy BSDF, GGX (single scattering), white, α = roughness²"


def alpha(roughness: float) -> float:
    """Blender's roughness → GGX α (Cycles: ``alpha = sqr(roughness)``; glTF the same)."""
    return float(roughness) ** 2


@dataclass(frozen=True)
class GlossyScene:
    env: Environment
    view: tuple[float, float]
    roughness: float

    @property
    def name(self) -> str:
        return f"glossy_{self.env.name}_r{self.roughness:g}"


@dataclass(frozen=True)
class VolumeScene:
    env: Environment

    @property
    def name(self) -> str:
        return f"volume_{self.env.name}"


def glossy_desc(gs: GlossyScene, exr: Path, variant: str = "world") -> dict[str, Any]:
    """The worker's description (``blender_worker.build``): :mod:`.world`'s sphere with the Glossy BSDF."""
    desc = {"kind": "world_sphere", "segments": wd.SEGMENTS, "rings": wd.RINGS, "albedo": 1.0,
            "ortho_scale": wd.ORTHO_SCALE, "camera": wd.camera_matrix(gs.view), "filter_px": 1.0, "world": {},
            "eevee": {}, "env_exr": str(exr), "bsdf": {"type": "glossy", "roughness": float(gs.roughness),
                                                       "distribution": "GGX"}}
    if variant in ("sphere_probe", "sphere_probe_far"):
        desc["probes"] = [{"type": "SPHERE", "location": [0.0, 0.0, 0.0], "radius": SPHERE_PROBE_RADIUS,
                           "hide_sphere": True}]
    if variant == "sphere_probe_far":
        desc["probes"][0]["parallax"] = FAR_PARALLAX
    return desc


def volume_desc(vs: VolumeScene, exr: Path, variant: str = "world") -> dict[str, Any]:
    desc = {"kind": "world_sphere", "segments": wd.SEGMENTS, "rings": wd.RINGS, "albedo": VOLUME_ALBEDO,
            "ortho_scale": VOLUME_ORTHO, "camera": wd.camera_matrix(VOLUME_VIEW), "filter_px": 1.0, "world": {},
            "eevee": {}, "env_exr": str(exr), "plane": [PLANE[0], PLANE[1], VOLUME_ALBEDO]}
    if variant == "cycles":  # Cycles' bounces = Mitsuba's max_depth − 2 (max_depth 2 is direct light, bounces 0)
        desc["cycles"] = {"max_bounces": VOLUME_DEPTH - 2, "diffuse_bounces": VOLUME_DEPTH - 2}
    if variant == "volume":
        desc["probes"] = [{"type": "VOLUME", "location": [0.0, 0.0, 0.0], "scale": list(VOLUME_SCALE),
                           "resolution": list(VOLUME_RESOLUTION), "samples": VOLUME_SAMPLES}]
    return desc


def job(desc: dict[str, Any], engine: bl.BlenderEngine, resolution: int, samples: int, seeds: tuple[int, ...],
        out: Path) -> bl.Job:
    return bl.Job("", str(out), engine.engine, resolution, samples, seeds, scene=desc)


# ---------------------------------------------------------------- the Mitsuba truth of the same descriptions

def sensor(view: tuple[float, float], ortho_scale: float, resolution: int, spp: int) -> dict[str, Any]:
    """Mitsuba's orthographic sensor of :mod:`.world` (film [−1, 1]²) scaled to span ``ortho_scale``."""
    import mitsuba as mi

    s = 0.5 * ortho_scale
    to_world = pathtrace.camera_to_world(view) @ mi.ScalarTransform4f().scale([s, s, 1])
    return {"type": "orthographic", "to_world": to_world,
            "film": {"type": "hdrfilm", "width": resolution, "height": resolution, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": pathtrace.SAMPLER, "sample_count": spp}}


def glossy_scene(env: Environment, roughness: float, resolution: int, spp: int, view: tuple[float, float]) -> Any:
    import mitsuba as mi

    from ...reference.gltf_bsdf import bsdf_dict

    return mi.load_dict({"type": "scene", "integrator": dict(pathtrace.INTEGRATOR),
                         "sensor": sensor(view, wd.ORTHO_SCALE, resolution, spp),
                         "sphere": {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0,
                                    "bsdf": bsdf_dict((1.0, 1.0, 1.0), 1.0, roughness)},
                         "environment": env.mitsuba_emitter()})


def volume_scene(env: Environment, resolution: int, spp: int) -> Any:
    import mitsuba as mi

    diffuse = {"type": "diffuse", "reflectance": {"type": "rgb", "value": [VOLUME_ALBEDO] * 3}}
    half = 0.5 * PLANE[1]
    plane = (mi.ScalarTransform4f().translate([0.0, PLANE[0], 0.0]) @ mi.ScalarTransform4f().rotate([1, 0, 0], -90)
             @ mi.ScalarTransform4f().scale([half, half, 1.0]))
    return mi.load_dict({"type": "scene",
                         "integrator": {"type": "path", "max_depth": VOLUME_DEPTH, "hide_emitters": True},
                         "sensor": sensor(VOLUME_VIEW, VOLUME_ORTHO, resolution, spp),
                         "sphere": {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0, "bsdf": diffuse},
                         "plane": {"type": "rectangle", "to_world": plane, "bsdf": dict(diffuse)},
                         "environment": env.mitsuba_emitter()})


@dataclass
class Truth:
    mean: np.ndarray  # (R, R, 3)
    stderr: np.ndarray
    passes: int
    spp: int
    images: np.ndarray  # (P, R, R, 3) the passes (the bias test's cross-fitted z)


def truth(kind: str, env: Environment, resolution: int, spp: int, passes: int, seed: int,
          roughness: float = 0.0, view: tuple[float, float] = VOLUME_VIEW) -> Truth:
    """Mitsuba's ``passes`` independent passes of ``kind`` ("glossy" | "volume"), cached on every setting."""
    import mitsuba as mi

    from ...backend import init

    def compute() -> dict[str, np.ndarray]:
        init()
        scene = (glossy_scene(env, roughness, resolution, spp, view) if kind == "glossy"
                 else volume_scene(env, resolution, spp))
        return {"passes": np.stack([np.array(mi.render(scene, seed=seed * pathtrace.MAX_PASSES + i, spp=spp),
                                             dtype=np.float64) for i in range(passes)])}

    parts = {"env": env.digest, "kind": kind, "resolution": resolution, "spp": spp, "passes": passes, "seed": seed,
             "view": list(view), "roughness": roughness,
             "model": "gltf_metallic_roughness base 1 metallic 1" if kind == "glossy" else
             {"albedo": VOLUME_ALBEDO, "depth": VOLUME_DEPTH, "plane": list(PLANE), "ortho": VOLUME_ORTHO}}
    images = cached("blender_probe_truth", parts, compute)["passes"]
    mean, stderr = mean_and_stderr(images, axis=0)
    return Truth(mean, stderr, passes, spp, images)


# ---------------------------------------------------------------- judgements

def eevee_numbers(img: np.ndarray, t: Truth, mask: np.ndarray) -> dict[str, Any]:
    """EEVEE (one half-float frame) against the truth on ``mask``: per-pixel acceptance within the combined
    uncertainty (the truth's passes and the half-float rounding), the mean of |E − T| / T (pixels whose truth is at
    least 10⁻³ of its mean: REL_FLOOR) beside the value the truth's noise alone would give (√(2/π) σ/T), the bias
    mean(E − T) / mean(T), the energy ratio."""
    sig = np.sqrt(t.stderr**2 + wd.half_sigma(img) ** 2)
    j = judge(img, t.mean, sig, t.passes - 1, mask, 0.0, "none")
    tm, e = t.mean[mask], img[mask]
    ok = tm > pathtrace.REL_FLOOR * tm.mean()
    r, u = wd.energy(e, wd.half_sigma(e), tm, t.stderr[mask])
    floor = math.sqrt(2.0 / math.pi) * sig[mask][ok] / tm[ok]  # E|N(0, σ)| / T: the mean |rel. error| of noise alone
    return {"accepted": j.fraction_accepted, "pixels": j.n_pixels,
            "rel_mean": float(np.mean(np.abs(e - tm)[ok] / tm[ok])), "noise_floor": float(floor.mean()),
            "bias": float((e - tm).mean() / tm.mean()), "energy": (r, u)}


def sphere_mask(resolution: int, frames: list[np.ndarray]) -> np.ndarray:
    """Pixels whose whole footprint lies on the sphere and every Blender frame covers."""
    cov = np.min([f[..., 3].min(axis=0) for f in frames], axis=0) if frames else np.ones((resolution, resolution))
    return interior_mask(pathtrace.footprint_mask(resolution), cov, 0)


def film_mask(resolution: int, frames: list[np.ndarray]) -> np.ndarray:
    cov = np.min([f[..., 3].min(axis=0) for f in frames], axis=0) if frames else np.ones((resolution, resolution))
    return cov >= 1.0 - 1e-6


def sphere_pixels(resolution: int, view: tuple[float, float], ortho_scale: float) -> np.ndarray:
    """(R, R) pixels whose centre ray meets the unit sphere (film spanning ``ortho_scale``)."""
    c = (np.arange(resolution) + 0.5) / resolution
    x, y = np.meshgrid(0.5 * ortho_scale * (1.0 - 2.0 * c), 0.5 * ortho_scale * (1.0 - 2.0 * c))
    return x * x + y * y <= 1.0


__all__ = ["ROUGHNESS", "GLOSSY_VARIANTS", "VOLUME_VARIANTS", "MODEL", "GlossyScene", "VolumeScene", "alpha",
           "glossy_desc", "volume_desc", "job", "truth", "eevee_numbers", "sphere_mask",
           "film_mask", "sphere_pixels", "Truth"]
