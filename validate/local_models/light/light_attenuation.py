"""Point lights with the distance attenuations that engines ship, as ``light`` techniques.

Every technique here is E = I max(0, n·ω) a(d) V (:func:`.classic_lights.point_irradiance`) with its
own a(d) in place of the physical 1/d²:

* OpenGL fixed function [1, §2.14.1; 2, ch. 7]: a(d) = 1 / (k_c + k_l d + k_q d²), with
  - ``point_gl_default``: (k_c, k_l, k_q) = (1, 0, 0), OpenGL's initial state [1, Table 2.10]: no
    falloff at all;
  - ``point_ogre_r7`` (1, 0.7, 1.8) and ``point_ogre_r50`` (1, 0.09, 0.032): the Ogre3D wiki's
    "Point Light Attenuation" table [3] for ranges 7 and 50 units, the sets LearnOpenGL's "Light
    casters" chapter copies [4] and many hobby engines use;
* ``point_gltf_range``: glTF 2.0 KHR_lights_punctual's recommended range falloff [5]:
  a(d) = clamp(1 − (d/range)⁴, 0, 1) / d² (``range`` from the light mapping, default
  :data:`DEFAULT_RANGE`);
* ``point_ue4``: Unreal Engine 4's inverse-square falloff windowed to a radius [6, eq. 9]:
  a(d) = saturate(1 − (d/range)⁴)² / (d² + 1) (d in metres here; UE4's "+1" is 1 m² when d is in m).

The constant-term sets (k_c = 1) were tuned for unit light colours, not radiant intensity: their
error against 1/d² is a shape error and a scale error at once (the experiment reports both).

References
  [1] M. Segal, K. Akeley, *The OpenGL Graphics System: A Specification*, version 2.1 (2006),
      §2.14.1 (attenuation factor) and Table 2.10 (lighting parameters, initial values 1, 0, 0).
  [2] D. Shreiner et al., *OpenGL Programming Guide* (Red Book), 8th ed., ch. 7, Examples 7.3–7.8
      (ConstantAttenuation, LinearAttenuation, QuadraticAttenuation in a fragment shader).
  [3] Ogre3D wiki, "Point Light Attenuation" (table of Range, Constant, Linear, Quadratic).
  [4] J. de Vries, *Learn OpenGL*, "Light casters" (attenuation table, after [3]).
  [5] Khronos, glTF 2.0 extension KHR_lights_punctual, "Range Property" (recommended implementation).
  [6] B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes, eq. 9.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from ..families import light
from .common import Visible, opaque, point_irradiance, require

DEFAULT_RANGE = 10.0  # m: range used by the windowed falloffs when the light mapping gives none

GL_SETS: dict[str, tuple[tuple[float, float, float], str]] = {
    "point_gl_default": ((1.0, 0.0, 0.0), "OpenGL default attenuation (1, 0, 0): no falloff [OpenGL 2.1 Table 2.10]"),
    "point_ogre_r7": ((1.0, 0.7, 1.8), "Ogre3D/LearnOpenGL attenuation for range 7: (1, 0.7, 1.8)"),
    "point_ogre_r50": ((1.0, 0.09, 0.032), "Ogre3D/LearnOpenGL attenuation for range 50: (1, 0.09, 0.032)"),
}


def gl_attenuation(kc: float, kl: float, kq: float) -> Callable[[Any], Any]:
    """a(d) = 1 / (k_c + k_l d + k_q d²) [1, §2.14.1]."""
    return lambda d: 1.0 / (kc + d * (kl + d * kq))


def over(d: Any, rng: float) -> Any:
    """d/range with the range opaque (a new range reuses the kernel), bit for bit as with the literal: drjit's JIT
    backends turn a division by a literal into a product with its reciprocal rounded in the array's dtype, the
    scalar backend divides."""
    from ..precision import NUMPY_DTYPE, active, active_backend  # noqa: PLC0415

    if active_backend() == "scalar":
        return d / opaque(rng)[0]
    dt = NUMPY_DTYPE[active()]
    return d * opaque(float(dt(1.0) / dt(rng)))[0]


def gltf_range_attenuation(rng: float) -> Callable[[Any], Any]:
    """a(d) = clamp(1 − (d/range)⁴, 0, 1) / d² [5]."""
    import drjit as dr

    def att(d: Any) -> Any:
        x = over(d, rng)
        return dr.clip(1.0 - x * x * x * x, 0.0, 1.0) / (d * d)
    return att


def ue4_attenuation(rng: float) -> Callable[[Any], Any]:
    """a(d) = saturate(1 − (d/range)⁴)² / (d² + 1) [6, eq. 9]."""
    import drjit as dr

    def att(d: Any) -> Any:
        x = over(d, rng)
        w = dr.clip(1.0 - x * x * x * x, 0.0, 1.0)
        return w * w / (d * d + 1.0)
    return att


def _register_gl(name: str, coeffs: tuple[float, float, float], doc: str) -> None:
    def technique(light_map: Mapping[str, Any], points: Any, normals: Any,
                  visible: Visible | None = None) -> np.ndarray:
        require(light_map, kinds=("point",))
        return point_irradiance(light_map, points, normals, visible, attenuation=gl_attenuation(*coeffs))
    technique.__doc__ = f"E = I max(0, n·ω) / (k_c + k_l d + k_q d²) V with {doc}."
    light.register(name, doc, lights=("point",), attenuation=coeffs)(technique)


for _name, (_coeffs, _doc) in GL_SETS.items():
    _register_gl(_name, _coeffs, _doc)


@light.register("point_gltf_range", "glTF KHR_lights_punctual range falloff clamp(1 − (d/range)⁴, 0, 1)/d²",
                lights=("point",))
def point_gltf_range(light_map: Mapping[str, Any], points: Any, normals: Any,
                     visible: Visible | None = None) -> np.ndarray:
    """E = I max(0, n·ω) clamp(1 − (d/range)⁴, 0, 1) / d² V [5]; range = light['range'] (default 10 m)."""
    require(light_map, kinds=("point",))
    rng = float(light_map.get("range", DEFAULT_RANGE))
    return point_irradiance(light_map, points, normals, visible, attenuation=gltf_range_attenuation(rng))


@light.register("point_ue4", "Unreal Engine 4 falloff saturate(1 − (d/range)⁴)² / (d² + 1) (Karis 2013 eq. 9)",
                lights=("point",))
def point_ue4(light_map: Mapping[str, Any], points: Any, normals: Any, visible: Visible | None = None) -> np.ndarray:
    """E = I max(0, n·ω) saturate(1 − (d/range)⁴)² / (d² + 1) V [6, eq. 9]; range = light['range'] (default 10 m)."""
    require(light_map, kinds=("point",))
    rng = float(light_map.get("range", DEFAULT_RANGE))
    return point_irradiance(light_map, points, normals, visible, attenuation=ue4_attenuation(rng))
