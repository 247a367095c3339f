"""The ``uberlight`` family's GLSL adapter: the declarations a ``.glsl`` technique of the family sees, the
harness's ``main()``, the host side of a call and the contract (:mod:`validate.local_models.glsl_adapter`,
``docs/glsl.md``). Loaded with the family; it registers the adapter and no technique."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..glsl_adapter import GLSLFamily, Run, fetch_inputs, register_glsl_family
from .common import check_light

UBER_DECL = fetch_inputs("p n v a") + """
uniform vec3 u_light_position; uniform vec3 u_light_x; uniform vec3 u_light_y; uniform vec3 u_light_z;
uniform float u_light_intensity;
uniform float u_light_width; uniform float u_light_height; uniform float u_light_width_edge;
uniform float u_light_height_edge; uniform float u_light_roundness;
uniform float u_light_near; uniform float u_light_far; uniform float u_light_near_edge; uniform float u_light_far_edge;
uniform float u_light_d0; uniform float u_light_alpha; uniform float u_light_max_intensity;
uniform float u_ks; uniform float u_specular_exponent;
out vec4 o_color;
// The receiver in the light's frame (x, y, z = forward): WCtoLC of Listing 12.6 applied to p.
vec3 light_coordinates(vec3 p) {
    vec3 r = p - u_light_position;
    return vec3(dot(r, u_light_x), dot(r, u_light_y), dot(r, u_light_z));
}
vec3 shade(vec3 p, vec3 n, vec3 v, float albedo);
"""
UBER_MAIN = """void main() {
    ivec2 t = ivec2(gl_FragCoord.xy);
    o_color = vec4(shade(texelFetch(u_in0, t, 0).xyz, texelFetch(u_in1, t, 0).xyz, texelFetch(u_in2, t, 0).xyz,
                         texelFetch(u_in3, t, 0).x), 1.0);
}"""
UBER_KEYS = ("intensity", "width", "height", "width_edge", "height_edge", "roundness", "near", "far", "near_edge",
             "far_edge", "d0", "alpha", "max_intensity")


def uberlight_uniforms(light: Mapping[str, Any], material: Mapping[str, Any]) -> dict[str, Any]:
    """The light mapping as uniforms ``u_light_<key>`` (checked as the Python techniques check it; the Fore June
    keys d0, alpha, max_intensity → 0 where absent), its ``axes`` rows as ``u_light_x, u_light_y, u_light_z``, and
    the material's ``ks`` (default 0) and ``specular_exponent`` (default 20)."""

    check_light(light)
    axes = np.asarray(light["axes"], dtype=np.float64).reshape(3, 3)
    u: dict[str, Any] = {"u_light_position": np.asarray(light["position"], dtype=np.float64),
                         "u_light_x": axes[0], "u_light_y": axes[1], "u_light_z": axes[2]}
    u.update({f"u_light_{k}": float(light.get(k, 0.0)) for k in UBER_KEYS})
    u["u_ks"] = float(material.get("ks", 0.0))
    u["u_specular_exponent"] = float(material.get("specular_exponent", 20.0))
    return u


def uberlight_call(run: Run, light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, views: np.ndarray,
                   material: Mapping[str, Any], shadow: np.ndarray | None = None, **_: Any) -> np.ndarray:
    """shade(p, n, v, albedo) per receiver (.r read); the host's shadow visibility multiplies it, as in the Python
    techniques (:func:`~.uberlight.common.shade`)."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    normals, views = (np.asarray(a, dtype=np.float64).reshape(-1, 3) for a in (normals, views))  # as given (unit)
    albedo = np.broadcast_to(np.asarray(material.get("albedo", 1.0), dtype=np.float64), (len(p),))
    uniforms = uberlight_uniforms(light, material)
    out = run([p, normals, views, albedo[:, None]], uniforms)[:, 0].astype(np.float64)
    return out if shadow is None else out * np.asarray(shadow, dtype=np.float64).reshape(-1)


CONTRACT = (
    "vec3 shade(vec3 p, vec3 n, vec3 v, float albedo) -> unshadowed outgoing radiance (.r read; v unit "
    "toward the viewer; the host's shadow multiplies it); uniforms vec3 u_light_position, u_light_x, "
    "u_light_y, u_light_z (the axes rows: x, y, z = forward), float u_light_intensity, u_light_width, "
    "u_light_height, u_light_width_edge, u_light_height_edge, u_light_roundness, u_light_near, "
    "u_light_far, u_light_near_edge, u_light_far_edge, u_light_d0, u_light_alpha, u_light_max_intensity "
    "(0 if absent), u_ks, u_specular_exponent; helper vec3 light_coordinates(vec3 p)"
)

SPEC = register_glsl_family(GLSLFamily(
    "uberlight", "vec3 shade(vec3 p, vec3 n, vec3 v, float albedo)", UBER_DECL, UBER_MAIN,
    uberlight_call, contract=CONTRACT))
