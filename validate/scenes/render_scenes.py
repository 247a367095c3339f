"""Render scenes described once: camera, a unit sphere, a glTF material, lights, an environment.

Each :class:`RenderScene` turns into (1) a Mitsuba scene dict (:meth:`RenderScene.mitsuba_dict`, no
sensor: :mod:`validate.reference.render_reference` traces pixel-centre rays itself) and (2) the JSON the
engine pages read (:meth:`RenderScene.engine_json`). Nothing else describes a render scene.

Conventions
-----------
* World: right-handed, +y up. Camera: orthographic, at ``CAMERA_POSITION`` looking at the origin, image
  spanning [−e, e]² in camera space (e = ``half_extent``); image row 0 is the TOP, column 0 the camera's
  left (world −x). Pixel (i, j) is judged at its centre ray (x, y) = (−e + (j + ½)·2e/W, e − (i + ½)·2e/H)
  — what an engine without MSAA rasterises.
* Geometry: the sphere of radius 1 at the origin (engines tessellate it: ``segments``).
* Material: glTF 2.0 metallic-roughness [1] — ``baseColor`` (linear), ``metallic``, ``roughness``
  (perceptual; α = roughness² [1, Appendix B.3.2]), ``specular`` (KHR_materials_specular's factor [2]:
  1 = the core model's F0 = 0.04 dielectric layer, 0 = no specular layer, i.e. Lambertian).
* Geometry: ``sphere`` (above) or ``plane`` — the square z = 0 of half-size ``PLANE_HALF_SIZE`` facing the
  camera (+z), filling the image.
* Lights: KHR_lights_punctual [3] units — a directional light's ``intensity`` is illuminance in lux
  (lm/m²) on a surface facing it; ``direction`` is the direction the light travels. A point or spot light's
  ``intensity`` is luminous intensity in candela (lm/sr), attenuated by the inverse square of the distance
  with no range (KHR: "range undefined → infinite"). A spot's angular falloff between ``inner_deg`` and
  ``outer_deg`` is KHR's reference formula [3, "Inner and Outer Cone Angles"]
  f = clamp((cos θ − cos θ_o)/(cos θ_i − cos θ_o), 0, 1)²  (``profile = "gltf"``), or three.js's
  smoothstep(cos θ_o, cos θ_i, cos θ) (``"smoothstep"``, lights_pars_begin.glsl getSpotAttenuation). The
  suite, like KHR's renderers, reads photometric units as the radiometric ones (1 cd ↔ 1 W/sr).
* Hemisphere light: an environment of radiance ``sky`` above the horizon (y > 0) and ``ground`` below
  (:class:`HemisphereLight`); each engine page converts it to its own light's parameters.
* Environment: constant radiance (the furnace) or an equirect probe (radiance, W/(sr·m²) per channel).

Mapping to Mitsuba, written once (:func:`mitsuba_bsdf`), from glTF 2.0 Appendix B [1]:

* metallic = 1: metal_brdf = conductor_fresnel(f0 = baseColor) · specular_brdf(α) — a GGX microfacet
  BRDF with Smith height-correlated masking (B.3.2). Mitsuba ``roughconductor`` (GGX, α = roughness²)
  with ``material = "none"`` (F = 1) and ``specular_reflectance = baseColor`` has glTF's D and F for
  baseColor = 1 (F = 1 under both Schlick and the complex Fresnel) and is single-scattering, as glTF's — but
  its masking is the separable G₁(ω_i)G₁(ω_o), not glTF's height-correlated G₂ (measured pointwise:
  :func:`validate.reference.gltf_bsdf.metal_vs_roughconductor`); model "gltf" below is the exact one.
* metallic = 0, specular = 0: diffuse_brdf = baseColor/π (B.3.4) — Mitsuba ``diffuse``.
* metallic = 0, specular = 1: dielectric_brdf = fresnel_mix(ior 1.5, diffuse, specular_brdf) (B.3.5).
  glTF's mix is not a layered BSDF; the physical layered counterpart is Mitsuba ``roughplastic``
  (GGX coating, int_ior 1.5, diffuse base with internal reflections [4]) — used here as the reference,
  and the report calls it what it is (a layered dielectric, not the glTF formula).
* ``model = "gltf"`` (any metallic): Appendix B exactly — the suite's Mitsuba plug-in
  ``gltf_metallic_roughness`` (:mod:`validate.reference.gltf_bsdf`), reference (i) of the (b) material rows.
* ``model = "multiscatter"`` (white metal): the suite's random-walk microsurface ``microsurface_walk``
  (:mod:`validate.reference.microsurface_bsdf`, Heitz et al. 2016), reference (ii).

References
----------
[1] Khronos, glTF 2.0 Specification, Appendix B "BRDF Implementation" (B.3.2 specular_brdf, B.3.4,
    B.3.5 fresnel_mix).
[2] Khronos, KHR_materials_specular (specularFactor scales F0 and F90 of the dielectric layer).
[3] Khronos, KHR_lights_punctual ("directional: intensity in lux (lm/m²)"; point and spot: candela;
    "Inner and Outer Cone Angles": the reference falloff above).
[4] W. Jakob et al., Mitsuba 3 plugin reference, ``roughplastic``, ``roughconductor``, ``diffuse``.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ValidateError

CAMERA_POSITION = (0.0, 0.0, 5.0)
HALF_EXTENT = 1.1  # the sphere (radius 1) fills the image with a 5 % margin for the silhouette mask
DIELECTRIC_IOR = 1.5  # glTF 2.0 B.3.5: F0 = ((1 − ior)/(1 + ior))² = 0.04


# The Mitsuba model of a material (``Material.model``): "mapped" — the mapping of ``mitsuba_bsdf`` (roughconductor /
# diffuse / roughplastic, metallic 0 or 1); "gltf" — glTF 2.0 Appendix B as specified, any metallic (the plug-in
# ``gltf_metallic_roughness`` of validate.reference.gltf_bsdf, reference (i)); "multiscatter" — Heitz et al. 2016's
# random-walk GGX conductor (``microsurface_walk`` of validate.reference.microsurface_bsdf, reference (ii)),
# white metal only (baseColor 1, metallic 1: F = 1).
MATERIAL_MODELS = ("mapped", "gltf", "multiscatter")


@dataclass(frozen=True)
class Material:
    """glTF metallic-roughness parameters (see the module docstring) and the Mitsuba ``model`` they map to."""

    base_color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    metallic: float = 0.0
    roughness: float = 1.0
    specular: float = 1.0
    model: str = "mapped"

    def __post_init__(self) -> None:
        for name in ("metallic", "roughness", "specular"):
            v = getattr(self, name)
            if not 0.0 <= v <= 1.0:
                raise ValidateError(f"material: {name}={v} outside [0, 1]")
        if self.model not in MATERIAL_MODELS:
            raise ValidateError(f"material: model={self.model!r} not one of {MATERIAL_MODELS}")
        if self.model == "gltf" and self.specular != 1.0:
            raise ValidateError(f"material: specular={self.specular}: the glTF model is the core (specular 1)")
        if self.model == "multiscatter" and (self.metallic != 1.0 or tuple(self.base_color) != (1.0, 1.0, 1.0)):
            raise ValidateError(f"material: the multiscatter model is white metal only (metallic 1, baseColor 1), "
                                f"got metallic={self.metallic}, baseColor={self.base_color}")
        if self.model == "mapped" and self.metallic not in (0.0, 1.0):
            raise ValidateError(f"material: metallic={self.metallic}: only 0 or 1 map to Mitsuba here")
        if self.model == "mapped" and self.metallic == 0.0 and self.specular not in (0.0, 1.0):
            raise ValidateError(f"material: specular={self.specular}: only 0 or 1 map to Mitsuba here")

    def to_json(self) -> dict[str, Any]:
        """The engines' parameters (and, when not "mapped", the model: part of the reference's cache key)."""
        return {"baseColor": list(self.base_color), "metallic": self.metallic, "roughness": self.roughness,
                "specular": self.specular, **({} if self.model == "mapped" else {"model": self.model})}


@dataclass(frozen=True)
class DirectionalLight:
    """KHR_lights_punctual directional light: ``intensity`` lux, travelling along ``direction``."""

    direction: tuple[float, float, float]
    intensity: float
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)

    def unit_direction(self) -> np.ndarray:
        d = np.asarray(self.direction, np.float64)
        return d / np.linalg.norm(d)

    def to_json(self) -> dict[str, Any]:
        return {"type": "directional", "direction": self.unit_direction().tolist(), "intensity": self.intensity,
                "color": list(self.color)}


@dataclass(frozen=True)
class PointLight:
    """KHR_lights_punctual point light: ``intensity`` candela at ``position``, inverse-square, no range."""

    position: tuple[float, float, float]
    intensity: float
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)

    def to_json(self) -> dict[str, Any]:
        return {"type": "point", "position": list(self.position), "intensity": self.intensity,
                "color": list(self.color)}


SPOT_PROFILES = ("gltf", "smoothstep")


@dataclass(frozen=True)
class SpotLight:
    """KHR_lights_punctual spot light at ``position`` aimed at ``target``: ``intensity`` candela on the axis,
    cone angles in degrees from the axis, falloff ``profile`` (module docstring)."""

    position: tuple[float, float, float]
    target: tuple[float, float, float]
    intensity: float
    inner_deg: float
    outer_deg: float
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    profile: str = "gltf"

    def __post_init__(self) -> None:
        if not 0.0 <= self.inner_deg < self.outer_deg < 90.0:
            raise ValidateError(f"spot light: need 0 <= inner_deg < outer_deg < 90, got {self.inner_deg}, "
                                f"{self.outer_deg}")
        if self.profile not in SPOT_PROFILES:
            raise ValidateError(f"spot light: profile {self.profile!r} not one of {SPOT_PROFILES}")

    def unit_direction(self) -> np.ndarray:
        d = np.asarray(self.target, np.float64) - np.asarray(self.position, np.float64)
        return d / np.linalg.norm(d)

    def falloff(self, cos_theta: np.ndarray) -> np.ndarray:
        """The angular falloff f(cos θ) of ``profile`` (module docstring)."""
        ci, co = np.cos(np.radians(self.inner_deg)), np.cos(np.radians(self.outer_deg))
        t = np.clip((np.asarray(cos_theta) - co) / (ci - co), 0.0, 1.0)
        return t * t if self.profile == "gltf" else t * t * (3.0 - 2.0 * t)

    def flux(self) -> float:
        """Luminous flux Φ = 2π I ∫_{cos θ_o}^1 f(c) dc in lm: with t linear in c, ∫ t² = (c_i − c_o)/3 (KHR) and
        ∫ t²(3 − 2t) = (c_i − c_o)/2 (smoothstep), plus 1 − c_i inside the inner cone."""
        ci, co = np.cos(np.radians(self.inner_deg)), np.cos(np.radians(self.outer_deg))
        return float(2 * np.pi * self.intensity * ((1 - ci) + (ci - co) / (3.0 if self.profile == "gltf" else 2.0)))

    def to_json(self) -> dict[str, Any]:
        return {"type": "spot", "position": list(self.position), "direction": self.unit_direction().tolist(),
                "target": list(self.target), "intensity": self.intensity, "inner_deg": self.inner_deg,
                "outer_deg": self.outer_deg, "color": list(self.color), "profile": self.profile}


@dataclass(frozen=True)
class HemisphereLight:
    """A two-value environment: radiance ``sky`` for directions with y > 0, ``ground`` below (W/(sr·m²))."""

    sky: tuple[float, float, float]
    ground: tuple[float, float, float]

    def to_json(self) -> dict[str, Any]:
        return {"type": "hemisphere", "sky": list(self.sky), "ground": list(self.ground), "up": [0.0, 1.0, 0.0]}

    def texels(self, height: int = 256) -> np.ndarray:
        """(H, 2H, 3) lat-long map, row 0 = zenith; the horizon falls on a row boundary (H even)."""
        rows = np.where((np.arange(height) < height // 2)[:, None], 1.0, 0.0)
        img = rows[..., None] * np.asarray(self.sky) + (1.0 - rows[..., None]) * np.asarray(self.ground)
        return np.repeat(img, 2 * height, axis=1)


@dataclass(frozen=True)
class RectLight:
    """(d) A one-sided rectangular area light of uniform luminance ``intensity`` (nits = cd/m², read as radiance
    W/(sr·m²), three.js RectAreaLight's unit), centre ``position``, facing ``target``, ``width`` × ``height`` m."""

    position: tuple[float, float, float]
    target: tuple[float, float, float]
    width: float
    height: float
    intensity: float
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)

    def area(self) -> float:
        return self.width * self.height

    def to_json(self) -> dict[str, Any]:
        return {"type": "rect", "position": list(self.position), "target": list(self.target), "width": self.width,
                "height": self.height, "intensity": self.intensity, "color": list(self.color)}


Light = DirectionalLight | PointLight | SpotLight | HemisphereLight | RectLight
GEOMETRIES = ("sphere", "plane")
PLANE_HALF_SIZE = 3.0


@dataclass(frozen=True)
class Environment:
    """Constant radiance (``texels`` None) or an equirect (H, W, 3) radiance map, row 0 = zenith,
    column u ↔ azimuth as Mitsuba's ``envmap`` reads a lat-long bitmap."""

    name: str
    radiance: tuple[float, float, float] = (1.0, 1.0, 1.0)
    texels: np.ndarray | None = field(default=None, compare=False, hash=False)

    def digest(self) -> str:
        if self.texels is None:
            return f"constant{list(self.radiance)}"
        return hashlib.sha256(np.ascontiguousarray(self.texels, np.float32).tobytes()).hexdigest()[:24]


@dataclass(frozen=True)
class RenderScene:
    """One sphere, one material, lights and an optional environment, seen by the orthographic camera."""

    name: str
    material: Material
    lights: tuple[Light, ...] = ()
    environment: Environment | None = None
    resolution: int = 64
    segments: tuple[int, int] = (512, 256)  # engines' sphere tessellation (longitude, latitude)
    geometry: str = "sphere"

    def __post_init__(self) -> None:
        if self.geometry not in GEOMETRIES:
            raise ValidateError(f"render scene {self.name}: geometry {self.geometry!r} not one of {GEOMETRIES}")

    def key(self) -> dict[str, Any]:
        """Everything the reference depends on (for the cache)."""
        return {"name": self.name, "material": self.material.to_json(),
                "lights": [li.to_json() for li in self.lights], "resolution": self.resolution,
                "environment": None if self.environment is None else self.environment.digest(),
                "camera": [CAMERA_POSITION, HALF_EXTENT], **({} if self.geometry == "sphere" else
                                                                {"geometry": self.geometry})}

    def pixel_centres(self) -> tuple[np.ndarray, np.ndarray]:
        """Camera-space (x, y) of every pixel centre, each (R, R); row 0 top, column 0 left."""
        r = self.resolution
        c = -HALF_EXTENT + (np.arange(r) + 0.5) * (2.0 * HALF_EXTENT / r)
        return np.broadcast_to(c[None, :], (r, r)), np.broadcast_to(-c[:, None], (r, r))

    def hit_mask(self) -> np.ndarray:
        """(R, R) bool: the pixel-centre ray hits the geometry (the plane fills the image)."""
        x, y = self.pixel_centres()
        return x**2 + y**2 < 1.0 if self.geometry == "sphere" else np.ones(x.shape, bool)

    def surface_points(self) -> np.ndarray:
        """(R, R, 3) world point seen at each pixel centre (NaN where the ray misses)."""
        x, y = self.pixel_centres()
        z = np.sqrt(np.clip(1.0 - x**2 - y**2, 0.0, None)) if self.geometry == "sphere" else np.zeros_like(x)
        p = np.stack([x, y, z], axis=-1)
        p[~self.hit_mask()] = np.nan
        return p

    def mitsuba_dict(self) -> dict[str, Any]:
        """Mitsuba scene dict without sensor or integrator (the reference adds them)."""
        d: dict[str, Any] = {"type": "scene", self.geometry: mitsuba_shape(self.geometry, self.material)}
        for k, li in enumerate(self.lights):
            d[f"light{k}"] = mitsuba_light(li)
        if self.environment is not None:
            d["environment"] = mitsuba_environment(self.environment)
        return d

    def engine_json(self) -> dict[str, Any]:
        """The scene as the engine pages read it (validate/local_models/render/*.mjs)."""
        env = None
        if self.environment is not None:
            env = engine_environment(self.environment)
        return {"name": self.name, "image": {"width": self.resolution, "height": self.resolution},
                "camera": {"half_extent": HALF_EXTENT, "position": list(CAMERA_POSITION), "target": [0, 0, 0],
                           "up": [0, 1, 0]},
                **({"sphere": {"radius": 1.0, "segments": list(self.segments)}} if self.geometry == "sphere" else {}),
                "geometry": ({"type": "sphere", "radius": 1.0, "segments": list(self.segments)}
                             if self.geometry == "sphere" else {"type": "plane", "size": 2.0 * PLANE_HALF_SIZE}),
                "material": self.material.to_json(),
                "lights": [li.to_json() for li in self.lights], "environment": env}


def mitsuba_shape(geometry: str, m: Material) -> dict[str, Any]:
    """The unit sphere, or the plane z = 0 (Mitsuba ``rectangle``: [−1, 1]², normal +z, scaled)."""
    if geometry == "sphere":
        return {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0, "bsdf": mitsuba_bsdf(m)}
    import mitsuba as mi

    return {"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([PLANE_HALF_SIZE, PLANE_HALF_SIZE, 1.0]),
            "bsdf": mitsuba_bsdf(m)}


def mitsuba_light(li: Light) -> dict[str, Any]:
    """KHR_lights_punctual → Mitsuba: ``directional`` (irradiance = lux), ``point`` (intensity = cd), ``spot``
    with its linear-in-angle ramp disabled (beam_width = cutoff_angle = θ_o: a hard cone, src/emitters/spot.cpp
    falloff_curve) times a projected texture that evaluates the KHR falloff exactly
    (:mod:`validate.scenes.spot_profile`); a hemisphere light is the two-value ``envmap`` of
    :meth:`HemisphereLight.texels`."""
    import mitsuba as mi

    if isinstance(li, HemisphereLight):
        return {"type": "envmap", "bitmap": mi.Bitmap(np.ascontiguousarray(li.texels(), np.float32))}
    rgb = {"type": "rgb", "value": [li.intensity * c for c in li.color]}
    if isinstance(li, RectLight):  # Mitsuba ``rectangle`` ([−1, 1]², normal +z) with an ``area`` emitter (one-sided)
        frame = mi.ScalarTransform4f().look_at(origin=list(li.position), target=list(li.target), up=[0.0, 1.0, 0.0])
        return {"type": "rectangle", "emitter": {"type": "area", "radiance": rgb},
                "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}},
                "to_world": frame.scale([li.width / 2, li.height / 2, 1.0])}
    if isinstance(li, DirectionalLight):
        return {"type": "directional", "direction": li.unit_direction().tolist(), "irradiance": rgb}
    if isinstance(li, PointLight):
        return {"type": "point", "position": list(li.position), "intensity": rgb}
    from .spot_profile import texture_dict

    p = np.asarray(li.position, np.float64)
    up = [0.0, 1.0, 0.0] if abs(li.unit_direction()[1]) < 0.9 else [1.0, 0.0, 0.0]
    return {"type": "spot", "to_world": mi.ScalarTransform4f().look_at(origin=p.tolist(), target=li.target, up=up),
            "intensity": rgb, "cutoff_angle": li.outer_deg, "beam_width": li.outer_deg,
            "texture": texture_dict(li.inner_deg, li.outer_deg, li.profile)}


def mitsuba_bsdf(m: Material) -> dict[str, Any]:
    """The glTF → Mitsuba mapping (module docstring, glTF 2.0 Appendix B)."""
    rgb = {"type": "rgb", "value": list(m.base_color)}
    alpha = max(m.roughness**2, 1e-4)
    if m.model == "gltf":  # registered by validate.reference.render_reference before loading (imports run down)
        return {"type": "gltf_metallic_roughness", **{f"base_{c}": float(v) for c, v in zip("rgb", m.base_color,
                                                                                           strict=True)},
                "metallic": float(m.metallic), "roughness": float(m.roughness)}
    if m.model == "multiscatter":
        return {"type": "microsurface_walk", "alpha": alpha, "f0": 1.0}
    if m.metallic == 1.0:
        return {"type": "roughconductor", "distribution": "ggx", "alpha": alpha, "material": "none",
                "specular_reflectance": rgb, "sample_visible": True}
    if m.specular == 0.0:
        return {"type": "diffuse", "reflectance": rgb}
    return {"type": "roughplastic", "distribution": "ggx", "alpha": alpha, "int_ior": DIELECTRIC_IOR,
            "ext_ior": 1.0, "diffuse_reflectance": rgb, "nonlinear": False}


def mitsuba_environment(env: Environment) -> dict[str, Any]:
    """Constant radiance, or Mitsuba ``envmap`` on :func:`mitsuba_envmap_nodes` of the texels (no ``filter_type``:
    Mitsuba 3.9's envmap has no such parameter and rejects it as unreferenced; it always interpolates bilinearly)."""
    if env.texels is None:
        return {"type": "constant", "radiance": {"type": "rgb", "value": list(env.radiance)}}
    import mitsuba as mi

    return {"type": "envmap", "bitmap": mi.Bitmap(np.ascontiguousarray(mitsuba_envmap_nodes(env.texels), np.float32))}


def mitsuba_envmap_nodes(texels: np.ndarray) -> np.ndarray:
    """(2H + 1, W, 3) bitmap on which Mitsuba's ``envmap`` evaluates exactly the engines' bilinear texture.

    The texels (H, W) follow the probes' convention: texel (i, j) is the direction at the texel *centre*
    θ = π(i + ½)/H, φ = 2π(j + ½)/W, d = (sin φ sin θ, cos θ, −cos φ sin θ); a GPU samples them bilinearly
    between centres, clamped to row 0 / H − 1 towards the poles. Mitsuba 3.9's envmap (measured:
    ``emitter.eval`` on an index-valued bitmap) reads columns at centres φ = 2π(j + ½)/W, the same, but rows at
    *nodes* θ = π m/(M − 1). With M = 2H + 1 the nodes fall on the poles, on every texel centre (m = 2i + 1) and
    half-way between: node values pole = edge row, centre = the texel, half-way = the mean of the two rows make
    Mitsuba's piecewise-linear interpolation in θ identical to the GPU's (and it is linear in φ in both)."""
    t = np.asarray(texels, np.float64)
    h = t.shape[0]
    out = np.empty((2 * h + 1, *t.shape[1:]))
    out[1::2] = t
    out[2:-1:2] = 0.5 * (t[:-1] + t[1:])
    out[0], out[-1] = t[0], t[-1]
    return out


def environment_texels(env: Environment) -> np.ndarray:
    """(H, W, 3) equirect radiance, row 0 = zenith; a constant environment as a 64 × 32 constant panorama."""
    if env.texels is None:
        return np.broadcast_to(np.asarray(env.radiance, np.float64), (32, 64, 3)).copy()
    return np.asarray(env.texels, np.float64)


def engine_environment(env: Environment) -> dict[str, Any]:
    """The same texels twice: float32 RGBA for three's DataTexture (:func:`engine_texels`), and an RGBE .hdr file
    served to Babylon's HDRCubeTexture (its own loader, panorama-to-cube and prefilter), turned a further quarter
    (the probes' columns rolled by W/2): in a right-handed scene Babylon's shader flips z of the lookup
    (REFLECTIONMAP_OPPOSITEZ) on top of its panorama's atan2(z, x). Measured on a 128 × 64 map with one bright
    lobe at (1, 0.6, 0.5)/|·|: Mitsuba, three (W/4) and Babylon (W/2) put the peak of a roughness-0.1 metal
    sphere on the same 32² pixel (row 11, column 22) to within a pixel; no mirror and no other quarter does."""
    from ..gl.browser_page import encode_f32, publish  # noqa: PLC0415 - only the engine side needs it

    rgb = engine_texels(environment_texels(env))
    h, w = rgb.shape[:2]
    rgba = np.concatenate([rgb, np.ones((h, w, 1))], axis=-1)
    url = publish(f"{env.digest()}.hdr".replace("[", "_").replace("]", "_").replace(",", "_").replace(" ", ""),
                  rgbe_bytes(np.roll(rgb, w // 4, axis=1)))
    return {"type": "equirect", "width": w, "height": h, "data": encode_f32(rgba), "key": env.digest(), "url": url}


def engine_texels(texels: np.ndarray) -> np.ndarray:
    """The probes' texels as three.js and Babylon index an equirect panorama.

    Both read u = atan2(d_z, d_x)/2π + ½ (three's equirectUv, common.glsl; Babylon's
    PanoramaToCubeMapTools.CalcProjectionSpherical), row 0 at the zenith. With the probes' d = (sin φ sin θ, cos θ,
    −cos φ sin θ), atan2(d_z, d_x) = φ − π/2, so u_engine = u + ¼: column j' holds the probes' column j' − W/4
    (``np.roll`` by W/4; W must be a multiple of 4). A constant or azimuth-independent map is unchanged."""
    t = np.asarray(texels)
    w = t.shape[1]
    if w % 4:
        raise ValidateError(f"environment texels: width {w} is not a multiple of 4 (the engines' quarter-turn)")
    return np.roll(t, w // 4, axis=1)


def rgbe_bytes(rgb: np.ndarray) -> bytes:
    """Radiance .hdr (RGBE, flat scanlines) of an (H, W, 3) image, row 0 = top [Ward, Graphics Gems II].

    Each pixel stores mantissas ⌊c·256/2^e⌋ and the shared exponent e + 128 with 2^(e−1) ≤ max(c) < 2^e;
    Babylon's reader decodes c = byte·2^(E − 136), so radiance 1 round-trips exactly.
    """
    h, w = rgb.shape[:2]
    if w < 8:
        raise ValueError("RGBE panoramas need at least 8 columns (Babylon's reader)")
    mx = rgb.max(axis=-1)
    mant, exp = np.frexp(mx)
    scale = np.where(mx > 1e-32, 256.0 / np.ldexp(1.0, exp), 0.0)
    px = np.zeros((h, w, 4), np.uint8)
    px[..., :3] = np.clip(np.floor(rgb * scale[..., None]), 0, 255).astype(np.uint8)
    px[..., 3] = np.where(mx > 1e-32, exp + 128, 0).astype(np.uint8)
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode("ascii")
    return header + px.tobytes()


FURNACE = Environment("white_furnace", (1.0, 1.0, 1.0))
FURNACE_ROUGHNESS = (0.25, 0.5, 1.0)
# KHR_lights_punctual: the sun at noon is ~1e5 lux; here 3 lux keeps radiance ≈ 1 (E ρ/π ≈ 0.95 at normal
# incidence) so the half-float and absolute trig budgets read directly as relative errors.
SUN_LUX = 3.0
SUN_DIRECTION = (-1.0, -1.0, -1.0)  # from the upper right front, so the terminator crosses the image


def furnace_scenes(resolution: int = 64, roughness: tuple[float, ...] = FURNACE_ROUGHNESS) -> list[RenderScene]:
    """(a) the white furnace: white dielectric and white metal spheres over ``roughness``."""
    out = []
    for metallic, kind in ((0.0, "dielectric"), (1.0, "metal")):
        for r in roughness:
            out.append(RenderScene(f"furnace_{kind}_r{r:g}", Material(metallic=metallic, roughness=r),
                                   environment=FURNACE, resolution=resolution))
    return out


def furnace_material_scenes(resolution: int = 64, roughness: tuple[float, ...] = FURNACE_ROUGHNESS,
                            metallic: float = 0.5) -> list[RenderScene]:
    """(a)/(b) white glTF spheres at intermediate ``metallic`` in the white furnace (three PR 32190's test), Mitsuba
    model "gltf" (reference (i))."""
    return [RenderScene(f"furnace_gltf_m{metallic:g}_r{r:g}", Material(metallic=metallic, roughness=r, model="gltf"),
                        environment=FURNACE, resolution=resolution) for r in roughness]


def lambert_sun_scene(resolution: int = 64, lux: float = SUN_LUX) -> RenderScene:
    """(c) a Lambertian sphere (roughness 1, metallic 0, no specular layer) under a directional light."""
    return RenderScene("lambert_directional", Material(metallic=0.0, roughness=1.0, specular=0.0),
                       lights=(DirectionalLight(SUN_DIRECTION, lux),), resolution=resolution)


# (c) punctual lights, KHR units. The plane and the sphere are Lambertian (ρ = 1); each light delivers E ≈ 2–3 lux
# at its brightest receiver, so radiance ρE/π ≈ 1 as in the directional scene.
POINT_ON_PLANE = PointLight((0.3, 0.4, 1.2), 3.0)  # E = I h/d³ = 2.08 lux at the foot (0.3, 0.4, 0)
POINT_ON_SPHERE = PointLight((1.5, 1.5, 2.5), 15.0)  # 2.28 m from the nearest surface point: E ≈ 2.9 lux there
# on the plane 1.5 m below, aimed 0.14 m off the foot: inner cone radius ≈ 0.55 m, outer ≈ 0.87 m, E ≈ 1.8 lux
SPOT_ON_PLANE = SpotLight((0.0, 0.0, 1.5), (0.1, -0.1, 0.0), 4.0, 20.0, 30.0)
# (f) a warm sky over a dark blue-grey ground
HEMISPHERE = HemisphereLight(sky=(1.0, 0.9, 0.8), ground=(0.2, 0.25, 0.3))
LAMBERT = Material(metallic=0.0, roughness=1.0, specular=0.0)


def punctual_scenes(resolution: int = 64) -> list[RenderScene]:
    """(c) a point light over the Lambertian plane and beside the sphere, a spot light over the plane."""
    return [RenderScene("point_plane", LAMBERT, lights=(POINT_ON_PLANE,), resolution=resolution, geometry="plane"),
            RenderScene("point_sphere", LAMBERT, lights=(POINT_ON_SPHERE,), resolution=resolution),
            spot_scene(resolution)]


def spot_scene(resolution: int = 64, profile: str = "gltf", outer_offset_deg: float = 0.0) -> RenderScene:
    """(c) the spot over the plane; ``profile`` and ``outer_offset_deg`` vary the reference (power checks)."""
    from dataclasses import replace

    li = replace(SPOT_ON_PLANE, profile=profile, outer_deg=SPOT_ON_PLANE.outer_deg + outer_offset_deg)
    return RenderScene("spot_plane", LAMBERT, lights=(li,), resolution=resolution, geometry="plane")


def spot_penumbra(scene: RenderScene) -> np.ndarray:
    """(R, R) bool: pixels whose surface point lies between the inner and outer cone of the scene's spot light
    (where the KHR and smoothstep profiles differ)."""
    [li] = [x for x in scene.lights if isinstance(x, SpotLight)]
    v = scene.surface_points() - np.asarray(li.position)
    with np.errstate(invalid="ignore"):
        cos = (v @ li.unit_direction()) / np.linalg.norm(v, axis=-1)
        return (cos < np.cos(np.radians(li.inner_deg))) & (cos > np.cos(np.radians(li.outer_deg)))


def hemisphere_scene(resolution: int = 64) -> RenderScene:
    """(f) the Lambertian sphere under the hemisphere light."""
    return RenderScene("hemisphere_sphere", LAMBERT, lights=(HEMISPHERE,), resolution=resolution)


def describe(scene: RenderScene) -> str:
    return json.dumps(scene.key(), sort_keys=True)


# (b) the shared probes on spheres over roughness × metalness
PROBE_FILE = "ict_uffizi_256x128.hdr"  # ../shared/probes: the Uffizi gallery, lat-long 256 × 128, max 15.9, mean 1.86
PROBE_SIZE = (64, 128)  # resampled lat-long (H, W): 2 × 2 box means of the 256 × 128 file, ≈ 2.8° per texel


def resample_probe(radiance: np.ndarray, size: tuple[int, int] = PROBE_SIZE) -> np.ndarray:
    """(H, W, 3) box means of a lat-long map whose shape is an integer multiple of ``size`` (probes' convention)."""
    r = np.asarray(radiance, np.float64)
    h, w = size
    if r.shape[0] % h or r.shape[1] % w:
        raise ValidateError(f"probe {r.shape[1]}×{r.shape[0]} is not a multiple of {w}×{h}")
    return r.reshape(h, r.shape[0] // h, w, r.shape[1] // w, 3).mean(axis=(1, 3))


def probe_scenes(texels: np.ndarray, name: str, resolution: int, roughness: tuple[float, ...],
                 metallic: tuple[float, ...]) -> list[RenderScene]:
    """(b) white spheres (baseColor 1) over ``metallic`` × ``roughness`` lit only by the probe ``texels``."""
    env = Environment(name, texels=np.asarray(texels, np.float64))
    return [RenderScene(f"probe_{'metal' if mt == 1.0 else 'dielectric'}_r{r:g}", Material(metallic=mt, roughness=r),
                        environment=env, resolution=resolution) for mt in metallic for r in roughness]


# (b) glTF materials under the probe: metalness × roughness against (i) glTF as specified and (ii) the multiscatter
# microsurface (white metal); metalness 0.5 is the three PR 32190 case (multiscatter energy at intermediate metalness)
MATERIAL_METALLIC = (0.0, 0.5, 1.0)


def probe_material_scenes(texels: np.ndarray, name: str, resolution: int, roughness: tuple[float, ...],
                          metallic: tuple[float, ...] = MATERIAL_METALLIC, model: str = "gltf") -> list[RenderScene]:
    """(b) white spheres (baseColor 1, the glTF core's specular layer) over ``metallic`` × ``roughness`` under the
    probe, Mitsuba ``model`` "gltf" (reference (i)) or "multiscatter" (reference (ii), metallic 1 only)."""
    env = Environment(name, texels=np.asarray(texels, np.float64))
    return [RenderScene(f"probe_{model}_m{mt:g}_r{r:g}", Material(metallic=mt, roughness=r, model=model),
                        environment=env, resolution=resolution) for mt in metallic for r in roughness]


def probe_lambert_scene(texels: np.ndarray, name: str, resolution: int) -> RenderScene:
    """(b) the Lambertian sphere (no specular layer) under the probe: the diffuse-dominated limit."""
    return RenderScene("probe_lambert", LAMBERT, environment=Environment(name, texels=np.asarray(texels, np.float64)),
                       resolution=resolution)


# (d) a square area light beside the view (x > HALF_EXTENT: no camera ray meets it), tilted 45° down onto the plane;
# every point of the plane sees all of it above its horizon, where an LTC diffuse integral is the exact polygon
# form factor. L = 10 nits over 0.36 m² gives E ≈ 1–2 lux on the lit side.
RECT_LIGHT = RectLight((1.6, 0.0, 0.8), (0.8, 0.0, 0.0), 0.6, 0.6, 10.0)


def rect_scene(resolution: int = 64) -> RenderScene:
    """(d) the Lambertian plane under ``RECT_LIGHT``."""
    return RenderScene("rect_plane", LAMBERT, lights=(RECT_LIGHT,), resolution=resolution, geometry="plane")


RECT_ON_SPHERE = RectLight((1.6, 0.0, 0.8), (0.0, 0.0, 0.0), 0.6, 0.6, 10.0)  # 1.79 m from the centre, facing it


def rect_scenes(resolution: int = 64) -> list[RenderScene]:
    """(d) the Lambertian plane under ``RECT_LIGHT`` and the Lambertian sphere under ``RECT_ON_SPHERE``."""
    return [rect_scene(resolution), RenderScene("rect_sphere", LAMBERT, lights=(RECT_ON_SPHERE,),
                                                resolution=resolution)]


def rect_corners(li: RectLight) -> np.ndarray:
    """(4, 3) corners of the rectangle: centre ± width/2 along x' ± height/2 along y' of the frame that turns +z
    towards the target (Mitsuba's look_at with up +y: x' = normalize(up × d), y' = d × x')."""
    d = np.asarray(li.target, float) - np.asarray(li.position, float)
    d /= np.linalg.norm(d)
    x = np.cross([0.0, 1.0, 0.0], d)
    x /= np.linalg.norm(x)
    y = np.cross(d, x)
    c = np.asarray(li.position, float)
    return np.array([c + sx * li.width / 2 * x + sy * li.height / 2 * y for sx, sy in ((-1, -1), (1, -1), (1, 1),
                                                                                      (-1, 1))])


def rect_above_horizon(scene: RenderScene) -> np.ndarray:
    """(R, R) bool: pixels whose surface point sees the whole rectangle above its tangent plane (every corner in
    front: (corner − p)·n > 0) — where the diffuse integral of a polygon needs no horizon clipping and Lambert's
    polygon formula (the LTC with the identity matrix) is exact."""
    [li] = [x for x in scene.lights if isinstance(x, RectLight)]
    p = scene.surface_points()
    n = p if scene.geometry == "sphere" else np.broadcast_to([0.0, 0.0, 1.0], p.shape)
    with np.errstate(invalid="ignore"):
        return np.all([((k - p) * n).sum(-1) > 0 for k in rect_corners(li)], axis=0)


def rect_form_factors(scene: RenderScene) -> tuple[np.ndarray, np.ndarray]:
    """(R, R) exact form factor F·n of the scene's rectangle at each surface point (Lambert's polygon formula:
    F = (1/2π) Σ_edges acos(v̂_i·v̂_j) (v̂_i × v̂_j)/|v̂_i × v̂_j|, v̂ the unit vectors to the corners; exact where
    the whole rectangle is above the horizon, ``rect_above_horizon``) and three.js's clipped-sphere form factor
    (|F|² + F·n)/(|F| + 1) (lights_physical_pars_fragment LTC_ClippedSphereFormFactor, after Heitz 2017), which it
    uses everywhere. Radiance of a Lambertian (ρ) point: ρ L × form factor."""
    [li] = [x for x in scene.lights if isinstance(x, RectLight)]
    p = scene.surface_points()
    n = p if scene.geometry == "sphere" else np.broadcast_to([0.0, 0.0, 1.0], p.shape)
    v = rect_corners(li)[:, None, None, :] - p[None]
    v = v / np.linalg.norm(v, axis=-1, keepdims=True)
    f = np.zeros(p.shape)
    for i in range(4):
        a, b = v[i], v[(i + 1) % 4]
        c = np.cross(a, b)
        f += np.arccos(np.clip((a * b).sum(-1), -1, 1))[..., None] * c / np.linalg.norm(c, axis=-1, keepdims=True)
    f /= 2 * np.pi
    # the corners run counter-clockwise seen from the lit side, so F points away from the light: flip it
    fz = -(f * n).sum(-1)
    ln = np.linalg.norm(f, axis=-1)
    return fz, (ln**2 + fz) / (ln + 1)
