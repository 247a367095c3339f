"""The ``shadow`` family's GLSL adapter: the declarations a ``.glsl`` technique of the family sees, the
harness's ``main()``, the host side of a call and the contract (:mod:`validate.local_models.glsl_adapter`,
``docs/glsl.md``). Loaded with the family; it registers the adapter and no technique."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...geometry import unit
from ..glsl_adapter import GLSLFamily, Run, fetch_inputs, register_glsl_family
from .shadow_map import DEPTH_LSB, PolygonOffset

SHADOW_DECL = fetch_inputs("w p n") + """
uniform sampler2D u_shadow_map;
uniform int u_shadow_resolution;
uniform float u_texel_tan; uniform float u_near; uniform float u_far; uniform float u_depth_scale;
uniform float u_offset_factor; uniform float u_offset_units; uniform float u_depth_lsb;
uniform vec3 u_light_position; uniform vec3 u_light_normal; uniform float u_light_radius;
out vec4 o_color;
float visibility(vec3 p, vec3 n, vec4 w);
"""
SHADOW_MAIN = """void main() {
    ivec2 t = ivec2(gl_FragCoord.xy);
    o_color = vec4(visibility(texelFetch(u_in1, t, 0).xyz, texelFetch(u_in2, t, 0).xyz, texelFetch(u_in0, t, 0)));
}"""


def shadow_call(run: Run, shadow_map: Any, light: Any, points: np.ndarray, normals: np.ndarray,
                **_: Any) -> np.ndarray:
    """Window coordinates (x, y, z_w, z) from :meth:`ShadowMap.window_coords` (host, float64 → float32);
    the map as an R × R texture (.r window depth D, 1 = empty; .g depth slope DZ per texel)."""

    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    n = unit(normals)
    x, y, z_w, z = shadow_map.window_coords(p)
    r = shadow_map.resolution
    tex = np.zeros((r, r, 4))
    tex[..., 0] = shadow_map.depth_image()
    tex[..., 1] = np.array(shadow_map.slope, dtype=np.float64).reshape(r, r)
    v, off = shadow_map.view, PolygonOffset()
    uniforms = {"u_shadow_resolution": np.int32(r), "u_texel_tan": shadow_map.texel_tan, "u_near": v.near,
                "u_far": v.far, "u_depth_scale": v.depth_scale, "u_offset_factor": off.factor,
                "u_offset_units": off.units, "u_depth_lsb": DEPTH_LSB,
                "u_light_position": np.asarray(light.centre, dtype=np.float64),
                "u_light_normal": np.asarray(light.normal, dtype=np.float64), "u_light_radius": float(light.radius)}
    out = run([np.stack([x, y, z_w, z], axis=1), p, n], uniforms, {"u_shadow_map": tex})
    return out[:, 0].astype(np.float64)


CONTRACT = (
    "float visibility(vec3 p, vec3 n, vec4 w) -> V in [0, 1]; w = (x, y, z_w, z): continuous texel "
    "coordinates, clamped window depth and view depth of p (ShadowMap.window_coords); uniforms "
    "sampler2D u_shadow_map (R×R, .r window depth D (1 = empty), .g slope DZ, texel (i, j) = "
    "texelFetch(ivec2(i, j))), int u_shadow_resolution, float u_texel_tan, u_near, u_far, "
    "u_depth_scale, u_offset_factor, u_offset_units, u_depth_lsb (glPolygonOffset(2, 4), 2^-24), "
    "vec3 u_light_position, u_light_normal, float u_light_radius"
)

SPEC = register_glsl_family(GLSLFamily(
    "shadow", "float visibility(vec3 p, vec3 n, vec4 w)", SHADOW_DECL, SHADOW_MAIN, shadow_call, contract=CONTRACT))
