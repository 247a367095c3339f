"""The ``irradiance`` family's GLSL adapter: the declarations a ``.glsl`` technique of the family sees, the
harness's ``main()``, the host side of a call and the contract (:mod:`validate.local_models.glsl_adapter`,
``docs/glsl.md``). Loaded with the family; it registers the adapter and no technique."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...geometry import unit
from ..glsl_adapter import ENV_DECL, GLSLFamily, Run, fetch_inputs, register_glsl_family
from .sh import project_environment

IRRADIANCE_DECL = fetch_inputs("n") + ENV_DECL + "vec3 irradiance(vec3 n);\n"
IRRADIANCE_MAIN = """void main() {
    o_color = vec4(irradiance(texelFetch(u_in0, ivec2(gl_FragCoord.xy), 0).xyz), 1.0);
}"""


def irradiance_call(run: Run, radiance: np.ndarray, normals: np.ndarray, **_: Any) -> np.ndarray:
    rad = np.asarray(radiance, dtype=np.float64)
    tex = np.concatenate([rad[..., :3], np.ones(rad.shape[:2] + (1,))], axis=-1)
    uniforms = {"u_sh": project_environment(rad, 2), "u_radiance_size": np.array(rad.shape[1::-1], dtype=np.int32)}
    out = run([unit(normals)], uniforms, {"u_radiance": tex})
    return out[:, :3].astype(np.float64)


CONTRACT = (
    "vec3 irradiance(vec3 n) -> E(n) (not E/π); uniforms vec3 u_sh[9] (radiance SH L00, L1m1, L10, "
    "L11, L2m2, L2m1, L20, L21, L22: orthonormal, no Condon–Shortley phase, world xyz, z polar), "
    "sampler2D u_radiance (lat-long, row 0 = zenith, texelFetch), ivec2 u_radiance_size; "
    "helper vec3 env_radiance(vec3 d)"
)

SPEC = register_glsl_family(GLSLFamily(
    "irradiance", "vec3 irradiance(vec3 n)", IRRADIANCE_DECL, IRRADIANCE_MAIN, irradiance_call, contract=CONTRACT))
