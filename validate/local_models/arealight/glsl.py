"""The ``arealight`` family's GLSL adapter: the declarations a ``.glsl`` technique of the family sees, the
harness's ``main()``, the host side of a call and the contract (:mod:`validate.local_models.glsl_adapter`,
``docs/glsl.md``). Loaded with the family; it registers the adapter and no technique."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...geometry import unit
from ..glsl_adapter import LIGHT_MAIN, GLSLFamily, Run, fetch_inputs, register_glsl_family

AREA_DECL = fetch_inputs("p n") + """
uniform int u_area_shape;
uniform vec3 u_area_center; uniform vec3 u_area_normal; uniform vec3 u_area_tangent;
uniform float u_area_radius; uniform vec2 u_area_size; uniform float u_area_radiance;
out vec4 o_color;
vec3 shade(vec3 p, vec3 n, vec3 v);
"""
AREA_SHAPES = {"disc": 0, "sphere": 1, "rectangle": 2}


def area_uniforms(light: Mapping[str, Any]) -> dict[str, Any]:
    """The area-light mapping as uniforms (absent keys → 0; normal and tangent normalised where given)."""
    shape = light.get("shape")
    if shape not in AREA_SHAPES:
        raise ValidateError(f"area light: shape {shape!r}; GLSL arealight techniques take {', '.join(AREA_SHAPES)}")

    def given(key: str, default: tuple[float, float, float]) -> np.ndarray:
        return unit(np.asarray(light.get(key, default), dtype=np.float64))

    size = np.broadcast_to(np.asarray(light.get("size", 0.0), dtype=np.float64), (2,))
    return {"u_area_shape": AREA_SHAPES[shape], "u_area_center": np.asarray(light["center"], dtype=np.float64),
            "u_area_normal": given("normal", (0.0, -1.0, 0.0)), "u_area_tangent": given("tangent", (1.0, 0.0, 0.0)),
            "u_area_radius": float(light.get("radius", 0.0)), "u_area_size": size,
            "u_area_radiance": float(light.get("radiance", 1.0))}


def arealight_call(run: Run, light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
                   **_: Any) -> np.ndarray:
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    return run([p, unit(normals)], area_uniforms(light))[:, 0].astype(np.float64)


CONTRACT = (
    "vec3 shade(vec3 p, vec3 n, vec3 v) -> E in W/m² (.r read; v = n); uniforms int u_area_shape "
    "(0 disc, 1 sphere, 2 rectangle), vec3 u_area_center, u_area_normal (the emitting side), "
    "u_area_tangent, float u_area_radius, vec2 u_area_size, float u_area_radiance"
)

SPEC = register_glsl_family(GLSLFamily(
    "arealight", "vec3 shade(vec3 p, vec3 n, vec3 v)", AREA_DECL, LIGHT_MAIN, arealight_call, contract=CONTRACT))
