"""Mitsuba scenes that measure irradiance: one light (or sky) and one small receiver disc.

Every scene holds a single ``disk`` shape named ``receiver`` (radius ε, :data:`RECEIVER_FRACTION`
of the light distance) carrying Mitsuba's ``irradiancemeter`` sensor, which samples a point on the
disc uniformly and a direction cosine-weighted about the disc's normal (local +z) and weights the
incident radiance by π, i.e. estimates E = ∫ L max(0, n·ω) dω averaged over the disc. The receiver
is re-oriented between renders (``receiver.to_world``) so one loaded scene serves every normal; it
never sees itself (a flat disc), and nothing else in the scene reflects: the integrator is ``path``
with ``max_depth = 1`` (emission seen directly along the sensor ray, no bounce).

Light scenes (geometry in world units, y up; the light is centred at the origin, the receiver at
(0, 0, d), so the direction from the receiver to the light is −z):

* :func:`sphere_light` — a ``sphere`` of radius r with an ``area`` emitter of radiance L: from any
  point at distance d it is a uniform cap of angular radius σ, sin σ = r/d.
* :func:`disc_light` — a ``disk`` of radius r in the plane z = 0, normal +z (Mitsuba area emitters
  are one-sided: they radiate on the side of the normal), facing the receiver on its axis: a uniform
  cap with tan σ = r/d, sin²σ = r²/(r² + d²), seen from the axis. (Off the axis it is not a cap; the
  receiver's radius ε = 10⁻³ d keeps the average over the receiver within ~ε²/d² = 10⁻⁶ of the axis.)

Sky scenes: :func:`sky` wraps any :class:`~validate.scenes.environment.Environment` (the two-tone
sky, ``sunsky`` sky + sun of :mod:`validate.scenes.procedural`) with the receiver at the origin.

Receiver normals: :func:`tilted_normals` returns unit normals at angles θ from an axis (the light
direction, or "up"), turned in the plane spanned by the axis and a chosen perpendicular direction.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ValidateError
from .environment import Environment

RECEIVER_FRACTION = 1e-3  # receiver radius / light distance: averaging bias ~ (ε/d)² = 1e-6 relative
FILM_SIZE = 32  # film pixels per side: stratifies the receiver position; keeps float32 accumulation short
INTEGRATOR = {"type": "path", "max_depth": 1}
SKY_RECEIVER_RADIUS = 1e-3  # the sky is at infinity: any small radius works


@dataclass(frozen=True, eq=False)
class MeterScene:
    """A Mitsuba scene dict with an irradiance meter on the disc ``receiver``, plus what it means.

    ``position``: the receiver's centre; ``light_direction``: unit vector from the receiver towards
    the light's centre (None for skies); ``sin2_sigma``: the cap's sin²σ seen from the receiver
    (None for skies); ``key``: a JSON-able description (the cache key of its measurements).
    """

    name: str
    scene: dict
    position: np.ndarray
    receiver_radius: float
    light_direction: np.ndarray | None = None
    sin2_sigma: float | None = None
    radiance: float = 1.0
    key: dict = field(default_factory=dict)


def _film(size: int) -> dict:
    return {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"}, "pixel_format": "rgb"}


def receiver_to_world(position: np.ndarray, normal: np.ndarray, radius: float) -> Any:
    """Transform placing Mitsuba's unit disc (normal +z) at ``position`` with ``normal``, radius ε."""
    import mitsuba as mi

    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    p = np.asarray(position, dtype=np.float64)
    up = np.array([0.0, 1.0, 0.0]) if abs(n[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    return (mi.ScalarTransform4f().look_at(origin=p.tolist(), target=(p + n).tolist(), up=up.tolist())
            @ mi.ScalarTransform4f().scale([radius, radius, radius]))


def _receiver(position: np.ndarray, normal: np.ndarray, radius: float, film_size: int) -> dict:
    return {"type": "disk", "to_world": receiver_to_world(position, normal, radius),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}},
            "sensor": {"type": "irradiancemeter", "film": _film(film_size), "sampler": {"type": "independent"}}}


def _area(radiance: float) -> dict:
    if not (np.isfinite(radiance) and radiance > 0):
        raise ValidateError(f"area light: radiance must be finite and > 0, got {radiance}")
    return {"type": "area", "radiance": {"type": "rgb", "value": [float(radiance)] * 3}}


def sphere_light(radius: float, distance: float, radiance: float = 1.0, film_size: int = FILM_SIZE) -> MeterScene:
    """A spherical area light (radius r, centre at the origin) seen by a receiver at (0, 0, d)."""
    if not (radius > 0 and distance > radius):
        raise ValidateError(f"sphere light: need 0 < radius < distance, got radius={radius}, distance={distance}")
    pos = np.array([0.0, 0.0, float(distance)])
    eps = RECEIVER_FRACTION * distance
    scene = {"type": "scene", "integrator": dict(INTEGRATOR),
             "light": {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": float(radius),
                       "emitter": _area(radiance)},
             "receiver": _receiver(pos, -pos, eps, film_size)}
    return MeterScene(f"sphere_r{radius:g}_d{distance:g}", scene, pos, eps, np.array([0.0, 0.0, -1.0]),
                      radius * radius / (distance * distance), float(radiance),
                      {"light": "sphere", "radius": radius, "distance": distance, "radiance": radiance,
                       "film": film_size, "eps": eps})


def disc_light(radius: float, distance: float, radiance: float = 1.0, film_size: int = FILM_SIZE) -> MeterScene:
    """A one-sided disc light (radius r, in z = 0, normal +z) seen by a receiver on its axis at (0, 0, d)."""
    import mitsuba as mi

    if not (radius > 0 and distance > 0):
        raise ValidateError(f"disc light: need radius > 0 and distance > 0, got radius={radius}, distance={distance}")
    pos = np.array([0.0, 0.0, float(distance)])
    eps = RECEIVER_FRACTION * distance
    scene = {"type": "scene", "integrator": dict(INTEGRATOR),
             "light": {"type": "disk", "to_world": mi.ScalarTransform4f().scale([radius, radius, 1.0]),
                       "emitter": _area(radiance)},
             "receiver": _receiver(pos, -pos, eps, film_size)}
    return MeterScene(f"disc_r{radius:g}_d{distance:g}", scene, pos, eps, np.array([0.0, 0.0, -1.0]),
                      radius * radius / (radius * radius + distance * distance), float(radiance),
                      {"light": "disc", "radius": radius, "distance": distance, "radiance": radiance,
                       "film": film_size, "eps": eps})


def sky(env: Environment, film_size: int = FILM_SIZE) -> MeterScene:
    """The environment ``env`` (its Mitsuba ``envmap``) seen by a receiver at the origin."""
    pos = np.zeros(3)
    scene = {"type": "scene", "integrator": dict(INTEGRATOR), "sky": env.mitsuba_emitter(),
             "receiver": _receiver(pos, np.array([0.0, 1.0, 0.0]), SKY_RECEIVER_RADIUS, film_size)}
    return MeterScene(f"sky_{env.name}", scene, pos, SKY_RECEIVER_RADIUS,
                      key={"sky": env.name, "env": env.digest, "film": film_size})


def tilted_normals(thetas_deg: np.ndarray, axis: np.ndarray, towards: np.ndarray) -> np.ndarray:
    """Unit normals n(θ) = cos θ · axis + sin θ · t, t the unit part of ``towards`` ⟂ axis; (N, 3)."""
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    t = np.asarray(towards, dtype=np.float64)
    t = t - (t @ a) * a
    if np.linalg.norm(t) < 1e-9:
        raise ValidateError("tilted_normals: 'towards' must not be parallel to the axis")
    t = t / np.linalg.norm(t)
    th = np.radians(np.asarray(thetas_deg, dtype=np.float64))
    return np.cos(th)[:, None] * a[None, :] + np.sin(th)[:, None] * t[None, :]


def tube_geometry(light: Any, who: str) -> tuple[np.ndarray, np.ndarray, float, float]:
    """(centre, unit axis, length ℓ ≥ 0, radius R > 0) of a tube (capsule) light mapping {'center', 'axis', 'length',
    'radius'}: the segment centre ± (ℓ/2)·axis swept by a sphere of radius R. ``who`` names the caller in the one-line
    ValidateError on bad values."""
    c = np.asarray(light["center"], dtype=np.float64)
    a = np.asarray(light.get("axis", (0.0, 0.0, 0.0)), dtype=np.float64)
    length, radius = float(light.get("length", -1.0)), float(light.get("radius", 0.0))
    if a.shape != (3,) or not np.linalg.norm(a) > 0.0 or not length >= 0.0 or not radius > 0.0:
        raise ValidateError(f"{who}: tube needs 'axis' (3,) non-zero, 'length' >= 0 and 'radius' > 0; got "
                            f"axis={a.tolist()!r}, length={length!r}, radius={radius!r}")
    return c, a / np.linalg.norm(a), length, radius
