"""The Red Book's point light and spotlight, Examples 7.4, 7.5 and 7.6 [1, ch. 7], run on llvmpipe.

The catalogue's edits (:mod:`.catalog`) restore what the extraction lost (``{``, ``gl_Position``, a
``</pre>`` tag, a space inside ``LinearAttenuation``) and fix the book's own omission in 7.6 (the
fragment shader reads LightDirection without declaring it). Host state: MVMatrix = I and
NormalMatrix = I (eye space = world), MVPMatrix = the per-receiver placement, VertexColor = (1, 1, 1, 1),
Ambient = 0, Strength = 0 (no specular: the family measures irradiance), Shininess = 1, EyeDirection =
(0, 0, 1); ConstantAttenuation, LinearAttenuation, QuadraticAttenuation = the light mapping's
``attenuation`` (default (0, 0, 1): the physical inverse square; the book prints no values);
spot: ConeDirection = the light's direction, SpotCosCutoff = cos(cutoff_angle), SpotExponent = exponent.

Exposure: the listings saturate at white (``min(…, vec3(1.0))``, "saturate at white"); the host sets
LightColor = k·I with k = ½ / max over the receivers of I·att(d), so no receiver reaches 1, and divides
the result by k. The shader is unchanged; the factor is exact in float32 up to one rounding.

Output: E = (red channel)/k = I·max(0, N·L)·att(d) [· spot factor], the irradiance of the light family.

References
  [1] J. Kessenich, G. Sellers, D. Shreiner, *OpenGL Programming Guide* (Red Book), ch. 7, Examples
      7.4–7.6.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...gl.listing_harness import Placement, homogeneous
from ..families import light
from ..light.common import Visible, as_points, require, shadow
from ..listings.runner import register_gl, run, unit

PHYSICAL = (0.0, 0.0, 1.0)  # (k_c, k_l, k_q) = inverse square


def attenuation(d: np.ndarray, coeffs: tuple[float, float, float]) -> np.ndarray:
    """1/(k_c + k_l d + k_q d²) (Examples 7.4–7.6)."""
    kc, kl, kq = coeffs
    return 1.0 / (kc + kl * d + kq * d * d)


def spot_factor(cos_a: np.ndarray, cos_cut: float, exponent: float) -> np.ndarray:
    """0 where spotCos < SpotCosCutoff, else spotCos^SpotExponent (Example 7.5)."""
    return np.where(cos_a < cos_cut, 0.0, np.power(np.maximum(cos_a, 0.0), exponent))


def python(light_map: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, spot: bool) -> np.ndarray:
    """(N,) I max(0, N·L) att(d) [× spot factor], float64 (Examples 7.4/7.5 with the host state above)."""
    pos = np.asarray(light_map["position"], dtype=np.float64)
    to = pos - points
    d = np.linalg.norm(to, axis=1)
    ld = to / d[:, None]
    e = float(light_map["intensity"]) * np.maximum(0.0, np.sum(unit(normals) * ld, axis=1)) * attenuation(
        d, tuple(light_map.get("attenuation", PHYSICAL)))
    if spot:
        cone = unit(np.asarray(light_map["direction"], dtype=np.float64))
        e = e * spot_factor(ld @ -cone, float(np.cos(np.radians(light_map["cutoff_angle"]))),
                            float(light_map.get("exponent", 1.0)))
    return e


def glsl(name: str, light_map: Mapping[str, Any], points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(N,) the listing ``name`` (redbook_7_4 | redbook_7_5 | redbook_7_6) run with the host state above."""
    i0 = float(light_map["intensity"])
    pos = np.asarray(light_map["position"], dtype=np.float64)
    coeffs = tuple(float(c) for c in light_map.get("attenuation", PHYSICAL))
    k = 0.5 / max(float(np.max(i0 * attenuation(np.linalg.norm(points - pos, axis=1), coeffs))), 1e-30)
    u: dict[str, Any] = {"MVMatrix": np.eye(4), "NormalMatrix": np.eye(3), "Ambient": (0.0, 0.0, 0.0),
                         "LightColor": (k * i0,) * 3, "LightPosition": tuple(pos), "Shininess": 1.0, "Strength": 0.0,
                         "EyeDirection": (0.0, 0.0, 1.0), "ConstantAttenuation": coeffs[0],
                         "LinearAttenuation": coeffs[1], "QuadraticAttenuation": coeffs[2]}
    if name == "redbook_7_5":
        u.update(ConeDirection=tuple(unit(np.asarray(light_map["direction"], dtype=np.float64))),
                 SpotCosCutoff=float(np.cos(np.radians(light_map["cutoff_angle"]))),
                 SpotExponent=float(light_map.get("exponent", 1.0)))
    p4 = homogeneous(points)
    out = run(name, p4, placement=Placement("MVPMatrix"), uniforms=u,
              attributes={"VertexPosition": p4, "VertexNormal": normals, "VertexColor": np.ones((len(p4), 4))})
    return out[:, 0].astype(np.float64) / k


def _technique(name: str, light_map: Mapping[str, Any], points: Any, normals: Any, visible: Visible | None
               ) -> np.ndarray:
    p, n = as_points(points, normals)
    e = glsl(name, light_map, p, n)
    pos = np.broadcast_to(np.asarray(light_map["position"], dtype=np.float64), p.shape)
    return e * shadow(visible, p, n, pos) if visible is not None else e


@register_gl(light, "point_redbook_7_4_glsl", "Red Book Example 7.4 (point light, fragment shader) on llvmpipe, "
             "attenuation (0, 0, 1)", "redbook_7_4", lights=("point",), seed="004 Red Book ch. 7, Example 7.4")
def point_redbook_7_4_glsl(light_map: Mapping[str, Any], points: Any, normals: Any,
                           visible: Visible | None = None) -> np.ndarray:
    require(light_map, "position", "intensity", kinds=("point",))
    return _technique("redbook_7_4", light_map, points, normals, visible)


@register_gl(light, "point_redbook_7_6_glsl", "Red Book Example 7.6 (point light, per vertex) on llvmpipe, "
             "attenuation (0, 0, 1)", "redbook_7_6", lights=("point",), seed="004 Red Book ch. 7, Example 7.6")
def point_redbook_7_6_glsl(light_map: Mapping[str, Any], points: Any, normals: Any,
                           visible: Visible | None = None) -> np.ndarray:
    require(light_map, "position", "intensity", kinds=("point",))
    return _technique("redbook_7_6", light_map, points, normals, visible)


@register_gl(light, "spot_redbook_7_5_glsl", "Red Book Example 7.5 (spotlight: cutoff cosine, cos^exponent) on "
             "llvmpipe", "redbook_7_5", lights=("spot",), seed="004 Red Book ch. 7, Example 7.5")
def spot_redbook_7_5_glsl(light_map: Mapping[str, Any], points: Any, normals: Any,
                          visible: Visible | None = None) -> np.ndarray:
    require(light_map, "position", "intensity", "direction", "cutoff_angle", kinds=("spot",))
    return _technique("redbook_7_5", light_map, points, normals, visible)


__all__ = ["PHYSICAL", "attenuation", "glsl", "python", "spot_factor"]
