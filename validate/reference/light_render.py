"""Reference renders of the classic-lights scene, the shadow-ray test, and the exact rectangle light.

Renders (:func:`render_lights`) use the shadow experiment's pixel-centre rays and G-buffer
(:mod:`validate.reference.shadow_render`): Mitsuba's ``direct`` integrator (the path tracer's direct
term, ``path`` with max_depth 2, with one emitter and one BSDF sample combined by MIS) on
pixel-centre camera rays, P passes → per-pixel mean ± standard error s/√P (P − 1 dof); the ``aov``
G-buffer (position, geometric normal, albedo) on the same rays. The passes use Mitsuba's
``independent`` sampler, pass k seeded ``seed + 7919 k``: every pixel and every pass is an
independent stream, so the per-pass image *totals* are independent too and a bias summed over the
image can be tested with P − 1 dof (a scrambled low-discrepancy sampler shares its scramble across
the pixels of a pass, which correlates their errors). The pass images are kept (``passes``).

* Delta lights (``point``, ``spot``, ``directional``) alone in a scene make the estimate
  deterministic: the emitter sample is the light itself and a BSDF sample never hits a delta
  emitter. Their passes agree bit for bit and the standard error is 0; what remains is float32
  rounding (the claims state it).
* With several emitters Mitsuba picks one per sample (probability 1/k), so a render with all lights
  is a genuine Monte Carlo estimate even when every light is a delta light.

The shadow-ray test handed to local models (:func:`shadow_tester`) traces Mitsuba rays against the
scene without the shape of the light being evaluated (other lights' shapes do cast shadows):
``scene.ray_test`` on segments lifted 10⁻⁴ m along the receiver's normal
(:func:`~validate.reference.shadow_render.segment_visible`).

Exact rectangle light (:func:`rectangle_irradiance`), Lambert's polygon formula [1; 2, eq. 2]:
for a uniform Lambertian polygon of radiance L entirely above the receiver's horizon,

    E(x) = (L/2) Σ_i θ_i n·γ_i,   θ_i = acos(u_i·u_{i+1}),  γ_i = (u_i × u_{i+1}) / |u_i × u_{i+1}|,

u_i the unit vectors from x to the vertices, ordered counter-clockwise as seen from x; the sum is
taken in absolute value. Points where the polygon crosses the horizon or which lie behind the
one-sided emitter are returned as NaN (the formula needs the polygon clipped there; not needed for
the ground-plane receivers it is used on).

References
  [1] J. H. Lambert, *Photometria*, 1760 (the polygon contour integral).
  [2] J. Arvo, "The Irradiance Jacobian for Partially Occluded Polyhedral Sources", SIGGRAPH 1994, eq. 2.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..backend import init
from ..errors import ValidateError
from ..scenes.light_scenes import Light, LightScene
from ..stats import mean_and_stderr
from .cache import cached
from .shadow_render import pixel_centre_positions, render_gbuffer, segment_visible

CODE_VERSION = "light_render/3"
PASS_SEED_STRIDE = 7919
SAME_HIT = 1e-4  # m: a pixel is a receiver when the light-free scene's camera ray hits the same point


@dataclass
class LightRender:
    """Per-pixel reference (H, W, ·), row 0 at the top."""

    radiance: np.ndarray  # mean over passes, W m⁻² sr⁻¹
    uncertainty: np.ndarray  # standard error of the mean
    position: np.ndarray
    normal: np.ndarray
    albedo: np.ndarray
    valid: np.ndarray  # (H, W) bool: the pixel-centre ray hits the ground/sphere/box (not an emitter)
    pass_images: np.ndarray  # (P, H, W, 3) the independent passes
    spp: int
    passes: int
    seed: int

    def settings(self) -> dict[str, Any]:
        return {"integrator": "direct (path max_depth 2: 1 emitter + 1 BSDF sample, MIS)", "sampler": "independent",
                "spp_per_pass": self.spp, "passes": self.passes, "seed": self.seed, "pixel_sampling": "pixel centres"}


def load(scene: LightScene, lights: str = "emit", with_sensor: bool = True, exclude: int | None = None) -> Any:
    """The Mitsuba scene (``lights``: emit / block / none, see :meth:`LightScene.mitsuba_dict`)."""
    import mitsuba as mi

    init()
    return mi.load_dict(scene.mitsuba_dict(lights, with_sensor, exclude))


def receiver_mask(scene: LightScene, gbuffer: dict[str, np.ndarray]) -> np.ndarray:
    """(H, W) pixels whose camera ray hits the scene's geometry, not an emitting shape: the G-buffer of the
    light-free scene must hit the same point (within :data:`SAME_HIT`)."""
    cam = scene.camera
    bare = render_gbuffer(load(scene, "none"), cam.width, cam.height)
    same = np.linalg.norm(bare["position"] - gbuffer["position"], axis=-1) < SAME_HIT
    return gbuffer["valid"] & bare["valid"] & same


def render_passes(mi_scene: Any, width: int, height: int, spp: int, passes: int, seed: int) -> np.ndarray:
    """(P, H, W, 3) pass images of the ``direct`` integrator on pixel-centre rays, ``independent`` sampler."""
    import mitsuba as mi

    if spp < 1 or passes < 2:
        raise ValidateError(f"light render spp={spp}, passes={passes}: need spp ≥ 1 and passes ≥ 2")
    integrator = mi.load_dict({"type": "direct", "emitter_samples": 1, "bsdf_samples": 1})
    rays, _ = mi_scene.sensors()[0].sample_ray(0.0, 0.5, pixel_centre_positions(width, height, spp),
                                               mi.Point2f(0.5, 0.5))
    images = []
    for k in range(passes):
        sampler = mi.load_dict({"type": "independent"})
        sampler.seed(seed + PASS_SEED_STRIDE * k, width * height * spp)
        spec, _, _ = integrator.sample(mi_scene, sampler, rays)
        images.append(np.array(spec).T.reshape(height, width, spp, 3).mean(axis=2, dtype=np.float64))
    return np.stack(images)


def render_lights(scene: LightScene, spp: int = 16, passes: int = 8, seed: int = 1234) -> LightRender:
    """The cached reference render of ``scene`` (module docstring)."""
    cam = scene.camera

    def compute() -> dict[str, np.ndarray]:
        lit = load(scene)
        g = render_gbuffer(lit, cam.width, cam.height)
        g["valid"] = receiver_mask(scene, g)
        return {**g, "passes": render_passes(lit, cam.width, cam.height, spp, passes, seed).astype(np.float32)}

    r = cached("light_render", {"code": CODE_VERSION, "scene": scene.parts(), "spp": spp, "passes": passes,
                                "seed": seed}, compute)
    imgs = r["passes"].astype(np.float64)
    mean, err = mean_and_stderr(imgs, axis=0)
    return LightRender(mean, err, r["position"], r["normal"], r["albedo"], r["valid"].astype(bool), imgs, spp,
                       passes, seed)


def shadow_tester(scene: LightScene, light_index: int = 0) -> Callable[[np.ndarray, np.ndarray, np.ndarray],
                                                                         np.ndarray]:
    """visible(origins (M, 3), normals (M, 3), targets (M, 3)) -> (M,) bool for the shadow rays of light
    ``light_index``: against the geometry, the blockers and every *other* area light's shape."""
    geometry = load(scene, "block", with_sensor=False, exclude=light_index)

    def visible(origins: np.ndarray, normals: np.ndarray, targets: np.ndarray) -> np.ndarray:
        o = np.ascontiguousarray(origins, dtype=np.float64).reshape(-1, 3)
        n = np.ascontiguousarray(normals, dtype=np.float64).reshape(-1, 3)
        t = np.ascontiguousarray(targets, dtype=np.float64).reshape(-1, 3)
        if not (o.shape == n.shape == t.shape):
            raise ValidateError(f"shadow test: {o.shape[0]} origins, {n.shape[0]} normals, {t.shape[0]} targets")
        return segment_visible(geometry, o, n, t) if o.size else np.zeros(0, dtype=bool)
    return visible


def rectangle_corners(light: Light) -> np.ndarray:
    """(4, 3) corners c ± a ± b, counter-clockwise seen from the emitting side (normal = forward)."""
    if light.kind != "rectangle":
        raise ValidateError(f"rectangle_corners: light of kind {light.kind!r}")
    left, up, _ = light.frame()
    c = np.asarray(light.position, dtype=np.float64)
    a, b = light.size[0] * left, light.size[1] * up
    return np.stack([c - a - b, c + a - b, c + a + b, c - a + b])


def rectangle_irradiance(light: Light, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Exact E(x) of the rectangle light (Lambert's formula, module docstring); NaN where it does not apply."""
    x = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    corners = rectangle_corners(light)
    nl = light.frame()[2]
    u = corners[None, :, :] - x[:, None, :]  # (N, 4, 3)
    above = np.all(np.einsum("nk,nvk->nv", n, u) > 0, axis=1)
    front = (x - np.asarray(light.position)) @ nl > 0
    u /= np.linalg.norm(u, axis=2, keepdims=True)
    total = np.zeros(x.shape[0])
    for i in range(4):
        a, b = u[:, i], u[:, (i + 1) % 4]
        cross = np.cross(a, b)
        theta = np.arccos(np.clip(np.einsum("nk,nk->n", a, b), -1.0, 1.0))
        total += theta * np.einsum("nk,nk->n", n, cross) / np.linalg.norm(cross, axis=1)
    e = 0.5 * light.power * np.abs(total)
    return np.where(above & front, e, np.nan)
