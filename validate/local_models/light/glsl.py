"""The ``light`` family's GLSL adapter: the declarations a ``.glsl`` technique of the family sees, the
harness's ``main()``, the host side of a call and the contract (:mod:`validate.local_models.glsl_adapter`,
``docs/glsl.md``). Loaded with the family; it registers the adapter and no technique."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...geometry import unit
from ..glsl_adapter import LIGHT_MAIN, GLSLFamily, Run, fetch_inputs, register_glsl_family
from . import common as light_common

LIGHT_DECL = fetch_inputs("p n") + """
uniform int u_light_type;
uniform vec3 u_light_position; uniform vec3 u_light_direction;
uniform float u_light_intensity; uniform float u_light_irradiance;
uniform float u_light_cutoff_angle; uniform float u_light_beam_width;
uniform float u_light_exponent; uniform float u_light_range;
out vec4 o_color;
vec3 shade(vec3 p, vec3 n, vec3 v);
"""

LIGHT_TYPES = {"point": 0, "spot": 1, "directional": 2}


def light_uniforms(light: Mapping[str, Any]) -> dict[str, Any]:
    """The light mapping as uniforms (absent keys → 0; direction normalised)."""
    kind = light.get("type")
    if kind not in LIGHT_TYPES:
        raise ValidateError(f"light of type {kind!r}: GLSL light techniques model "
                                           f"{', '.join(LIGHT_TYPES)} only")
    d = np.asarray(light.get("direction", (0.0, 0.0, -1.0)), dtype=np.float64)
    u = {"u_light_type": LIGHT_TYPES[kind], "u_light_direction": d / np.linalg.norm(d),
         "u_light_position": np.asarray(light.get("position", (0.0, 0.0, 0.0)), dtype=np.float64)}
    for key in ("intensity", "irradiance", "cutoff_angle", "beam_width", "exponent", "range"):
        u[f"u_light_{key}"] = float(light.get(key, 1.0 if key == "exponent" else 0.0))
    return u


def host_shadow(light: Mapping[str, Any], p: np.ndarray, n: np.ndarray, e: np.ndarray, visible: Any) -> np.ndarray:
    """E·V with V the scene's shadow-ray test, exactly as :func:`light_common.point_irradiance` and
    :func:`light_common.directional` apply it (lit receivers only, lifted along the lit side's normal)."""
    lit = e > 0
    if visible is None or not lit.any():
        return e
    if light["type"] == "directional":
        to_light = -np.asarray(light["direction"], dtype=np.float64)
        to_light /= np.linalg.norm(to_light)
        targets = p[lit] + light_common.DIRECTIONAL_REACH * to_light
        facing = n[lit]
    else:
        pos = np.asarray(light["position"], dtype=np.float64)
        sign = np.sign(np.sum((pos - p[lit]) * n[lit], axis=-1))
        facing, targets = n[lit] * sign[:, None], np.broadcast_to(pos, p[lit].shape)
    out = e.copy()
    out[lit] *= light_common.shadow(visible, p[lit], facing, targets)
    return out


def light_call(run: Run, light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
               visible: Any = None, **_: Any) -> np.ndarray:
    p, n = light_common.as_points(points, normals)
    n = unit(n)
    e = run([p, n], light_uniforms(light))[:, 0].astype(np.float64)
    return host_shadow(light, p, n, e, visible)


CONTRACT = (
    "vec3 shade(vec3 p, vec3 n, vec3 v) -> unshadowed E in W/m² (.r read; v = n; V applied by the host); "
    "uniforms int u_light_type (0 point, 1 spot, 2 directional), vec3 u_light_position, u_light_direction, "
    "float u_light_intensity, u_light_irradiance, u_light_cutoff_angle, u_light_beam_width (degrees), "
    "u_light_exponent, u_light_range"
)

SPEC = register_glsl_family(GLSLFamily(
    "light", "vec3 shade(vec3 p, vec3 n, vec3 v)", LIGHT_DECL, LIGHT_MAIN, light_call, contract=CONTRACT))
