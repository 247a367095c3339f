"""Scenes of the überlight experiment: a diffuse wall and floor with a sphere, lit by a shaped beam.

Conventions: y is up, metres, linear grey RGB; every surface is Lambertian (Mitsuba ``diffuse``).

Geometry: floor y = 0 (x, z ∈ [−3, 3], normal +y), back wall z = −2.5 (x ∈ [−3, 3], y ∈ [0, 3.5],
normal +z), a sphere on the floor in the beam (``with_object``). The camera looks at the lit corner.

Light frame (Mitsuba's ``look_at(position, target, up = +y)``): x → left = normalise(up × f),
y → up' = f × left, z → forward f = normalise(target − position). "Light coordinates" of the
überlight [1] are the coordinates of a point in this frame with the origin at ``position``.

Luminaires (``kind``):

* ``projector``: Mitsuba's ``projector`` emitter [2] at ``position``, same frame, a square bitmap
  texture over the horizontal field of view ``fov_deg`` (supplied by the experiment: the überlight's
  angular mask; see :mod:`validate.reference.uberlight_render` for the radiometry).
* ``barndoor``: a physical barn-door luminaire: a Lambertian ``disk`` emitter of radius r and
  radiance L at ``position`` facing forward, at the back of a black box housing of depth h whose
  front plate (at ``position + h·f``) has a rectangular aperture of half sizes (a_x, a_y) along
  (left, up'). The plate is four black rectangles around the hole, the housing four black side
  walls; black = ``diffuse`` with reflectance 0. A receiver at light depth Z sees a disc point at
  lateral offset x_d through the aperture edge iff (x/Z)·h < a − x_d(1 − h/Z): in tan-space
  t = x/Z the beam is fully lit to t = (a − r(1 − h/Z))/h and dark beyond (a + r(1 − h/Z))/h — a
  penumbra of width 2r(1 − h/Z)/h centred on a/h. With ``aperture_roundness`` ρ > 0 the hole is the
  superellipse |x/a_x|^{2/ρ} + |y/a_y|^{2/ρ} = 1 — the überlight's own shape family — and the plate a
  triangle mesh (OBJ written once to the temp folder, :func:`rounded_plate_obj`).

References
  [1] R. Rost, *OpenGL Shading Language*, 2nd ed., §12.4 "The ÜberLight Shader", Listings 12.6/12.7.
  [2] Mitsuba 3 documentation and src/emitters/projector.cpp (``projector``); ``disk`` + ``area``.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ..errors import ValidateError
from .camera import PerspectiveCamera

ALBEDO = {"floor": 0.5, "wall": 0.7, "object": 0.6}
FLOOR_HALF = 3.0
WALL_Z = -2.5
WALL_TOP = 3.5
SPHERE = {"center": (0.35, 0.45, -1.3), "radius": 0.45}
PLATE_HALF = 0.25  # m: half size of the barn-door front plate and housing (the hole is inside it)
LIGHT_POSITION = (0.0, 2.2, 2.6)
LIGHT_TARGET = (0.0, 1.0, -2.5)


def look_at_frame(position: tuple[float, ...], target: tuple[float, ...]) -> np.ndarray:
    """(3, 3) rows (left, up', forward) of Mitsuba's look_at(position, target, up = +y), float64."""
    f = np.asarray(target, dtype=np.float64) - np.asarray(position, dtype=np.float64)
    f /= np.linalg.norm(f)
    left = np.cross([0.0, 1.0, 0.0], f)
    left /= np.linalg.norm(left)
    return np.stack([left, np.cross(f, left), f])


@dataclass(frozen=True)
class Camera(PerspectiveCamera):
    origin: tuple[float, float, float] = (2.2, 2.6, 4.6)
    target: tuple[float, float, float] = (-0.1, 0.7, -1.6)
    fov_deg: float = 58.0  # horizontal
    width: int = 96
    height: int = 72


@dataclass(frozen=True)
class Luminaire:
    """``projector`` (fov_deg) or ``barndoor`` (radius r, depth h, half aperture (a_x, a_y), radiance L)."""

    kind: str
    position: tuple[float, float, float] = LIGHT_POSITION
    target: tuple[float, float, float] = LIGHT_TARGET
    fov_deg: float = 70.0
    radius: float = 0.05
    depth: float = 0.25
    aperture: tuple[float, float] = (0.08, 0.06)
    radiance: float = 2.0e3
    aperture_roundness: float = 0.0  # 0: the rectangle; > 0: the superellipse hole |x/a_x|^{2/ρ} + |y/a_y|^{2/ρ} = 1

    def __post_init__(self) -> None:
        if self.kind not in ("projector", "barndoor"):
            raise ValidateError(f"überlight luminaire kind {self.kind!r}; accepted: projector, barndoor")
        if self.kind == "barndoor":
            ax, ay = self.aperture
            if not (0 < self.radius and 0 < self.depth and 0 < ax < PLATE_HALF and 0 < ay < PLATE_HALF
                    and self.radius < PLATE_HALF):
                raise ValidateError(f"barn-door luminaire r={self.radius}, h={self.depth}, a={self.aperture}: "
                                    f"need positive sizes with r and a below the plate half size {PLATE_HALF} m")

    def frame(self) -> np.ndarray:
        return look_at_frame(self.position, self.target)

    def intensity(self) -> float:
        """On-axis radiant intensity of the barn-door disc seen whole: I₀ = L π r² (W sr⁻¹)."""
        return float(self.radiance * np.pi * self.radius ** 2)

    def penumbra_tan(self, depth: float) -> tuple[float, float]:
        """(inner, outer) tan-space edges of the beam along x at light depth Z (module docstring)."""
        k = self.radius * (1.0 - self.depth / depth)
        a = self.aperture[0]
        return (a - k) / self.depth, (a + k) / self.depth

    def _local(self) -> Any:
        import mitsuba as mi

        return mi.ScalarTransform4f().look_at(origin=list(self.position), target=list(self.target), up=[0, 1, 0])

    def barndoor_shapes(self) -> dict[str, dict[str, Any]]:
        """The disc emitter, the front plate (4 strips around the hole) and the 4 housing walls."""
        import mitsuba as mi

        T = mi.ScalarTransform4f
        base, h, p = self._local(), self.depth, PLATE_HALF
        ax, ay = self.aperture
        black = {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.0}}
        out: dict[str, dict[str, Any]] = {
            "lamp_disc": {"type": "disk", "to_world": base @ T().scale([self.radius, self.radius, 1.0]),
                          "emitter": {"type": "area", "radiance": {"type": "rgb", "value": float(self.radiance)}}}}
        if self.aperture_roundness > 0:
            out["plate"] = {"type": "obj", "filename": rounded_plate_obj(ax, ay, self.aperture_roundness, p, h),
                            "bsdf": black, "to_world": base, "face_normals": True}
            strips: dict[str, tuple[float, float, float, float]] = {}
        else:
            # front plate: rectangles [x0, x1] × [y0, y1] at local z = h (the rectangle is [−1, 1]² in z = 0)
                strips = {"left": (ax, p, -p, p), "right": (-p, -ax, -p, p), "top": (-ax, ax, ay, p),
                      "bottom": (-ax, ax, -p, -ay)}
        for name, (x0, x1, y0, y1) in strips.items():
            out[f"plate_{name}"] = {"type": "rectangle", "bsdf": black, "to_world": base @ T().translate(
                [(x0 + x1) / 2, (y0 + y1) / 2, h]) @ T().scale([(x1 - x0) / 2, (y1 - y0) / 2, 1.0])}
        # housing walls x = ±p (rectangle rotated about y: local x → ∓z) and y = ±p (about x: local y → z)
        for name, (shift, axis, scale) in {
                "x_pos": ([p, 0.0], [0, 1, 0], [h / 2, p, 1.0]), "x_neg": ([-p, 0.0], [0, 1, 0], [h / 2, p, 1.0]),
                "y_pos": ([0.0, p], [1, 0, 0], [p, h / 2, 1.0]), "y_neg": ([0.0, -p], [1, 0, 0], [p, h / 2, 1.0])
        }.items():
            out[f"housing_{name}"] = {"type": "rectangle", "bsdf": black, "to_world": base @ T().translate(
                [shift[0], shift[1], h / 2]) @ T().rotate(axis, 90.0) @ T().scale(scale)}
        return out


def rounded_plate_obj(ax: float, ay: float, roundness: float, half: float, z: float, n: int = 512) -> str:
    """Path of an OBJ file (written once, keyed by its parameters) of the plate [−half, half]² at local depth z
    with the superellipse hole |x/a_x|^{2/ρ} + |y/a_y|^{2/ρ} = 1: a strip of quads between the hole's contour
    c(t) = (a_x sgn(cos t)|cos t|^ρ, a_y sgn(sin t)|sin t|^ρ) and the square's o(t) (the ray at polar angle t),
    t = 2πk/n with n divisible by 8 so that the square's corners are vertices (no gap at the corners)."""
    import tempfile
    from pathlib import Path

    if n % 8 or not 0 < roundness <= 2 or not (0 < ax < half and 0 < ay < half):
        raise ValidateError(f"rounded aperture a=({ax}, {ay}), ρ={roundness}, plate {half}: need 0 < a < plate, "
                            "0 < ρ ≤ 2")
    t = 2 * np.pi * np.arange(n) / n
    c, s = np.cos(t), np.sin(t)
    inner = np.stack([ax * np.sign(c) * np.abs(c) ** roundness, ay * np.sign(s) * np.abs(s) ** roundness], 1)
    scale = half / np.maximum(np.abs(c), np.abs(s))
    outer = np.stack([c * scale, s * scale], 1)
    key = hashlib.sha256(json.dumps([ax, ay, roundness, half, z, n]).encode()).hexdigest()[:16]
    path = Path(tempfile.gettempdir()) / "validate_uberlight" / f"plate_{key}.obj"
    if not path.exists():
        lines = [f"v {x:.9f} {y:.9f} {z:.9f}" for x, y in np.concatenate([inner, outer])]
        for k in range(n):
            k1 = (k + 1) % n
            lines += [f"f {k + 1} {n + k + 1} {n + k1 + 1}", f"f {k + 1} {n + k1 + 1} {k1 + 1}"]
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".{np.random.default_rng().integers(1 << 30)}.tmp")
        tmp.write_text("\n".join(lines) + "\n")
        tmp.replace(path)
    return str(path)


@dataclass(frozen=True)
class UberScene:
    """Floor, wall (and sphere) + one luminaire + camera; ``parts()`` is the cache key."""

    luminaire: Luminaire
    camera: Camera = field(default_factory=Camera)
    with_object: bool = True
    name: str = "uberlight"

    def parts(self) -> dict[str, Any]:
        return {"name": self.name, "luminaire": asdict(self.luminaire), "camera": asdict(self.camera),
                "object": self.with_object, "geometry": [ALBEDO, FLOOR_HALF, WALL_Z, WALL_TOP, SPHERE, PLATE_HALF]}

    def digest(self) -> str:
        return hashlib.sha256(json.dumps(self.parts(), sort_keys=True).encode()).hexdigest()[:16]

    def receivers(self) -> dict[str, dict[str, Any]]:
        """Mitsuba dicts of the floor, the wall and (``with_object``) the sphere."""
        import mitsuba as mi

        T = mi.ScalarTransform4f

        def diffuse(name: str) -> dict[str, Any]:
            return {"type": "diffuse", "reflectance": {"type": "rgb", "value": ALBEDO[name]}}

        half_h = WALL_TOP / 2
        shapes: dict[str, dict[str, Any]] = {
            "floor": {"type": "rectangle", "bsdf": diffuse("floor"),
                      "to_world": T().rotate([1, 0, 0], -90).scale(FLOOR_HALF)},
            "wall": {"type": "rectangle", "bsdf": diffuse("wall"),
                     "to_world": T().translate([0.0, half_h, WALL_Z]).scale([FLOOR_HALF, half_h, 1.0])}}
        if self.with_object:
            shapes["object"] = {"type": "sphere", "center": list(SPHERE["center"]), "radius": SPHERE["radius"],
                                "bsdf": diffuse("object")}
        return shapes

    def mitsuba_dict(self, texture: np.ndarray | None = None, with_light: bool = True) -> dict[str, Any]:
        """The scene; a ``projector`` needs its (n, n) irradiance ``texture`` (see uberlight_render)."""
        import mitsuba as mi

        d: dict[str, Any] = {"type": "scene", **self.receivers(), "sensor": self.camera.mitsuba()}
        lum = self.luminaire
        if lum.kind == "barndoor":
            shapes = lum.barndoor_shapes()
            if not with_light:
                shapes.pop("lamp_disc")
            d.update(shapes)
        elif with_light:
            if texture is None or texture.ndim != 2 or texture.shape[0] != texture.shape[1]:
                raise ValidateError("überlight projector scene: needs a square 2-D irradiance texture")
            rgb = np.repeat(np.ascontiguousarray(texture, dtype=np.float32)[..., None], 3, axis=2)
            d["projector"] = {"type": "projector", "fov": float(lum.fov_deg), "to_world": lum._local(),
                              "irradiance": {"type": "bitmap", "bitmap": mi.Bitmap(rgb), "raw": True,
                                             "filter_type": "bilinear", "wrap_mode": "clamp"}}
        return d


def projector_scene(width: int, height: int, fov_deg: float = 70.0) -> UberScene:
    return UberScene(Luminaire("projector", fov_deg=fov_deg), Camera(width=width, height=height), True,
                     "projector")


def barndoor_scene(width: int, height: int, radius: float, depth: float, aperture: tuple[float, float],
                   radiance: float, aperture_roundness: float = 0.0) -> UberScene:
    """The barn-door luminaire over the bare wall and floor (no sphere: its own penumbra is the
    ``shadows`` experiment's subject; here only the beam's edge is measured)."""
    lum = Luminaire("barndoor", radius=radius, depth=depth, aperture=aperture, radiance=radiance,
                    aperture_roundness=aperture_roundness)
    name = f"barndoor_r{radius:g}" + (f"_rounded{aperture_roundness:g}" if aperture_roundness > 0 else "")
    return UberScene(lum, Camera(width=width, height=height), False, name)
