"""(e) Shadows for the ``renders`` experiment, described once: the Lambertian plane, a box occluder, a light.

A :class:`ShadowScene` is a :class:`~validate.scenes.render_scenes.RenderScene` (the same camera: orthographic at
z = 5 over [−1.1, 1.1]², the plane z = 0 filling the image) plus a box occluder *outside the camera's view*
(x > ``HALF_EXTENT``: no camera ray meets it, so every judged pixel is the plane) and the light's physical size,
which only the reference sees.

Lights (KHR_lights_punctual units, :mod:`validate.scenes.render_scenes`):

* directional, E = ``SUN_LUX`` lux travelling along (−1, 0, −1)/√2 (45° incidence). The engines model it as a
  delta light (a hard shadow) filtered by their shadow-map filter. The reference gives it an angular radius
  α = ``SUN_ANGULAR_RADIUS_DEG`` (3°; the real sun's is 0.27°, which at 64² would be a sub-pixel penumbra): a
  Mitsuba ``sphere`` area emitter of radius D sin α at distance D = ``SUN_DISTANCE`` along −direction, radiance
  L = E/(π sin²α). A uniform spherical cap of half-angle α wholly above the horizon delivers
  E = π L sin²α cos θ (Nusselt analogue: its projected disc), so the unshadowed plane receives exactly the
  engines' E cos θ; the finite distance changes the direction by < 1.1·√2/D rad and the irradiance by
  < 2·1.1/D relative (2e-4 at D = 1e4, inside the 0.25 %-of-peak budget).
* spot, I = ``SPOT_CD`` cd at ``SPOT_POSITION`` aimed at ``SPOT_TARGET`` with a 40°/50° cone that holds the
  whole view inside its inner cone (falloff 1 on every pixel: the cone plays no part, its shadow camera does).
  Reference: a Mitsuba ``sphere`` emitter of radius r = ``SPOT_RADIUS`` at the light's position, radiance
  L = I/(π r²) — a uniform sphere's intensity is L·π r² in every direction and its irradiance I cos θ/d² exactly
  (wholly above the horizon), the engines' inverse square.

Both references are Mitsuba's ``path`` (max_depth 2: direct light only, no bounce off the occluder — the engines
have none either), so the truth's penumbra is the visible fraction of the light's disc; :func:`visibility`
computes it geometrically (cos-weighted disc samples against the box slabs) to classify pixels as lit,
penumbra and umbra, independently of Mitsuba.

Engines (the scene JSON's ``shadow`` entry, read by ``three_shadows.mjs`` / ``babylon_shadows.mjs``): the plane
receives, only the occluder casts (castShadow false on the plane: no receiver self-shadowing, so no bias is needed:
three's bias 0, Babylon's default 5e-5; three's VSM alone draws the receiver into its map all the same — its
``receiveShadow`` meshes are rendered under VSM — and self-shadows the lit plane,
three's ``defects["shadows.vsm.lit"]``),
shadow map ``MAP_SIZE``² (three's default mapSize), the same light frustum in both engines
(directional: orthographic ±``ORTHO_HALF`` m from ``LIGHT_DISTANCE`` m along −direction; spot: perspective at the
light), near/far ``SHADOW_NEAR``/``SHADOW_FAR`` m. Shadow types (each engine's ``shadow_types``): three 0.187 Basic,
PCF,
PCFSoft (removed in r180: WebGLShadowMap warns and uses PCF) and VSM (radius 1, blurSamples 8, its defaults);
Babylon 9.35 PCF (usePercentageCloserFiltering, QUALITY_HIGH), PCSS (useContactHardeningShadow — Babylon's
contact-hardening shadows *are* its PCSS; contactHardeningLightSizeUVRatio 0.1, its default), ESM
(useExponentialShadowMap, depthScale 50) and blurred ESM (useBlurExponentialShadowMap); Filament 1.53.4
(``filament_shadows.mjs``) PCF only — its JS View binds View$ShadowType but no setShadowType, and its ShadowOptions
(map size, biases, PCSS light size) are not bound, so Filament's defaults hold (1024² map, constantBias 1 mm,
normalBias 1) and its own light frustum; its plane casts as well as receives (measured: otherwise no shadow at all).

References
----------
[1] Khronos, KHR_lights_punctual (directional: lux; spot: candela).
[2] W. Jakob et al., Mitsuba 3 plugin reference, ``sphere`` shape with an ``area`` emitter, ``cube``.
[3] R. Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 sketches (penumbra ∝ light size ×
    (d_receiver − d_blocker)/d_blocker).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..errors import ValidateError
from .render_scenes import HALF_EXTENT, LAMBERT, DirectionalLight, RenderScene, SpotLight, mitsuba_bsdf, mitsuba_shape

SUN_LUX = 3.0  # E ρ/π ≈ 0.68 at 45° incidence: radiance of order 1, as the other scenes
SUN_DIRECTION = (-1.0, 0.0, -1.0)  # travelling towards −x, −z: the occluder at x > 1.1 shadows the view
SUN_ANGULAR_RADIUS_DEG = 3.0
SUN_DISTANCE = 1.0e4  # m: the reference's sun sphere
SPOT_POSITION = (1.8, 0.0, 2.0)
SPOT_TARGET = (0.3, 0.0, 0.0)
SPOT_CD = 6.0  # E = I cos θ/d² ≈ 0.6–1.1 lux on the view
SPOT_INNER_DEG, SPOT_OUTER_DEG = 40.0, 50.0  # the view lies within 26° of the axis
SPOT_RADIUS = 0.15  # m: the reference's sphere light
MAP_SIZE = 512
LIGHT_DISTANCE = 5.0
ORTHO_HALF = 2.5
SHADOW_NEAR, SHADOW_FAR = 0.5, 10.0
VISIBILITY_SAMPLES = 16  # per axis of the light disc (16² cos-weighted samples per pixel)
DISC_NODES = 64  # per axis of the disc emitter's irradiance quadrature (64² equal-area nodes)


@dataclass(frozen=True)
class Box:
    """An axis-aligned box: ``center`` and full ``size`` (m)."""

    center: tuple[float, float, float]
    size: tuple[float, float, float]

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        c, h = np.asarray(self.center, float), 0.5 * np.asarray(self.size, float)
        return c - h, c + h

    def to_json(self) -> dict[str, Any]:
        return {"type": "box", "center": list(self.center), "size": list(self.size)}

    def mitsuba_dict(self) -> dict[str, Any]:
        """Mitsuba ``cube`` ([−1, 1]³) scaled to ``size`` and moved to ``center``; grey diffuse (it is never seen
        and, at max_depth 2, never lights the plane)."""
        import mitsuba as mi

        t = mi.ScalarTransform4f().translate(list(self.center)).scale([0.5 * s for s in self.size])
        return {"type": "cube", "to_world": t, "bsdf": mitsuba_bsdf(LAMBERT)}


# directional: a thin plate 1 m above the plane, wholly at x > 1.1 (out of view); its shadow (offset −1 m in x by the
# 45° light) covers x ∈ [0.2, 1.25], y ∈ [−0.5, 0.5] of the view
SUN_OCCLUDER = Box((1.7, 0.0, 0.975), (1.0, 1.0, 0.05))
# spot: a plate at 1.0–1.05 m between the light (z = 2) and the plane; its shadow covers x ≳ 0.5, |y| ≲ 0.6
SPOT_OCCLUDER = Box((1.4, 0.0, 1.025), (0.4, 0.6, 0.05))


@dataclass(frozen=True)
class ShadowScene(RenderScene):
    """The plane, one light, a box ``occluder``; ``light_size`` is the reference light's angular radius (deg,
    directional) or sphere radius (m, spot); ``shadow_type`` is the engines' filter (not part of the reference)."""

    occluder: Box = SUN_OCCLUDER
    light_size: float = 0.0
    shadow_type: str = "pcf"

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.geometry != "plane" or len(self.lights) != 1 or not isinstance(self.lights[0], (DirectionalLight,
                                                                                                   SpotLight)):
            raise ValidateError(f"shadow scene {self.name}: needs the plane and one directional or spot light")
        if not self.light_size > 0.0:
            raise ValidateError(f"shadow scene {self.name}: light_size={self.light_size}: must be > 0")
        lo, _ = self.occluder.bounds()
        if lo[0] <= HALF_EXTENT:
            raise ValidateError(f"shadow scene {self.name}: the occluder must lie outside the view (x > {HALF_EXTENT})")

    @property
    def light(self) -> DirectionalLight | SpotLight:
        return self.lights[0]  # type: ignore[return-value]

    def key(self) -> dict[str, Any]:
        """The reference's dependencies (the engines' shadow type is not one)."""
        return {**super().key(), "occluder": self.occluder.to_json(), "light_size": self.light_size,
                "sun_distance": SUN_DISTANCE}

    def emitter_sphere(self) -> tuple[np.ndarray, float, float]:
        """(centre, radius, radiance) of the reference's sphere emitter (module docstring)."""
        li = self.light
        if isinstance(li, DirectionalLight):
            s = np.sin(np.radians(self.light_size))
            return -li.unit_direction() * SUN_DISTANCE, SUN_DISTANCE * s, li.intensity / (np.pi * s * s)
        return np.asarray(li.position, float), self.light_size, li.intensity / (np.pi * self.light_size**2)

    def mitsuba_dict(self) -> dict[str, Any]:
        c, r, radiance = self.emitter_sphere()
        rgb = {"type": "rgb", "value": [radiance * k for k in self.light.color]}
        return {"type": "scene", "plane": mitsuba_shape("plane", self.material),
                "occluder": self.occluder.mitsuba_dict(),
                "light0": {"type": "sphere", "center": c.tolist(), "radius": float(r),
                           "emitter": {"type": "area", "radiance": rgb}}}

    def engine_json(self) -> dict[str, Any]:
        return {**super().engine_json(), "shadow": {
            "type": self.shadow_type, "occluders": [self.occluder.to_json()], "map_size": MAP_SIZE,
            "light_distance": LIGHT_DISTANCE, "ortho_half": ORTHO_HALF, "near": SHADOW_NEAR, "far": SHADOW_FAR}}

    def with_shadow_type(self, shadow_type: str) -> ShadowScene:
        """The scene with the engines' filter ``shadow_type``; which types an engine offers is its own
        (``Engine.shadow_types``: an engine refuses one it does not offer)."""
        if not isinstance(shadow_type, str) or not shadow_type.isidentifier():
            raise ValidateError(f"shadow type {shadow_type!r}: not a shadow type name")
        return replace(self, shadow_type=shadow_type)


class DiscShadowScene(ShadowScene):
    """The spot's shadow scene lit by a disc instead of a sphere: a one-sided Lambertian disc of radius
    ``light_size`` at the spot's position, facing along the spot's direction, radiance L = I/(π r²), so its on-axis
    intensity L·π r² is the spot's I (and its flux π I). Mitsuba: a ``disk`` shape with an ``area`` emitter (which
    emits on the side of its normal); Blender: an AREA light of shape DISK, size 2r, power π I (Blender's area light
    of power P emits radiance P/(π A): measured with Cycles against the closed form of a disc over a plane,
    E = π L r²/(h² + r²), to 0.3 %)."""

    def key(self) -> dict[str, Any]:
        return {**super().key(), "light_shape": "disc"}

    def emitter_disc(self) -> tuple[np.ndarray, np.ndarray, float, float]:
        """(centre, unit normal, radius, radiance) of the disc emitter."""
        li = self.light
        return (np.asarray(li.position, float), li.unit_direction(), self.light_size,
                li.intensity / (np.pi * self.light_size**2))

    def mitsuba_dict(self) -> dict[str, Any]:
        import mitsuba as mi

        c, n, r, radiance = self.emitter_disc()
        up = [0.0, 1.0, 0.0] if abs(n[1]) < 0.9 else [1.0, 0.0, 0.0]
        t = mi.ScalarTransform4f().look_at(origin=c.tolist(), target=(c + n).tolist(), up=up).scale([r, r, 1.0])
        rgb = {"type": "rgb", "value": [radiance * k for k in self.light.color]}
        return {"type": "scene", "plane": mitsuba_shape("plane", self.material),
                "occluder": self.occluder.mitsuba_dict(),
                "light0": {"type": "disk", "to_world": t, "emitter": {"type": "area", "radiance": rgb}}}


def disc_shadow_scene(resolution: int = 64) -> DiscShadowScene:
    li = SpotLight(SPOT_POSITION, SPOT_TARGET, SPOT_CD, SPOT_INNER_DEG, SPOT_OUTER_DEG)
    return DiscShadowScene("shadow_disc", LAMBERT, lights=(li,), resolution=resolution, geometry="plane",
                           occluder=SPOT_OCCLUDER, light_size=SPOT_RADIUS)


def sun_shadow_scene(resolution: int = 64) -> ShadowScene:
    return ShadowScene("shadow_directional", LAMBERT, lights=(DirectionalLight(SUN_DIRECTION, SUN_LUX),),
                       resolution=resolution, geometry="plane", occluder=SUN_OCCLUDER,
                       light_size=SUN_ANGULAR_RADIUS_DEG)


def spot_shadow_scene(resolution: int = 64) -> ShadowScene:
    li = SpotLight(SPOT_POSITION, SPOT_TARGET, SPOT_CD, SPOT_INNER_DEG, SPOT_OUTER_DEG)
    return ShadowScene("shadow_spot", LAMBERT, lights=(li,), resolution=resolution, geometry="plane",
                       occluder=SPOT_OCCLUDER, light_size=SPOT_RADIUS)


def shadow_scenes(resolution: int = 64) -> list[ShadowScene]:
    """(e) the directional and the spot light over the plane, each with its occluder."""
    return [sun_shadow_scene(resolution), spot_shadow_scene(resolution)]


def unshadowed_radiance(scene: ShadowScene) -> np.ndarray:
    """(R, R) radiance ρ E(p)/π of the Lambertian plane without the occluder: E = E_sun cos θ (directional) or
    I cos θ/d² (spot; its cone's falloff is 1 on the view — checked), the engines' and the reference's alike; for
    :class:`DiscShadowScene` the disc's E by quadrature (:func:`_disc_irradiance`)."""
    p = scene.surface_points()
    li, rho = scene.light, float(np.mean(scene.material.base_color))
    if isinstance(scene, DiscShadowScene):
        return rho * _disc_irradiance(scene, p.reshape(-1, 3)).reshape(p.shape[:2]) / np.pi
    if isinstance(li, DirectionalLight):
        return np.full(p.shape[:2], rho * li.intensity * max(-li.unit_direction()[2], 0.0) / np.pi)
    v = np.asarray(li.position) - p
    d = np.linalg.norm(v, axis=-1)
    if np.any(li.falloff((-v / d[..., None]) @ li.unit_direction()) < 1.0):
        raise ValidateError(f"{scene.name}: part of the view lies outside the spot's inner cone")
    return rho * li.intensity * (v[..., 2] / d) / d**2 / np.pi


def _disc_irradiance(scene: DiscShadowScene, p: np.ndarray, n: int = DISC_NODES) -> np.ndarray:
    """(N,) E(p) = L ∫ cos θ_p cos θ_l / d² dA over the disc emitter, n² equal-area nodes (upward plane normal)."""
    c, normal, r, radiance = scene.emitter_disc()
    u, v = _frame(normal)
    disc = _disc_samples(n)
    q = c + r * (disc[:, :1] * u + disc[:, 1:] * v)
    out = np.empty(len(p))
    for k in range(0, len(p), 256):
        d = q[None] - p[k:k + 256, None]
        t = np.linalg.norm(d, axis=-1)
        cos_p, cos_l = np.clip(d[..., 2] / t, 0.0, None), np.clip(-(d @ normal) / t, 0.0, None)
        out[k:k + 256] = (cos_p * cos_l / t**2).sum(axis=1)
    return radiance * out * np.pi * r * r / len(q)


def _disc_samples(n: int) -> np.ndarray:
    """(n², 2) points of the unit disc, equal-area (concentric rings of a regular polar grid)."""
    i, j = np.meshgrid((np.arange(n) + 0.5) / n, (np.arange(n) + 0.5) / n, indexing="ij")
    r, phi = np.sqrt(i.ravel()), 2 * np.pi * j.ravel() + np.pi * i.ravel()
    return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=-1)


def _frame(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    a = np.array([0.0, 1.0, 0.0]) if abs(w[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    u = np.cross(a, w)
    u /= np.linalg.norm(u)
    return u, np.cross(w, u)


def visibility(scene: ShadowScene, n: int = VISIBILITY_SAMPLES) -> np.ndarray:
    """(R, R) fraction of the light visible from each pixel's surface point, cos θ-weighted: n² equal-area samples
    of the light's disc (directional: the cone of half-angle α about −direction; spot: the sphere's silhouette
    disc, radius r, facing the point; :class:`DiscShadowScene`: the disc itself) tested against the occluder's slabs
    (Kay–Kajiya)."""
    p = scene.surface_points().reshape(-1, 3)
    c, r, _ = scene.emitter_sphere()
    lo, hi = scene.occluder.bounds()
    disc = _disc_samples(n)
    if isinstance(scene.light, DirectionalLight):
        w = -scene.light.unit_direction()
        u, v = _frame(w)
        t = np.tan(np.radians(scene.light_size))
        dirs = w + t * (disc[:, :1] * u + disc[:, 1:] * v)
        dirs = np.broadcast_to(dirs / np.linalg.norm(dirs, axis=-1, keepdims=True), (p.shape[0], *dirs.shape))
        tmax = np.full(dirs.shape[:2], np.inf)
    else:
        frame = _frame(scene.emitter_disc()[1]) if isinstance(scene, DiscShadowScene) else None
        vis = np.empty(p.shape[0])
        for k in range(p.shape[0]):
            vis[k] = _visible_fraction(p[k], c, r, disc, lo, hi, frame)
        return vis.reshape(scene.resolution, scene.resolution)
    return _slab_visible(p[:, None, :], dirs, tmax, lo, hi).reshape(scene.resolution, scene.resolution)


def _visible_fraction(p: np.ndarray, c: np.ndarray, r: float, disc: np.ndarray, lo: np.ndarray,
                      hi: np.ndarray, frame: tuple[np.ndarray, np.ndarray] | None = None) -> float:
    """The visible fraction of a disc of radius r about c: the sphere's silhouette facing p, or a fixed disc whose
    plane is spanned by ``frame``."""
    w = c - p
    u, v = _frame(w / np.linalg.norm(w)) if frame is None else frame
    q = c + r * (disc[:, :1] * u + disc[:, 1:] * v)
    d = q - p
    t = np.linalg.norm(d, axis=-1)
    return float(_slab_visible(p[None, None, :], (d / t[:, None])[None], t[None], lo, hi)[0])


def _slab_visible(o: np.ndarray, d: np.ndarray, tmax: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(N,) cos-weighted fraction of the rays o + t d (t < tmax; d (N, K, 3)) that miss the box [lo, hi]."""
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / d
        t0, t1 = (lo - o) * inv, (hi - o) * inv
    tn = np.nanmax(np.minimum(t0, t1), axis=-1)
    tf = np.nanmin(np.maximum(t0, t1), axis=-1)
    blocked = (tn <= tf) & (tf > 0) & (tn < tmax)
    cos = np.clip(d[..., 2], 0.0, None)
    return (cos * ~blocked).sum(-1) / cos.sum(-1)


def regions(scene: ShadowScene, vis: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """(R, R) bool masks from :func:`visibility`: ``lit`` (the whole light visible, 2 px or more from any pixel that
    is not), ``penumbra`` (0 < visible < 1), ``umbra`` (nothing visible, 1 px or more inside)."""
    from scipy import ndimage

    v = visibility(scene) if vis is None else vis
    lit, umbra = v >= 1.0 - 1e-12, v <= 1e-12
    return {"lit": ndimage.binary_erosion(lit, iterations=2, border_value=1),
            "penumbra": ~lit & ~umbra, "umbra": ndimage.binary_erosion(umbra, iterations=1, border_value=1)}
