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
* Lights: KHR_lights_punctual [3] units — a directional light's ``intensity`` is illuminance in lux
  (lm/m²) on a surface facing it; ``direction`` is the direction the light travels.
* Environment: constant radiance (the furnace) or an equirect probe (radiance, W/(sr·m²) per channel).

Mapping to Mitsuba, written once (:func:`mitsuba_bsdf`), from glTF 2.0 Appendix B [1]:

* metallic = 1: metal_brdf = conductor_fresnel(f0 = baseColor) · specular_brdf(α) — a GGX microfacet
  BRDF with Smith height-correlated masking (B.3.2). Mitsuba ``roughconductor`` (GGX, α = roughness²)
  with ``material = "none"`` (F = 1) and ``specular_reflectance = baseColor`` is exact for
  baseColor = 1 (F = 1 under both Schlick and the complex Fresnel) and single-scattering, as glTF's.
* metallic = 0, specular = 0: diffuse_brdf = baseColor/π (B.3.4) — Mitsuba ``diffuse``.
* metallic = 0, specular = 1: dielectric_brdf = fresnel_mix(ior 1.5, diffuse, specular_brdf) (B.3.5).
  glTF's mix is not a layered BSDF; the physical layered counterpart is Mitsuba ``roughplastic``
  (GGX coating, int_ior 1.5, diffuse base with internal reflections [4]) — used here as the reference,
  and the report calls it what it is (a layered dielectric, not the glTF formula).

References
----------
[1] Khronos, glTF 2.0 Specification, Appendix B "BRDF Implementation" (B.3.2 specular_brdf, B.3.4,
    B.3.5 fresnel_mix).
[2] Khronos, KHR_materials_specular (specularFactor scales F0 and F90 of the dielectric layer).
[3] Khronos, KHR_lights_punctual ("directional: intensity in lux (lm/m²)").
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


@dataclass(frozen=True)
class Material:
    """glTF metallic-roughness parameters (see the module docstring)."""

    base_color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    metallic: float = 0.0
    roughness: float = 1.0
    specular: float = 1.0

    def __post_init__(self) -> None:
        for name in ("metallic", "roughness", "specular"):
            v = getattr(self, name)
            if not 0.0 <= v <= 1.0:
                raise ValidateError(f"material: {name}={v} outside [0, 1]")
        if self.metallic not in (0.0, 1.0):
            raise ValidateError(f"material: metallic={self.metallic}: only 0 or 1 map to Mitsuba here")
        if self.metallic == 0.0 and self.specular not in (0.0, 1.0):
            raise ValidateError(f"material: specular={self.specular}: only 0 or 1 map to Mitsuba here")

    def to_json(self) -> dict[str, Any]:
        return {"baseColor": list(self.base_color), "metallic": self.metallic, "roughness": self.roughness,
                "specular": self.specular}


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
    lights: tuple[DirectionalLight, ...] = ()
    environment: Environment | None = None
    resolution: int = 64
    segments: tuple[int, int] = (512, 256)  # engines' sphere tessellation (longitude, latitude)

    def key(self) -> dict[str, Any]:
        """Everything the reference depends on (for the cache)."""
        return {"name": self.name, "material": self.material.to_json(),
                "lights": [li.to_json() for li in self.lights], "resolution": self.resolution,
                "environment": None if self.environment is None else self.environment.digest(),
                "camera": [CAMERA_POSITION, HALF_EXTENT]}

    def pixel_centres(self) -> tuple[np.ndarray, np.ndarray]:
        """Camera-space (x, y) of every pixel centre, each (R, R); row 0 top, column 0 left."""
        r = self.resolution
        c = -HALF_EXTENT + (np.arange(r) + 0.5) * (2.0 * HALF_EXTENT / r)
        return np.broadcast_to(c[None, :], (r, r)), np.broadcast_to(-c[:, None], (r, r))

    def mitsuba_dict(self) -> dict[str, Any]:
        """Mitsuba scene dict without sensor or integrator (the reference adds them)."""
        d: dict[str, Any] = {"type": "scene", "sphere": {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0,
                                                         "bsdf": mitsuba_bsdf(self.material)}}
        for k, li in enumerate(self.lights):
            d[f"light{k}"] = {"type": "directional", "direction": li.unit_direction().tolist(),
                              "irradiance": {"type": "rgb", "value": [li.intensity * c for c in li.color]}}
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
                "sphere": {"radius": 1.0, "segments": list(self.segments)}, "material": self.material.to_json(),
                "lights": [li.to_json() for li in self.lights], "environment": env}


def mitsuba_bsdf(m: Material) -> dict[str, Any]:
    """The glTF → Mitsuba mapping (module docstring, glTF 2.0 Appendix B)."""
    rgb = {"type": "rgb", "value": list(m.base_color)}
    alpha = max(m.roughness**2, 1e-4)
    if m.metallic == 1.0:
        return {"type": "roughconductor", "distribution": "ggx", "alpha": alpha, "material": "none",
                "specular_reflectance": rgb, "sample_visible": True}
    if m.specular == 0.0:
        return {"type": "diffuse", "reflectance": rgb}
    return {"type": "roughplastic", "distribution": "ggx", "alpha": alpha, "int_ior": DIELECTRIC_IOR,
            "ext_ior": 1.0, "diffuse_reflectance": rgb, "nonlinear": False}


def mitsuba_environment(env: Environment) -> dict[str, Any]:
    if env.texels is None:
        return {"type": "constant", "radiance": {"type": "rgb", "value": list(env.radiance)}}
    import mitsuba as mi

    return {"type": "envmap", "bitmap": mi.Bitmap(np.ascontiguousarray(env.texels, np.float32)),
            "filter_type": "bilinear"}


def environment_texels(env: Environment) -> np.ndarray:
    """(H, W, 3) equirect radiance, row 0 = zenith; a constant environment as a 64 × 32 constant panorama."""
    if env.texels is None:
        return np.broadcast_to(np.asarray(env.radiance, np.float64), (32, 64, 3)).copy()
    return np.asarray(env.texels, np.float64)


def engine_environment(env: Environment) -> dict[str, Any]:
    """The same texels twice: float32 RGBA for three's DataTexture, and an RGBE .hdr file served to Babylon's
    HDRCubeTexture (its own loader, panorama-to-cube and prefilter)."""
    from ..gl.browser_page import encode_f32, publish  # noqa: PLC0415 - only the engine side needs it

    rgb = environment_texels(env)
    h, w = rgb.shape[:2]
    rgba = np.concatenate([rgb, np.ones((h, w, 1))], axis=-1)
    url = publish(f"{env.digest()}.hdr".replace("[", "_").replace("]", "_").replace(",", "_").replace(" ", ""),
                  rgbe_bytes(rgb))
    return {"type": "equirect", "width": w, "height": h, "data": encode_f32(rgba), "key": env.digest(), "url": url}


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


def lambert_sun_scene(resolution: int = 64, lux: float = SUN_LUX) -> RenderScene:
    """(c) a Lambertian sphere (roughness 1, metallic 0, no specular layer) under a directional light."""
    return RenderScene("lambert_directional", Material(metallic=0.0, roughness=1.0, specular=0.0),
                       lights=(DirectionalLight(SUN_DIRECTION, lux),), resolution=resolution)


def describe(scene: RenderScene) -> str:
    return json.dumps(scene.key(), sort_keys=True)
