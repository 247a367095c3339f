"""The ``specular_arealight`` family's GLSL adapter: the declarations a ``.glsl`` technique of the family sees, the
harness's ``main()``, the host side of a call and the contract (:mod:`validate.local_models.glsl_adapter`,
``docs/glsl.md``). Loaded with the family; it registers the adapter and no technique."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...geometry import unit
from ..arealight.glsl import area_uniforms
from ..glsl_adapter import GLSLFamily, Run, fetch_inputs, register_glsl_family
from .common import brdf_params

SPEC_AREA_DECL = fetch_inputs("p n v") + """
uniform int u_area_shape;
uniform vec3 u_area_center; uniform vec3 u_area_normal; uniform vec3 u_area_tangent; uniform vec3 u_area_axis;
uniform float u_area_radius; uniform vec2 u_area_size; uniform float u_area_length; uniform float u_area_radiance;
uniform float u_alpha; uniform vec3 u_f0;
out vec4 o_color;
vec3 shade(vec3 p, vec3 n, vec3 v);
"""
SPEC_AREA_MAIN = """void main() {
    ivec2 t = ivec2(gl_FragCoord.xy);
    o_color = vec4(shade(texelFetch(u_in0, t, 0).xyz, texelFetch(u_in1, t, 0).xyz, texelFetch(u_in2, t, 0).xyz), 1.0);
}"""
SPEC_AREA_SHAPES = {"disc": 0, "sphere": 1, "rectangle": 2, "tube": 3}


def specular_area_uniforms(light: Mapping[str, Any], brdf: Mapping[str, Any]) -> dict[str, Any]:
    """The light mapping (as :func:`area_uniforms`, plus shape 3 = tube with its unit ``axis`` and ``length``)
    and the GGX BRDF (``alpha``, ``f0`` broadcast to RGB; checked as the Python techniques check them)."""

    shape = light.get("shape")
    if shape not in SPEC_AREA_SHAPES:
        raise ValidateError(f"area light: shape {shape!r}; GLSL specular_arealight techniques take "
                            f"{', '.join(SPEC_AREA_SHAPES)}")
    alpha, f0 = brdf_params(brdf, "glsl")
    u = area_uniforms(dict(light, shape="disc"))
    u["u_area_shape"] = SPEC_AREA_SHAPES[shape]
    u["u_area_axis"] = unit(np.asarray(light.get("axis", (1.0, 0.0, 0.0)), dtype=np.float64))
    u["u_area_length"] = float(light.get("length", 0.0))
    return {**u, "u_alpha": alpha, "u_f0": np.asarray(f0, dtype=np.float64)}


def specular_arealight_call(run: Run, light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray,
                            normals: np.ndarray, views: np.ndarray, **_: Any) -> np.ndarray:
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    out = run([p, unit(normals), unit(views)], specular_area_uniforms(light, brdf))
    return out[:, :3].astype(np.float64)


CONTRACT = (
    "vec3 shade(vec3 p, vec3 n, vec3 v) -> outgoing radiance (RGB) of a GGX BRDF lit by the "
    "light; uniforms int u_area_shape (0 disc, 1 sphere, 2 rectangle, 3 tube), vec3 "
    "u_area_center, u_area_normal, u_area_tangent, u_area_axis, float u_area_radius, vec2 "
    "u_area_size, float u_area_length, u_area_radiance; float u_alpha (GGX α), vec3 u_f0"
)

SPEC = register_glsl_family(GLSLFamily(
    "specular_arealight", "vec3 shade(vec3 p, vec3 n, vec3 v)", SPEC_AREA_DECL, SPEC_AREA_MAIN,
    specular_arealight_call, contract=CONTRACT))
