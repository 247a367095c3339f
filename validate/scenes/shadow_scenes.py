"""Shadow test scenes: a ground plane, four occluders and a disc area light, as Mitsuba scene dicts.

Conventions: y is up, units are metres, every surface is Lambertian (``diffuse``). The scene is
direct lighting only: the one emitter is a one-sided ``disk`` shape with an ``area`` emitter of
uniform radiance L_e, centred at ``light.centre`` at height h, facing ``light.target``. There is no
environment (the issue's optional dim environment is left out on purpose): a point that sees none of
the disc is exactly black in the reference, so any light in the umbra is a shadow-map leak.

Occluders (chosen so every shadow-mapping failure has somewhere to show):

* a floating sphere (radius 0.45, bottom 0.55 m above the ground): a detached shadow whose
  penumbra widens with the gap, and a curved terminator where slope-scaled bias matters;
* a box (0.8 m cube turned 30° about y) standing on the ground: contact shadows, where too much
  bias detaches the shadow from the caster ("peter-panning");
* a thin pole (radius 4 cm, 1.6 m tall, a ``cylinder`` closed by a ``disk`` cap, since the camera
  would otherwise see the black back faces inside it): a shadow a few shadow-map texels wide that
  low resolutions lose;
* steps (three 0.35 m treads rising 0.25 m each towards the light, a triangle mesh): each riser
  shadows part of the tread below it, and the risers face away from the light (a terminator between
  lit and back-facing faces one texel apart in the shadow map).

Light power: the radiance is set from the radius so that the irradiance on the light's axis at the
target stays ``target_irradiance`` for every radius, E_axis = π L_e r² / (r² + d²) (the exact
on-axis disc formula), so renders with different radii differ only in their shadows.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ..errors import ValidateError
from .camera import PerspectiveCamera

LIGHT_CENTRE = (1.6, 4.0, 1.6)  # height h = 4 m, in front and to the right: shadows fall back and left
LIGHT_TARGET = (0.0, 0.0, 0.0)
LIGHT_RADII = (0.02, 0.1, 0.25, 0.5, 1.0)  # near-point (r/d = 0.0043) … large (r/d = 0.22), d = 4.6 m
NEAR_POINT_RADIUS = LIGHT_RADII[0]
TARGET_IRRADIANCE = 3.0  # W/m² on the light axis at the target, for every radius

GROUND_HALF_SIZE = 5.0
SPHERE = {"center": (-1.3, 1.0, 0.8), "radius": 0.45}
BOX = {"center": (1.2, 0.4, -0.7), "half_size": 0.4, "yaw_deg": 30.0}
POLE = {"base": (0.3, 0.0, 1.2), "height": 1.6, "radius": 0.04}
STEPS = {"origin": (-0.5, 0.0, -2.0), "tread": 0.35, "rise": 0.25, "count": 3, "width": 1.0}

ALBEDO = {  # diffuse reflectance (linear RGB) per shape
    "ground": (0.7, 0.7, 0.7),
    "sphere": (0.8, 0.35, 0.3),
    "box": (0.3, 0.45, 0.8),
    "pole": (0.8, 0.8, 0.4),
    "steps": (0.4, 0.75, 0.4),
}


@dataclass(frozen=True)
class DiscLight:
    """A one-sided disc of radius ``radius`` centred at ``centre``, facing ``target``, radiance L_e."""

    centre: tuple[float, float, float]
    target: tuple[float, float, float]
    radius: float
    radiance: float

    def __post_init__(self) -> None:
        if not (np.isfinite(self.radius) and self.radius > 0):
            raise ValidateError(f"disc light radius {self.radius}: must be a finite number > 0")
        if not (np.isfinite(self.radiance) and self.radiance > 0):
            raise ValidateError(f"disc light radiance {self.radiance}: must be a finite number > 0")
        if np.linalg.norm(np.subtract(self.target, self.centre)) <= 0:
            raise ValidateError("disc light: centre and target coincide; the facing direction is undefined")

    @property
    def normal(self) -> np.ndarray:
        """Unit normal n_L of the emitting side (from the centre towards the target)."""
        d = np.subtract(self.target, self.centre).astype(np.float64)
        return d / np.linalg.norm(d)

    @property
    def area(self) -> float:
        return float(np.pi * self.radius**2)

    def frame(self) -> tuple[np.ndarray, np.ndarray]:
        """Two unit vectors (a, b) spanning the disc plane, with a × b = n_L."""
        n = self.normal
        helper = np.array([0.0, 1.0, 0.0]) if abs(n[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
        a = np.cross(helper, n)
        a /= np.linalg.norm(a)
        return a, np.cross(n, a)

    def mitsuba_shape(self) -> dict[str, Any]:
        """A ``disk`` (unit disc in local z = 0, normal +z) mapped by look_at (local +z → n_L)."""
        import mitsuba as mi

        up = [0.0, 1.0, 0.0] if abs(self.normal[1]) < 0.9 else [1.0, 0.0, 0.0]
        to_world = mi.ScalarTransform4f().look_at(origin=list(self.centre), target=list(self.target), up=up)
        return {"type": "disk", "to_world": to_world @ mi.ScalarTransform4f().scale(self.radius),
                "emitter": {"type": "area", "radiance": {"type": "rgb", "value": float(self.radiance)}}}


def radiance_for_irradiance(radius: float, distance: float, irradiance: float) -> float:
    """L_e such that a facing disc gives E = π L_e r² / (r² + d²) = ``irradiance`` on its axis."""
    return float(irradiance * (radius**2 + distance**2) / (np.pi * radius**2))


@dataclass(frozen=True)
class Camera(PerspectiveCamera):
    origin: tuple[float, float, float] = (0.0, 4.0, 5.6)
    target: tuple[float, float, float] = (-0.4, 0.2, -0.5)
    fov_deg: float = 44.0  # horizontal
    width: int = 160
    height: int = 120


@dataclass(frozen=True)
class ShadowScene:
    """Ground + occluders + one disc light + a camera. ``parts()`` is the cache key."""

    light: DiscLight
    camera: Camera = field(default_factory=Camera)
    name: str = "occluders"

    def parts(self) -> dict[str, Any]:
        return {"name": self.name, "light": asdict(self.light), "camera": asdict(self.camera),
                "geometry": geometry_parts()}

    def digest(self) -> str:
        blob = json.dumps(self.parts(), sort_keys=True).encode()
        return hashlib.sha256(blob).hexdigest()[:16]

    def geometry_dict(self) -> dict[str, Any]:
        """Every shape except the light (the shadow-map rasteriser's and the visibility rays' scene)."""
        return occluder_shapes()

    def mitsuba_dict(self, with_light: bool = True, with_sensor: bool = True) -> dict[str, Any]:
        d: dict[str, Any] = {"type": "scene", **self.geometry_dict()}
        if with_light:
            d["light"] = self.light.mitsuba_shape()
        if with_sensor:
            d["sensor"] = self.camera.mitsuba_sensor()
        return d


def geometry_parts() -> dict[str, Any]:
    return {"ground": GROUND_HALF_SIZE, "sphere": SPHERE, "box": BOX, "pole": POLE, "steps": STEPS,
            "albedo": ALBEDO}


def _diffuse(name: str) -> dict[str, Any]:
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(ALBEDO[name])}}


def steps_mesh_arrays(origin: tuple[float, float, float], tread: float, rise: float, count: int,
                      width: float) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (V, 3), faces (F, 3)) of a staircase with outward-facing triangles.

    The profile lies in the x–y plane: step k (k = 0 … count−1) spans x ∈ [k·tread, count·tread] and
    y ∈ [0, (k+1)·rise], so the staircase rises towards +x; it is extruded over z ∈ [0, width]. Every
    face has its own vertices (flat normals). Winding: counter-clockwise seen from outside. There is
    no bottom face: the staircase stands on the ground, and a face coplanar with it would only invite
    ties.
    """
    ox, oy, oz = origin
    quads: list[list[tuple[float, float, float]]] = []

    def quad(p0: tuple, p1: tuple, p2: tuple, p3: tuple) -> None:
        quads.append([p0, p1, p2, p3])

    z0, z1 = 0.0, width
    for k in range(count):
        x0, x1 = k * tread, (k + 1) * tread
        y_top = (k + 1) * rise
        # tread (top, +y) and riser (−x) of step k
        quad((x0, y_top, z1), (x1, y_top, z1), (x1, y_top, z0), (x0, y_top, z0))
        quad((x0, k * rise, z0), (x0, k * rise, z1), (x0, y_top, z1), (x0, y_top, z0))
        # front (+z) and back (−z) of the column under tread k
        quad((x0, 0.0, z1), (x1, 0.0, z1), (x1, y_top, z1), (x0, y_top, z1))
        quad((x1, 0.0, z0), (x0, 0.0, z0), (x0, y_top, z0), (x1, y_top, z0))
    xe, ye = count * tread, count * rise
    quad((xe, 0.0, z1), (xe, 0.0, z0), (xe, ye, z0), (xe, ye, z1))  # back wall (+x)
    verts = np.array([p for q in quads for p in q], dtype=np.float64) + np.array([ox, oy, oz])
    faces = []
    for i in range(len(quads)):
        b = 4 * i
        faces += [(b, b + 1, b + 2), (b, b + 2, b + 3)]
    return verts, np.array(faces, dtype=np.uint32)


def steps_mesh() -> Any:
    """The staircase as a Mitsuba mesh with its diffuse BSDF."""
    import drjit as dr
    import mitsuba as mi

    v, f = steps_mesh_arrays(STEPS["origin"], STEPS["tread"], STEPS["rise"], STEPS["count"], STEPS["width"])
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(_diffuse("steps"))
    mesh = mi.Mesh("steps", v.shape[0], f.shape[0], props=props, has_vertex_normals=False)
    params = mi.traverse(mesh)
    params["vertex_positions"] = dr.ravel(mi.Point3f(*[mi.Float(v[:, i].astype(np.float32)) for i in range(3)]))
    params["faces"] = dr.ravel(mi.Vector3u(*[mi.UInt32(f[:, i]) for i in range(3)]))
    params.update()
    return mesh


def occluder_shapes() -> dict[str, Any]:
    """Mitsuba dicts of the ground and the four occluders (no light, no sensor)."""
    import mitsuba as mi

    T = mi.ScalarTransform4f
    bx = BOX
    pole = POLE
    base = np.array(pole["base"])
    return {
        "ground": {"type": "rectangle", "bsdf": _diffuse("ground"),
                   "to_world": T().rotate([1, 0, 0], -90).scale(GROUND_HALF_SIZE)},
        "sphere": {"type": "sphere", "center": list(SPHERE["center"]), "radius": SPHERE["radius"],
                   "bsdf": _diffuse("sphere")},
        "box": {"type": "cube", "bsdf": _diffuse("box"),
                "to_world": T().translate(list(bx["center"])).rotate([0, 1, 0], bx["yaw_deg"])
                .scale(bx["half_size"])},
        "pole": {"type": "cylinder", "p0": base.tolist(), "p1": (base + [0, pole["height"], 0]).tolist(),
                 "radius": pole["radius"], "bsdf": _diffuse("pole")},
        "pole_cap": {"type": "disk", "bsdf": _diffuse("pole"),  # closes the open cylinder's top
                     "to_world": T().translate((base + [0, pole["height"], 0]).tolist()).rotate([1, 0, 0], -90)
                     .scale(pole["radius"])},
        "steps": steps_mesh(),
    }


def shadow_scene(radius: float, width: int = 160, height: int = 120,
                 target_irradiance: float = TARGET_IRRADIANCE) -> ShadowScene:
    """The standard scene with a disc light of ``radius`` (m) at LIGHT_CENTRE facing LIGHT_TARGET."""
    if not (np.isfinite(radius) and radius > 0):
        raise ValidateError(f"light radius {radius}: must be a finite number > 0")
    d = float(np.linalg.norm(np.subtract(LIGHT_TARGET, LIGHT_CENTRE)))
    if radius > 0.5 * d:
        raise ValidateError(f"light radius {radius}: must be at most half the light's distance {d:.2f} m")
    light = DiscLight(LIGHT_CENTRE, LIGHT_TARGET, float(radius), radiance_for_irradiance(radius, d, target_irradiance))
    return ShadowScene(light, Camera(width=width, height=height))
