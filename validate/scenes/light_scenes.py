"""The classic-lights scene: a diffuse ground plane, a sphere and a box under textbook light sources.

Conventions: y is up, metres, linear RGB; every surface is Lambertian (Mitsuba ``diffuse``).
Intensities are physical: a point or spot light has a radiant intensity I in W sr⁻¹, a directional
light an irradiance E⊥ in W m⁻² on a plane facing it, an area light a radiance L in W m⁻² sr⁻¹.
Receivers see, for a light at distance d and angle θ to their normal, E = I cos θ / d² (point [1]
eq. 6.37–6.40), E = E⊥ cos θ (directional), E = ∫ L cos θ dω (area lights [1] eq. 6.44).

Light kinds and their Mitsuba emitters (Mitsuba 3 plugin documentation [2]):

* ``point``: ``point`` emitter, ``position``, ``intensity`` (W sr⁻¹);
* ``spot``: ``spot`` emitter at ``position`` looking at ``target``, ``intensity`` on the axis,
  ``cutoff_angle`` and ``beam_width`` in degrees. Mitsuba's profile (src/emitters/spot.cpp,
  ``falloff_curve``): 1 for α ≤ beam_width, (cutoff − α)/(cutoff − beam_width) between (linear in
  the angle α, not in cos α), 0 beyond the cutoff;
* ``directional``: ``directional`` emitter, ``direction`` (where the light travels), ``irradiance``;
* ``rectangle`` / ``disk``: the Mitsuba shape (unit square [−1, 1]² or unit disc in local z = 0,
  normal +z) mapped by ``look_at(position, target, up)`` and scaled by the half sizes / the radius,
  with an ``area`` emitter of radiance L (one-sided: it emits on the side its normal points to);
* ``sphere``: a ``sphere`` shape of ``radius`` at ``position`` with an ``area`` emitter (emits
  outward everywhere);
* ``lamp``: a real spot lamp — a ``disk`` emitter of radius r at the closed end of a black open
  ``cylinder`` (the aperture) of radius a ≥ r and depth h, whose mouth is centred at ``position`` and
  faces ``target`` (``size`` = (r, h, a)). Seen from far away it is a spot whose intensity is the
  emitter's area visible through the mouth (a ray from a disc point leaves through the mouth circle
  or is stopped by the wall): I(α) = L cos α · A(h tan α), A(δ) the overlap of a disc of radius r and
  one of radius a whose centres are δ apart; flat to tan α = (a − r)/h, zero beyond (a + r)/h.
  (a slightly larger than r keeps the disc's rim off the wall, where Mitsuba's shadow rays to rim
  points grazing the wall would leak.)

``look_at`` frame (Mitsuba's ``Transform4f.look_at``): forward f = normalise(target − origin),
left l = normalise(up × f), up' = f × l; local x → l, y → up', z → f. :meth:`Light.frame` computes
the same vectors in float64 so local models receive the corners/axes of the very shape Mitsuba
renders.

References
  [1] F. Ganovelli, S. Corsini, S. Pattanaik, M. Di Benedetto, *Introduction to Computer Graphics:
      A Practical Learning Approach*, CRC 2014, ch. 6 (eq. 6.37–6.49).
  [2] Mitsuba 3 documentation, "Emitters": point, spot, directional, area.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np

from ..errors import ValidateError
from .camera import PerspectiveCamera

KINDS = ("point", "spot", "directional", "rectangle", "disk", "sphere", "lamp")
AREA_KINDS = ("rectangle", "disk", "sphere")
SHAPED_KINDS = AREA_KINDS + ("lamp",)  # lights with geometry (they cast shadows on the others)

GROUND_HALF_SIZE = 3.0
SPHERE = {"center": (-0.7, 0.5, 0.3), "radius": 0.5}
BOX = {"center": (0.8, 0.35, -0.4), "half_size": 0.35, "yaw_deg": 25.0}
ALBEDO = {"ground": (0.6, 0.6, 0.6), "sphere": (0.8, 0.4, 0.3), "box": (0.3, 0.5, 0.8)}


@dataclass(frozen=True)
class Light:
    """One light. ``position``: point/spot position or area-light centre; ``target``: where a spot or a
    rectangle/disc faces (unused by point and sphere); ``direction``: where a directional light's
    light travels. ``power`` is I (W/sr) for point/spot, E⊥ (W/m²) for directional, L (W/(m² sr)) for
    area lights. ``size``: (half width, half height) of a rectangle, (radius,) of a disc or sphere."""

    kind: str
    power: float
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    target: tuple[float, float, float] = (0.0, 0.0, 0.0)
    direction: tuple[float, float, float] = (0.0, -1.0, 0.0)
    size: tuple[float, ...] = ()
    cutoff_deg: float = 20.0
    beam_deg: float = 15.0

    def __post_init__(self) -> None:
        where = f"light {self.kind!r}"
        if self.kind not in KINDS:
            raise ValidateError(f"{where}: unknown kind; accepted: {', '.join(KINDS)}")
        if not (np.isfinite(self.power) and self.power > 0):
            raise ValidateError(f"{where}: power {self.power} must be a finite number > 0")
        need = {"rectangle": 2, "disk": 1, "sphere": 1, "lamp": 3}.get(self.kind, 0)
        if len(self.size) != need or not all(np.isfinite(s) and s > 0 for s in self.size):
            raise ValidateError(f"{where}: size {self.size} must be {need} finite number(s) > 0")
        if self.kind == "spot" and not 0 < self.beam_deg <= self.cutoff_deg < 90:
            raise ValidateError(f"{where}: need 0 < beam_width {self.beam_deg}° ≤ cutoff {self.cutoff_deg}° < 90°")
        if self.kind == "lamp" and self.size[2] < self.size[0]:
            raise ValidateError(f"{where}: aperture radius {self.size[2]} must be ≥ the disc's radius {self.size[0]}")
        facing = ("spot", "rectangle", "disk", "lamp")
        if self.kind in facing and np.linalg.norm(np.subtract(self.target, self.position)) <= 0:
            raise ValidateError(f"{where}: position and target coincide; the facing direction is undefined")

    # -- geometry -------------------------------------------------------------------------------
    def frame(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(left, up', forward) of Mitsuba's look_at(position, target, up) (module docstring)."""
        f = np.subtract(self.target, self.position).astype(np.float64)
        f /= np.linalg.norm(f)
        up = np.array([0.0, 1.0, 0.0]) if abs(f[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
        left = np.cross(up, f)
        left /= np.linalg.norm(left)
        return left, np.cross(f, left), f

    @property
    def area(self) -> float:
        if self.kind == "rectangle":
            return 4.0 * self.size[0] * self.size[1]
        if self.kind == "disk":
            return float(np.pi * self.size[0] ** 2)
        if self.kind == "sphere":
            return float(4 * np.pi * self.size[0] ** 2)
        return 0.0

    @property
    def extent(self) -> float:
        """The light's largest dimension: rectangle diagonal, disc or sphere diameter (0 for delta lights)."""
        if self.kind == "rectangle":
            return float(2.0 * np.hypot(*self.size))
        return 2.0 * self.size[0] if self.size else 0.0

    def as_mapping(self) -> dict[str, Any]:
        """What a ``light`` technique receives (see :mod:`validate.local_models.light.classic_lights`)."""
        m: dict[str, Any] = {"type": self.kind, "position": np.array(self.position, dtype=np.float64)}
        if self.kind in ("point", "spot"):
            m["intensity"] = float(self.power)
        elif self.kind == "directional":
            d = np.asarray(self.direction, dtype=np.float64)
            m["direction"], m["irradiance"] = d / np.linalg.norm(d), float(self.power)
        else:
            m["radiance"] = float(self.power)
        if self.kind == "spot":
            m.update(direction=self.frame()[2], cutoff_angle=float(self.cutoff_deg), beam_width=float(self.beam_deg))
        if self.kind in ("rectangle", "disk"):
            left, up, fwd = self.frame()
            m["normal"] = fwd
            if self.kind == "rectangle":
                m["axes"] = np.stack([self.size[0] * left, self.size[1] * up])  # half-edge vectors
            else:
                m["radius"], m["axes"] = float(self.size[0]), np.stack([left, up])
        if self.kind == "sphere":
            m["radius"] = float(self.size[0])
        if self.kind == "lamp":  # the mouth's centre, the axis, the disc's radius, its depth, the aperture
            m.update(direction=self.frame()[2], radius=float(self.size[0]), depth=float(self.size[1]),
                     aperture=float(self.size[2]))
        return m

    # -- Mitsuba ----------------------------------------------------------------------------------
    def _look_at(self) -> Any:
        import mitsuba as mi

        up = [0.0, 1.0, 0.0] if abs(self.frame()[2][1]) < 0.9 else [1.0, 0.0, 0.0]
        return mi.ScalarTransform4f().look_at(origin=list(self.position), target=list(self.target), up=up)

    def mitsuba(self) -> dict[str, Any]:
        """The Mitsuba emitter (or emitting shape) dict."""
        import mitsuba as mi

        rgb = {"type": "rgb", "value": float(self.power)}
        if self.kind == "point":
            return {"type": "point", "position": list(self.position), "intensity": rgb}
        if self.kind == "spot":
            return {"type": "spot", "to_world": self._look_at(), "intensity": rgb,
                    "cutoff_angle": float(self.cutoff_deg), "beam_width": float(self.beam_deg)}
        if self.kind == "directional":
            return {"type": "directional", "direction": list(self.direction), "irradiance": rgb}
        emitter = {"type": "area", "radiance": rgb}
        if self.kind == "sphere":
            return {"type": "sphere", "center": list(self.position), "radius": float(self.size[0]),
                    "emitter": emitter}
        scale = [self.size[0], self.size[1], 1.0] if self.kind == "rectangle" else [self.size[0]] * 3
        return {"type": self.kind, "to_world": self._look_at() @ mi.ScalarTransform4f().scale(scale),
                "emitter": emitter}

    def blocker(self) -> dict[str, Any]:
        """The area light's shape without its emitter, black (reflectance 0): geometry only."""
        if self.kind not in AREA_KINDS:
            raise ValidateError(f"light {self.kind!r}: a delta light has no shape to block with")
        d = dict(self.mitsuba())
        d.pop("emitter")
        d["bsdf"] = BLACK
        return d

    def lamp_disc(self) -> Light:
        """A lamp's emitting disc: radius r, at depth h behind the mouth, facing the same way."""
        if self.kind != "lamp":
            raise ValidateError(f"light {self.kind!r}: not a lamp")
        back = np.asarray(self.position) - self.size[1] * self.frame()[2]
        return Light("disk", self.power, tuple(back.tolist()), tuple((back + self.frame()[2]).tolist()),
                     size=(self.size[0],))

    def shapes(self, mode: str) -> dict[str, dict[str, Any]]:
        """Mitsuba entries (suffix → dict) of this light: ``emit`` (emitter, and a lamp's tube), ``block``
        (its shapes, black), ``self`` (what its own shadow rays see: a lamp's tube only)."""
        tube: dict[str, dict[str, Any]] = {}
        if self.kind == "lamp":
            disc = self.lamp_disc()
            tube = {"_tube": {"type": "cylinder", "p0": list(disc.position), "p1": list(self.position),
                              "radius": float(self.size[2]), "bsdf": BLACK}}
            main = disc.mitsuba() if mode == "emit" else disc.blocker()
        elif mode == "emit":
            main = self.mitsuba()
        else:
            main = self.blocker() if self.kind in AREA_KINDS else {}
        if mode == "self":
            return tube
        return ({"": main} if main else {}) | tube


@dataclass(frozen=True)
class Camera(PerspectiveCamera):
    origin: tuple[float, float, float] = (0.4, 3.0, 4.6)
    target: tuple[float, float, float] = (0.0, 0.2, -0.1)
    fov_deg: float = 52.0  # horizontal
    width: int = 64
    height: int = 48


@dataclass(frozen=True)
class LightScene:
    """Ground (+ sphere and box when ``occluders``) + lights + camera; ``parts()`` is the cache key.

    ``blockers``: lights present only as black, non-emitting shapes (so that a single-light render
    has the same geometry as a render where those lights shine: an area light's shape casts shadows).
    """

    lights: tuple[Light, ...]
    camera: Camera = field(default_factory=Camera)
    occluders: bool = True
    name: str = "classic"
    blockers: tuple[Light, ...] = ()

    def __post_init__(self) -> None:
        if not self.lights:
            raise ValidateError(f"light scene {self.name!r}: no light")

    def parts(self) -> dict[str, Any]:
        return {"name": self.name, "lights": [asdict(light) for light in self.lights], "camera": asdict(self.camera),
                "occluders": self.occluders, "geometry": [GROUND_HALF_SIZE, SPHERE, BOX, ALBEDO],
                "blockers": [asdict(b) for b in self.blockers]}

    def digest(self) -> str:
        return hashlib.sha256(json.dumps(self.parts(), sort_keys=True).encode()).hexdigest()[:16]

    def mitsuba_dict(self, lights: str = "emit", with_sensor: bool = True, exclude: int | None = None
                     ) -> dict[str, Any]:
        """``lights``: "emit" (the render), "block" (every area light but ``exclude`` as a black shape, no
        emission: the geometry shadow rays see), "none" (receivers only: no light shapes, no blockers)."""
        if lights not in ("emit", "block", "none"):
            raise ValidateError(f"light scene: lights={lights!r}; accepted: emit, block, none")
        d: dict[str, Any] = {"type": "scene", **geometry_shapes(self.occluders)}
        if lights != "none":
            for i, b in enumerate(self.blockers):
                d.update({f"blocker{i}{k}": v for k, v in b.shapes("block").items()})
            for i, light in enumerate(self.lights):
                mode = "emit" if lights == "emit" else ("self" if i == exclude else "block")
                d.update({f"light{i}{k}": v for k, v in light.shapes(mode).items()})
        if with_sensor:
            d["sensor"] = self.camera.mitsuba()
        return d


BLACK = {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.0}}


def _diffuse(name: str) -> dict[str, Any]:
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(ALBEDO[name])}}


def geometry_shapes(occluders: bool = True) -> dict[str, Any]:
    """Mitsuba dicts of the ground plane (y = 0, normal +y) and, with ``occluders``, the sphere and box."""
    import mitsuba as mi

    T = mi.ScalarTransform4f
    shapes: dict[str, Any] = {"ground": {"type": "rectangle", "bsdf": _diffuse("ground"),
                                         "to_world": T().rotate([1, 0, 0], -90).scale(GROUND_HALF_SIZE)}}
    if occluders:
        shapes["sphere"] = {"type": "sphere", "center": list(SPHERE["center"]), "radius": SPHERE["radius"],
                            "bsdf": _diffuse("sphere")}
        shapes["box"] = {"type": "cube", "bsdf": _diffuse("box"),
                         "to_world": T().translate(list(BOX["center"])).rotate([0, 1, 0], BOX["yaw_deg"])
                         .scale(BOX["half_size"])}
    return shapes


# The standard lights, physical units. Positions keep every light above the box and sphere.
STANDARD_LIGHTS: dict[str, Light] = {
    "point": Light("point", 40.0, position=(1.4, 2.6, 1.2)),
    "spot": Light("spot", 120.0, position=(-1.6, 3.2, 1.8), target=(-0.3, 0.0, 0.0), cutoff_deg=24.0,
                  beam_deg=18.0),
    "directional": Light("directional", 3.0, direction=(-0.35, -1.0, -0.45)),
    "rectangle": Light("rectangle", 30.0, position=(1.0, 2.2, 1.1), target=(0.0, 0.0, 0.0), size=(0.6, 0.35)),
    "disk": Light("disk", 30.0, position=(1.0, 2.2, 1.1), target=(0.0, 0.0, 0.0), size=(0.45,)),
    "sphere": Light("sphere", 30.0, position=(1.0, 2.2, 1.1), size=(0.3,)),
    "lamp": Light("lamp", 2000.0, position=(-0.2, 3.0, 0.9), target=(0.0, 0.0, -0.2), size=(0.08, 0.3, 0.085)),
}


def light_scene(kinds: tuple[str, ...], width: int = 64, height: int = 48, occluders: bool = True,
                blockers: tuple[str, ...] = (), **overrides: Light) -> LightScene:
    """The standard scene lit by the standard lights ``kinds`` (``overrides``: kind → Light), with the
    standard area lights ``blockers`` present as black shapes."""
    unknown = [k for k in kinds if k not in STANDARD_LIGHTS]
    if unknown:
        raise ValidateError(f"light scene: unknown light(s) {unknown}; accepted: {', '.join(STANDARD_LIGHTS)}")
    lights = tuple(overrides.get(k, STANDARD_LIGHTS[k]) for k in kinds)
    name = "+".join(kinds) + "".join(f"|{b}" for b in blockers)
    return LightScene(lights, Camera(width=width, height=height), occluders, name,
                      tuple(STANDARD_LIGHTS[b] for b in blockers))


def scaled(light: Light, factor: float) -> Light:
    """The same light with its power multiplied by ``factor``."""
    return replace(light, power=light.power * factor)
