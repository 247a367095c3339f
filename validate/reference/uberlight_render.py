"""Reference renders of the überlight scenes: a textured Mitsuba projector and a barn-door luminaire.

Both use the lights experiment's machinery (:mod:`validate.reference.light_render`): Mitsuba's
``direct`` integrator on pixel-centre camera rays, P passes with the ``independent`` sampler
(pass k seeded ``seed + 7919 k``) → per-pixel mean ± standard error (P − 1 dof), and the ``aov``
G-buffer of the same rays.

Projector radiometry (Mitsuba 3, src/emitters/projector.cpp, ``sample_direction``): for a receiver
at p_local = (x, y, z) in the emitter's frame (z forward) the returned emitter weight is

    π · scale · T(u, v) / (z² · cos θ),   cos θ = z/|p_local|,

i.e. a radiant intensity I(ω) = π · scale · T(u, v) / cos³θ (so that the irradiance on the plane z = 1,
I cos³θ, is π · scale · T). The texel lookup: (u, v) = (½ − ½ x/(z t), ½ − ½ a y/(z t)),
t = tan(fov_x/2), a = n_x/n_y the texture's aspect (``perspective_projection`` inverted; u = 0 at the
texture's first column, v = 0 at its first row). A square n × n texture over fov_x therefore holds
at texel centre (i, j) the direction x/z = t(1 − 2(i + ½)/n), y/z = t(1 − 2(j + ½)/n). To emit
I(ω) = I₀ · A(x/z, y/z), :func:`projector_texture` stores T = I₀ A cos³θ / π (scale = 1). The emitter is
a delta light: the estimate is deterministic (passes agree; the uncertainty is float32 rounding).

Barn-door luminaire (:mod:`validate.scenes.uberlight_scenes`): an area ``disk`` emitter behind a
black plate with a rectangular hole; the direct integrator samples the disc (and the BSDF, MIS), the
plate occludes: its beam edge is the true penumbra. Monte Carlo: per-pixel standard errors.

Exact on-axis irradiance of a Lambertian disc of radiance L and radius r facing a receiver at
distance d on its axis [1, Table 4.2 / eq. for the coaxial disc]:

    E(d) = π L r² / (r² + d²),

finite (π L) at d = 0 and → I₀/d² with I₀ = π L r² as d → ∞ (:func:`disc_on_axis_irradiance`).

References
  [1] M. F. Modest, *Radiative Heat Transfer*, 3rd ed., Appendix D (view factor of a coaxial disc
      from a parallel differential element, F = r²/(r² + d²)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..backend import init
from ..errors import ValidateError
from ..scenes.uberlight_scenes import UberScene
from ..stats import mean_and_stderr
from .cache import array_digest, cached
from .light_render import render_passes
from .shadow_render import render_gbuffer, segment_visible

CODE_VERSION = "uberlight_render/1"


@dataclass
class UberRender:
    """Per-pixel reference (H, W, ·), row 0 at the top; ``valid``: receiver pixels (albedo > 0)."""

    radiance: np.ndarray  # (H, W) grey radiance, mean over passes (W m⁻² sr⁻¹)
    uncertainty: np.ndarray  # (H, W) standard error of the mean
    position: np.ndarray
    normal: np.ndarray
    albedo: np.ndarray  # (H, W) grey albedo
    valid: np.ndarray
    pass_images: np.ndarray  # (P, H, W)
    spp: int
    passes: int
    seed: int

    def settings(self) -> dict[str, Any]:
        return {"integrator": "direct (1 emitter + 1 BSDF sample, MIS)", "sampler": "independent",
                "spp_per_pass": self.spp, "passes": self.passes, "seed": self.seed, "pixel_sampling": "pixel centres"}


def texel_directions(n: int, fov_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """(x/z, y/z) at the centres of an n × n projector texture over fov_x (module docstring), (n, n) each."""
    if n < 2 or not 0 < fov_deg < 180:
        raise ValidateError(f"projector texture n={n}, fov={fov_deg}: need n ≥ 2 and 0 < fov < 180")
    t = math.tan(math.radians(fov_deg) / 2)
    c = t * (1.0 - 2.0 * (np.arange(n) + 0.5) / n)
    return np.meshgrid(c, c, indexing="xy")  # [row j, column i]: x from column, y from row


def projector_texture(mask: np.ndarray, intensity: float, fov_deg: float) -> np.ndarray:
    """T = I₀ · A · cos³θ / π at the texel centres (scale 1): the projector then emits I₀ · A."""
    n = mask.shape[0]
    x, y = texel_directions(n, fov_deg)
    cos3 = (1.0 + x * x + y * y) ** -1.5
    return intensity * np.asarray(mask, dtype=np.float64) * cos3 / math.pi


def _load(scene: UberScene, texture: np.ndarray | None = None, with_light: bool = True) -> Any:
    import mitsuba as mi

    init()
    return mi.load_dict(scene.mitsuba_dict(texture, with_light))


def render(scene: UberScene, texture: np.ndarray | None = None, spp: int = 1, passes: int = 2,
           seed: int = 1234) -> UberRender:
    """The cached render of ``scene`` (a projector needs its ``texture``)."""
    cam = scene.camera
    key = {"code": CODE_VERSION, "scene": scene.parts(), "spp": spp, "passes": passes, "seed": seed}
    if texture is not None:

        key["texture"] = array_digest(np.ascontiguousarray(texture, dtype=np.float32))

    def compute() -> dict[str, np.ndarray]:
        lit = _load(scene, texture)
        g = render_gbuffer(lit, cam.width, cam.height)
        imgs = render_passes(lit, cam.width, cam.height, spp, passes, seed)
        return {**g, "passes": imgs[..., 0].astype(np.float32)}

    r = cached("uberlight_render", key, compute)
    imgs = r["passes"].astype(np.float64)
    mean, err = mean_and_stderr(imgs, axis=0)
    albedo = r["albedo"][..., 0]
    valid = r["valid"].astype(bool) & (albedo > 0)
    return UberRender(mean, err, r["position"], r["normal"], albedo, valid, imgs, spp, passes, seed)


def visibility(scene: UberScene, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(N,) 1 where the segment from each receiver (lifted 10⁻⁴ m along its normal) to the light position
    is free of the scene's geometry (Mitsuba ``ray_test``), else 0."""
    geometry = _load(scene, with_light=False)
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    target = np.broadcast_to(np.asarray(scene.luminaire.position, dtype=np.float64), p.shape)
    return segment_visible(geometry, p, np.asarray(normals, dtype=np.float64).reshape(-1, 3),
                           np.ascontiguousarray(target)).astype(np.float64)


def disc_on_axis_irradiance(d: np.ndarray, radiance: float, radius: float) -> np.ndarray:
    """E(d) = π L r²/(r² + d²): exact on-axis irradiance of a facing Lambertian disc (module docstring)."""
    d = np.asarray(d, dtype=np.float64)
    return math.pi * radiance * radius ** 2 / (radius ** 2 + d ** 2)
