"""The generic part of a family's GLSL adapter. Each family's adapter lives in its folder (``<family>/glsl.py``):
the declarations a ``.glsl`` technique of the family sees, the harness's ``main()``, the host side that turns the
family's Python call into per-receiver float textures and uniforms and the read-back colour into the family's
output, and the contract text; it registers itself with :func:`register_glsl_family` when its family is loaded,
as a technique does. Here: the adapter's shape (:class:`GLSLFamily`), the registry (:data:`SPECS`), the
uniforms' bytes and the declarations two families share (the environment lookup, the shading ``main()``). The
contracts are documented in :mod:`validate.local_models.glsl_technique` and ``docs/glsl.md``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .registry import FAMILIES

Run = Callable[..., np.ndarray]  # run(inputs: list[(N, k)], uniforms: {name: value}, textures=None) -> (N, 4)


def uniform_bytes(value: Any) -> bytes:
    """A uniform's bytes: Python/NumPy ints → int32, everything else → float32 (arrays flattened)."""
    arr = np.asarray(value)
    if arr.dtype.kind in "iub":
        return np.ascontiguousarray(arr, dtype=np.int32).tobytes()
    return np.ascontiguousarray(arr, dtype=np.float32).tobytes()


def fetch_inputs(names: str) -> str:
    """The per-receiver input textures ``u_in0`` … of a family's inputs (space-separated names)."""
    return "\n".join(f"uniform sampler2D u_in{k};" for k in range(len(names.split())))


@dataclass(frozen=True)
class GLSLFamily:
    """How a family's call maps onto its GLSL entry point."""

    name: str
    entry: str
    declarations: str
    main: str
    call: Callable[..., np.ndarray]
    contract: str = ""  # the entry point and its uniforms in words (`validate list`, docs/glsl.md)


SPECS: dict[str, GLSLFamily] = {}  # family name -> its adapter, in the order the families load


def register_glsl_family(spec: GLSLFamily) -> GLSLFamily:
    """Register a family's adapter (its ``glsl.py`` does, on import) and show its contract on the family."""
    SPECS[spec.name] = spec
    FAMILIES[spec.name].glsl_contract = spec.contract  # shown by `validate list`, documented in docs/glsl.md
    return spec


# the environment lookup the irradiance and specular families' techniques see
ENV_DECL = """
uniform vec3 u_sh[9];
uniform sampler2D u_radiance;
uniform ivec2 u_radiance_size;
out vec4 o_color;
// Radiance of the lat-long map toward unit d, bilinear in (phi, theta) as Mitsuba's envmap: row i at
// theta = i pi/(H-1), column j at phi = 2 pi (j + 1/2)/W, wrapping in phi. Done with texelFetch and the
// weights in float32 (texture()'s hardware weights are quantised: llvmpipe errs ~2e-5 of a texel step).
// Angles through atan2_precise: Mesa's acos errs 1.6e-4 rad and its atan 3.3e-6 (measured), one Newton
// step on r sin(t - theta) with the precise sin/cos (<= 7.4e-8) brings atan to float32 rounding.
float atan2_precise(float y, float x) {
    float t = atan(y, x);
    return t + (y * cos(t) - x * sin(t)) / max(length(vec2(x, y)), 1e-30);
}
vec3 env_radiance(vec3 d) {
    float theta = atan2_precise(length(d.xz), d.y);
    float phi = atan2_precise(d.x, -d.z);
    if (phi < 0.0) phi += 6.28318530717958648;
    int W = u_radiance_size.x, H = u_radiance_size.y;
    float x = phi / 6.28318530717958648 * float(W) - 0.5;
    float y = theta / 3.14159265358979324 * float(H - 1);
    float x0 = floor(x), y0 = min(floor(y), float(H - 2));
    float fx = x - x0, fy = y - y0;
    int i0 = int(y0), j0 = (int(x0) % W + W) % W, j1 = (j0 + 1) % W;
    vec3 a = mix(texelFetch(u_radiance, ivec2(j0, i0), 0).rgb,
                 texelFetch(u_radiance, ivec2(j1, i0), 0).rgb, fx);
    vec3 b = mix(texelFetch(u_radiance, ivec2(j0, i0 + 1), 0).rgb,
                 texelFetch(u_radiance, ivec2(j1, i0 + 1), 0).rgb, fx);
    return mix(a, b, fy);
}
"""

# the shading main() of the light and arealight families
LIGHT_MAIN = """void main() {
    ivec2 t = ivec2(gl_FragCoord.xy);
    vec3 n = texelFetch(u_in1, t, 0).xyz;
    o_color = vec4(shade(texelFetch(u_in0, t, 0).xyz, n, n), 1.0);
}"""
