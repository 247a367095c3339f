"""The ``brdf`` family's GLSL adapter: the declarations a ``.glsl`` technique of the family sees, the
harness's ``main()``, the host side of a call and the contract (:mod:`validate.local_models.glsl_adapter`,
``docs/glsl.md``). Loaded with the family; it registers the adapter and no technique."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...geometry import unit
from ..glsl_adapter import GLSLFamily, Run, fetch_inputs, register_glsl_family
from . import common as brdf_common

BRDF_DECL = fetch_inputs("n l v") + """
uniform vec3 u_albedo; uniform vec3 u_ks; uniform vec3 u_eta; uniform vec3 u_k;
uniform float u_exponent; uniform float u_phong_exponent; uniform float u_alpha;
uniform float u_sigma; uniform float u_minnaert_k;
uniform int u_distribution;
out vec4 o_color;
vec3 brdf(vec3 n, vec3 l, vec3 v);
"""
BRDF_MAIN = """void main() {
    ivec2 t = ivec2(gl_FragCoord.xy);
    o_color = vec4(brdf(texelFetch(u_in0, t, 0).xyz, texelFetch(u_in1, t, 0).xyz, texelFetch(u_in2, t, 0).xyz), 1.0);
}"""


def brdf_uniforms(params: Mapping[str, Any], who: str) -> dict[str, Any]:
    """The ``params`` mapping as uniforms (scalars broadcast to RGB for the vec3 ones)."""
    rgb = {k: np.broadcast_to(brdf_common.param(params, k, who), (3,)) for k in ("albedo", "ks", "eta", "k")}
    scal = {k: float(np.mean(brdf_common.param(params, k, who)))
            for k in ("exponent", "phong_exponent", "alpha", "sigma", "minnaert_k")}
    dist = str(params.get("distribution", brdf_common.DEFAULTS["distribution"])).lower()
    return {**{f"u_{k}": v for k, v in rgb.items()}, **{f"u_{k}": v for k, v in scal.items()},
            "u_distribution": 1 if dist == "ggx" else 0}


def brdf_call(run: Run, params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray,
              **_: Any) -> np.ndarray:
    out = run([unit(normals), unit(lights), unit(views)], brdf_uniforms(params, "glsl"))
    return out[:, :3].astype(np.float64)


CONTRACT = (
    "vec3 brdf(vec3 n, vec3 l, vec3 v) -> f_r(l, v)·max(0, n·l), zero below either horizon; uniforms "
    "vec3 u_albedo, u_ks, u_eta, u_k; float u_exponent, u_phong_exponent, u_alpha, u_sigma, u_minnaert_k; "
    "int u_distribution (0 beckmann, 1 ggx)"
)

SPEC = register_glsl_family(GLSLFamily(
    "brdf", "vec3 brdf(vec3 n, vec3 l, vec3 v)", BRDF_DECL, BRDF_MAIN, brdf_call, contract=CONTRACT))
