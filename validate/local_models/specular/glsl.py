"""The ``specular`` family's GLSL adapter: the declarations a ``.glsl`` technique of the family sees, the
harness's ``main()``, the host side of a call and the contract (:mod:`validate.local_models.glsl_adapter`,
``docs/glsl.md``). Loaded with the family; it registers the adapter and no technique."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...geometry import frame, unit
from ..glsl_adapter import ENV_DECL, GLSLFamily, Run, fetch_inputs, register_glsl_family
from ..irradiance.sh import project_environment
from . import common as spec_common
from .common import reflect

SPECULAR_DECL = fetch_inputs("n v") + ENV_DECL + """
uniform int u_brdf_model;
uniform float u_exponent; uniform float u_reflectance; uniform float u_alpha; uniform float u_f0;
uniform float u_eta; uniform float u_rho;
uniform sampler2D u_prefiltered; uniform int u_prefiltered_face;
uniform sampler2D u_dfg; uniform int u_dfg_size;
// The prefiltered cube map at direction d (need not be unit): CubeMap.lookup's face choice, coordinates and
// bilinear weights in float32 on the padded faces (face f, padded row y, column x at texel (x, f (N+2) + y)).
vec3 prefiltered_radiance(vec3 d) {
    int n = u_prefiltered_face, p = n + 2;
    float ax = abs(d.x), ay = abs(d.y), az = abs(d.z);
    bool use_x = ax >= ay && ax >= az;
    bool use_y = !use_x && ay >= az;
    int face = use_x ? (d.x >= 0.0 ? 0 : 1) : (use_y ? (d.y >= 0.0 ? 2 : 3) : (d.z >= 0.0 ? 4 : 5));
    float sc = use_x ? (d.x >= 0.0 ? -d.z : d.z) : (use_y ? d.x : (d.z >= 0.0 ? d.x : -d.x));
    float tc = use_x ? -d.y : (use_y ? (d.y >= 0.0 ? d.z : -d.z) : -d.y);
    float ma = max(use_x ? ax : (use_y ? ay : az), 1e-30);
    float fx = (sc / ma + 1.0) * (0.5 * float(n)) - 0.5;
    float fy = (tc / ma + 1.0) * (0.5 * float(n)) - 0.5;
    float x0 = floor(fx), y0 = floor(fy);
    float wx = fx - x0, wy = fy - y0;
    int ix = int(clamp(x0 + 1.0, 0.0, float(p - 2)));
    int iy = face * p + int(clamp(y0 + 1.0, 0.0, float(p - 2)));
    vec3 a = mix(texelFetch(u_prefiltered, ivec2(ix, iy), 0).rgb,
                 texelFetch(u_prefiltered, ivec2(ix + 1, iy), 0).rgb, wx);
    vec3 b = mix(texelFetch(u_prefiltered, ivec2(ix, iy + 1), 0).rgb,
                 texelFetch(u_prefiltered, ivec2(ix + 1, iy + 1), 0).rgb, wx);
    return mix(a, b, wy);
}
// (A, B) of the environment-BRDF table at (mu, alpha): DFGTable.lookup (cell centres (i + 1/2)/n, clamped to the
// edge cells, bilinear in float32); texel (i, j) = (A, B) at mu_i, alpha_j.
vec2 env_brdf(float mu, float alpha) {
    float nf = float(u_dfg_size);
    float x = clamp(mu * nf - 0.5, 0.0, nf - 1.0), y = clamp(alpha * nf - 0.5, 0.0, nf - 1.0);
    float x0 = min(floor(x), nf - 2.0), y0 = min(floor(y), nf - 2.0);
    float wx = x - x0, wy = y - y0;
    ivec2 b = ivec2(int(x0), int(y0));
    vec2 lo = mix(texelFetch(u_dfg, b, 0).rg, texelFetch(u_dfg, b + ivec2(1, 0), 0).rg, wx);
    vec2 hi = mix(texelFetch(u_dfg, b + ivec2(0, 1), 0).rg, texelFetch(u_dfg, b + ivec2(1, 1), 0).rg, wx);
    return mix(lo, hi, wy);
}
vec3 specular(vec3 n, vec3 v);
"""
SPECULAR_MAIN = """void main() {
    ivec2 t = ivec2(gl_FragCoord.xy);
    o_color = vec4(specular(texelFetch(u_in0, t, 0).xyz, texelFetch(u_in1, t, 0).xyz), 1.0);
}"""
SPECULAR_MODELS = {"phong": 0, "ggx": 1, "ggx_plastic": 2}
DILATE_RAD = 1e-4  # the prefiltered map also covers directions 1e-4 rad around each host r (module note)


def footprint_directions(r: np.ndarray) -> np.ndarray:
    """r and the 8 directions DILATE_RAD away along ±t, ±b, ±t ± b: the sparse prefiltered map is evaluated on
    their lookup footprint, so the shader's float32 r (≲ 1e-6 rad from the host's float64 r) never reads a
    texel the map left unevaluated (a cell or face boundary that close to r is crossed by one of them)."""

    r = unit(np.asarray(r, dtype=np.float64).reshape(-1, 3))
    t, b = frame(r)
    steps = [(i, j) for i in (-1, 0, 1) for j in (-1, 0, 1)]
    return np.concatenate([r + DILATE_RAD * (i * t + j * b) for i, j in steps])


def prefiltered_map(radiance: np.ndarray, model: str, brdf: Mapping[str, Any], r: np.ndarray) -> Any:
    """(face size, () -> padded texture (6 (N+2), N+2, 4)) of the model's prefiltered cube map: GGX P_α of
    :func:`~.specular.split_sum.prefilter_ggx_cube` for ggx / ggx_plastic, Phong P_{s+1} of
    :func:`~.specular.prefiltered_specular.prefilter_phong_cube` (``phong_prefiltered``'s map) for phong."""
    # technique modules at call time: imported with this module they would register before their turn
    from . import prefiltered_specular as ps  # noqa: PLC0415
    from . import split_sum as ss  # noqa: PLC0415

    r = np.asarray(r, dtype=np.float64)
    rkey = spec_common.array_digest(r)  # the footprint directions are a function of r: r keys the map
    if model == "phong":
        s = ps.map_exponent_for_brdf(float(brdf["exponent"]))
        face = ps.phong_face_size(s)
        key = ("glsl phong", spec_common.array_digest(radiance), s, rkey)
        build = lambda: ps.prefilter_phong_cube(radiance, s, needed=footprint_directions(r))  # noqa: E731
    else:
        alpha = float(brdf["alpha"])
        face = ss.ggx_face_size(alpha)  # checks α ∈ [1e-3, 1] as split_sum_ggx does
        key = ("glsl ggx", spec_common.array_digest(radiance), alpha, rkey)
        build = lambda: ss.prefilter_ggx_cube(radiance, alpha, needed=footprint_directions(r))  # noqa: E731

    def texture() -> np.ndarray:
        pad = spec_common.cached(key, build).padded  # type: ignore[attr-defined]
        tex = np.ones(pad.shape[:3] + (4,), dtype=np.float32)
        tex[..., :3] = pad[..., :3]
        return tex.reshape(-1, pad.shape[2], 4)
    return face, texture


def specular_uniforms(brdf: Mapping[str, Any]) -> dict[str, Any]:
    """The BRDF mapping as uniforms (absent keys → the Python techniques' defaults)."""
    model = brdf.get("model")
    if model not in SPECULAR_MODELS or ("alpha" if model != "phong" else "exponent") not in brdf:
        raise ValidateError(f"specular BRDF {dict(brdf)!r}: GLSL specular techniques take {{'model': 'phong', "
                            "'exponent': s}, {'model': 'ggx', 'alpha': α, 'f0'} or {'model': 'ggx_plastic', 'alpha', "
                            "'eta', 'rho'}")
    return {"u_brdf_model": SPECULAR_MODELS[model], "u_exponent": float(brdf.get("exponent", 0.0)),
            "u_reflectance": float(brdf.get("reflectance", 1.0)), "u_alpha": float(brdf.get("alpha", 0.0)),
            "u_f0": float(brdf.get("f0", 1.0)), "u_eta": float(brdf.get("eta", 1.49)),
            "u_rho": float(brdf.get("rho", 0.5))}


def specular_call(run: Run, radiance: np.ndarray, brdf: Mapping[str, Any], normals: np.ndarray, views: np.ndarray,
                  **_: Any) -> np.ndarray:
    """Environment as for irradiance (u_sh, u_radiance, env_radiance); the model's prefiltered cube map and the
    DFG table (:func:`~.specular.split_sum.default_dfg_table`) built only where the shader reads them."""
    from . import split_sum as ss  # noqa: PLC0415 — a technique module: at call time, as above

    uniforms = specular_uniforms(brdf)
    rad = np.asarray(radiance, dtype=np.float64)
    n, v = unit(normals), unit(views)
    face, pre = prefiltered_map(rad, str(brdf["model"]), brdf, reflect(n, v))

    def dfg() -> np.ndarray:
        t = ss.default_dfg_table()
        return np.stack([t.a, t.b, np.zeros_like(t.a), np.ones_like(t.a)], axis=-1)
    uniforms.update({"u_sh": lambda: project_environment(rad, 2), "u_prefiltered_face": np.int32(face),
                     "u_dfg_size": np.int32(ss.DFG_SIZE),
                     "u_radiance_size": np.array(rad.shape[1::-1], dtype=np.int32)})
    tex = np.concatenate([rad[..., :3], np.ones(rad.shape[:2] + (1,))], axis=-1)
    out = run([n, v], uniforms, {"u_radiance": tex, "u_prefiltered": pre, "u_dfg": dfg})
    return out[:, :3].astype(np.float64)


CONTRACT = (
    "vec3 specular(vec3 n, vec3 v) -> outgoing radiance L_o (RGB; n, v unit, v toward the viewer); "
    "uniforms int u_brdf_model (0 phong, 1 ggx, 2 ggx_plastic), float u_exponent, u_reflectance, u_alpha, "
    "u_f0, u_eta, u_rho; the environment as for irradiance (u_sh[9], u_radiance, u_radiance_size, "
    "env_radiance); sampler2D u_prefiltered (the model's prefiltered cube map: GGX P_α, Phong P_{s+1}), "
    "int u_prefiltered_face, helper vec3 prefiltered_radiance(vec3 d); sampler2D u_dfg (.rg = A, B at "
    "μ_i, α_j), int u_dfg_size, helper vec2 env_brdf(float mu, float alpha)"
)

SPEC = register_glsl_family(GLSLFamily(
    "specular", "vec3 specular(vec3 n, vec3 v)", SPECULAR_DECL, SPECULAR_MAIN, specular_call, contract=CONTRACT))
