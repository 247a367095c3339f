"""Per-family GLSL glue: the declarations a ``.glsl`` technique sees, the harness's ``main()``, and the
host side that turns a family's Python call into per-receiver float textures and uniforms and the
read-back colour into the family's output. The contracts are documented in
:mod:`validate.local_models.glsl_technique` and ``docs/glsl.md``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ValidateError
from ..geometry import unit
from .registry import FAMILIES

Run = Callable[..., np.ndarray]  # run(inputs: list[(N, k)], uniforms: {name: value}, textures=None) -> (N, 4)


def uniform_bytes(value: Any) -> bytes:
    """A uniform's bytes: Python/NumPy ints → int32, everything else → float32 (arrays flattened)."""
    arr = np.asarray(value)
    if arr.dtype.kind in "iub":
        return np.ascontiguousarray(arr, dtype=np.int32).tobytes()
    return np.ascontiguousarray(arr, dtype=np.float32).tobytes()


def _fetch(names: str) -> str:
    return "\n".join(f"uniform sampler2D u_in{k};" for k in range(len(names.split())))


@dataclass(frozen=True)
class GLSLFamily:
    """How a family's call maps onto its GLSL entry point."""

    name: str
    entry: str
    declarations: str
    main: str
    call: Callable[..., np.ndarray]


# -- brdf ---------------------------------------------------------------------------------------------------
BRDF_DECL = _fetch("n l v") + """
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
    from .brdf import common as brdf_common  # noqa: PLC0415 — at call time: the family packages import this module
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


# -- irradiance ---------------------------------------------------------------------------------------------
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
IRRADIANCE_DECL = _fetch("n") + ENV_DECL + "vec3 irradiance(vec3 n);\n"
IRRADIANCE_MAIN = """void main() {
    o_color = vec4(irradiance(texelFetch(u_in0, ivec2(gl_FragCoord.xy), 0).xyz), 1.0);
}"""


def irradiance_call(run: Run, radiance: np.ndarray, normals: np.ndarray, **_: Any) -> np.ndarray:
    from .irradiance.sh import project_environment  # noqa: PLC0415

    rad = np.asarray(radiance, dtype=np.float64)
    tex = np.concatenate([rad[..., :3], np.ones(rad.shape[:2] + (1,))], axis=-1)
    uniforms = {"u_sh": project_environment(rad, 2), "u_radiance_size": np.array(rad.shape[1::-1], dtype=np.int32)}
    out = run([unit(normals)], uniforms, {"u_radiance": tex})
    return out[:, :3].astype(np.float64)


# -- light --------------------------------------------------------------------------------------------------
LIGHT_DECL = _fetch("p n") + """
uniform int u_light_type;
uniform vec3 u_light_position; uniform vec3 u_light_direction;
uniform float u_light_intensity; uniform float u_light_irradiance;
uniform float u_light_cutoff_angle; uniform float u_light_beam_width;
uniform float u_light_exponent; uniform float u_light_range;
out vec4 o_color;
vec3 shade(vec3 p, vec3 n, vec3 v);
"""
LIGHT_MAIN = """void main() {
    ivec2 t = ivec2(gl_FragCoord.xy);
    vec3 n = texelFetch(u_in1, t, 0).xyz;
    o_color = vec4(shade(texelFetch(u_in0, t, 0).xyz, n, n), 1.0);
}"""
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
    from .light import common as light_common  # noqa: PLC0415 — at call time (import cycle via the family packages)
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
    from .light import common as light_common  # noqa: PLC0415 — at call time (import cycle via the family packages)
    p, n = light_common.as_points(points, normals)
    n = unit(n)
    e = run([p, n], light_uniforms(light))[:, 0].astype(np.float64)
    return host_shadow(light, p, n, e, visible)


# -- arealight ----------------------------------------------------------------------------------------------
AREA_DECL = _fetch("p n") + """
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


# -- shadow -------------------------------------------------------------------------------------------------
SHADOW_DECL = _fetch("w p n") + """
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
    from .shadow.shadow_map import DEPTH_LSB, PolygonOffset  # noqa: PLC0415

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


# -- specular -----------------------------------------------------------------------------------------------
SPECULAR_DECL = _fetch("n v") + ENV_DECL + """
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
    from ..geometry import frame  # noqa: PLC0415

    r = unit(np.asarray(r, dtype=np.float64).reshape(-1, 3))
    t, b = frame(r)
    steps = [(i, j) for i in (-1, 0, 1) for j in (-1, 0, 1)]
    return np.concatenate([r + DILATE_RAD * (i * t + j * b) for i, j in steps])


def prefiltered_map(radiance: np.ndarray, model: str, brdf: Mapping[str, Any], r: np.ndarray) -> Any:
    """(face size, () -> padded texture (6 (N+2), N+2, 4)) of the model's prefiltered cube map: GGX P_α of
    :func:`~.specular.split_sum.prefilter_ggx_cube` for ggx / ggx_plastic, Phong P_{s+1} of
    :func:`~.specular.prefiltered_specular.prefilter_phong_cube` (``phong_prefiltered``'s map) for phong."""
    from .specular import common as spec_common  # noqa: PLC0415 — at call time (import cycle)
    from .specular import prefiltered_specular as ps  # noqa: PLC0415
    from .specular import split_sum as ss  # noqa: PLC0415

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
    from .irradiance.sh import project_environment  # noqa: PLC0415
    from .specular import split_sum as ss  # noqa: PLC0415
    from .specular.common import reflect  # noqa: PLC0415

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


# -- specular_arealight -------------------------------------------------------------------------------------
SPEC_AREA_DECL = _fetch("p n v") + """
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
    from .specular_arealight.common import brdf_params  # noqa: PLC0415 — at call time (import cycle)

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


# -- uberlight ----------------------------------------------------------------------------------------------
UBER_DECL = _fetch("p n v a") + """
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
    from .uberlight.common import check_light  # noqa: PLC0415 — at call time (import cycle via the family packages)

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


GLSL_CONTRACTS = {
    "brdf": "vec3 brdf(vec3 n, vec3 l, vec3 v) -> f_r(l, v)·max(0, n·l), zero below either horizon; uniforms "
            "vec3 u_albedo, u_ks, u_eta, u_k; float u_exponent, u_phong_exponent, u_alpha, u_sigma, u_minnaert_k; "
            "int u_distribution (0 beckmann, 1 ggx)",
    "irradiance": "vec3 irradiance(vec3 n) -> E(n) (not E/π); uniforms vec3 u_sh[9] (radiance SH L00, L1m1, L10, "
                  "L11, L2m2, L2m1, L20, L21, L22: orthonormal, no Condon–Shortley phase, world xyz, z polar), "
                  "sampler2D u_radiance (lat-long, row 0 = zenith, texelFetch), ivec2 u_radiance_size; "
                  "helper vec3 env_radiance(vec3 d)",
    "light": "vec3 shade(vec3 p, vec3 n, vec3 v) -> unshadowed E in W/m² (.r read; v = n; V applied by the host); "
             "uniforms int u_light_type (0 point, 1 spot, 2 directional), vec3 u_light_position, u_light_direction, "
             "float u_light_intensity, u_light_irradiance, u_light_cutoff_angle, u_light_beam_width (degrees), "
             "u_light_exponent, u_light_range",
    "arealight": "vec3 shade(vec3 p, vec3 n, vec3 v) -> E in W/m² (.r read; v = n); uniforms int u_area_shape "
                 "(0 disc, 1 sphere, 2 rectangle), vec3 u_area_center, u_area_normal (the emitting side), "
                 "u_area_tangent, float u_area_radius, vec2 u_area_size, float u_area_radiance",
    "specular": "vec3 specular(vec3 n, vec3 v) -> outgoing radiance L_o (RGB; n, v unit, v toward the viewer); "
                "uniforms int u_brdf_model (0 phong, 1 ggx, 2 ggx_plastic), float u_exponent, u_reflectance, u_alpha, "
                "u_f0, u_eta, u_rho; the environment as for irradiance (u_sh[9], u_radiance, u_radiance_size, "
                "env_radiance); sampler2D u_prefiltered (the model's prefiltered cube map: GGX P_α, Phong P_{s+1}), "
                "int u_prefiltered_face, helper vec3 prefiltered_radiance(vec3 d); sampler2D u_dfg (.rg = A, B at "
                "μ_i, α_j), int u_dfg_size, helper vec2 env_brdf(float mu, float alpha)",
    "specular_arealight": "vec3 shade(vec3 p, vec3 n, vec3 v) -> outgoing radiance (RGB) of a GGX BRDF lit by the "
                          "light; uniforms int u_area_shape (0 disc, 1 sphere, 2 rectangle, 3 tube), vec3 "
                          "u_area_center, u_area_normal, u_area_tangent, u_area_axis, float u_area_radius, vec2 "
                          "u_area_size, float u_area_length, u_area_radiance; float u_alpha (GGX α), vec3 u_f0",
    "shadow": "float visibility(vec3 p, vec3 n, vec4 w) -> V in [0, 1]; w = (x, y, z_w, z): continuous texel "
              "coordinates, clamped window depth and view depth of p (ShadowMap.window_coords); uniforms "
              "sampler2D u_shadow_map (R×R, .r window depth D (1 = empty), .g slope DZ, texel (i, j) = "
              "texelFetch(ivec2(i, j))), int u_shadow_resolution, float u_texel_tan, u_near, u_far, "
              "u_depth_scale, u_offset_factor, u_offset_units, u_depth_lsb (glPolygonOffset(2, 4), 2^-24), "
              "vec3 u_light_position, u_light_normal, float u_light_radius",
    "uberlight": "vec3 shade(vec3 p, vec3 n, vec3 v, float albedo) -> unshadowed outgoing radiance (.r read; v unit "
                 "toward the viewer; the host's shadow multiplies it); uniforms vec3 u_light_position, u_light_x, "
                 "u_light_y, u_light_z (the axes rows: x, y, z = forward), float u_light_intensity, u_light_width, "
                 "u_light_height, u_light_width_edge, u_light_height_edge, u_light_roundness, u_light_near, "
                 "u_light_far, u_light_near_edge, u_light_far_edge, u_light_d0, u_light_alpha, u_light_max_intensity "
                 "(0 if absent), u_ks, u_specular_exponent; helper vec3 light_coordinates(vec3 p)",
}

SPECS: dict[str, GLSLFamily] = {
    "brdf": GLSLFamily("brdf", "vec3 brdf(vec3 n, vec3 l, vec3 v)", BRDF_DECL, BRDF_MAIN, brdf_call),
    "irradiance": GLSLFamily("irradiance", "vec3 irradiance(vec3 n)", IRRADIANCE_DECL, IRRADIANCE_MAIN,
                             irradiance_call),
    "light": GLSLFamily("light", "vec3 shade(vec3 p, vec3 n, vec3 v)", LIGHT_DECL, LIGHT_MAIN, light_call),
    "arealight": GLSLFamily("arealight", "vec3 shade(vec3 p, vec3 n, vec3 v)", AREA_DECL, LIGHT_MAIN,
                            arealight_call),
    "specular": GLSLFamily("specular", "vec3 specular(vec3 n, vec3 v)", SPECULAR_DECL, SPECULAR_MAIN, specular_call),
    "specular_arealight": GLSLFamily("specular_arealight", "vec3 shade(vec3 p, vec3 n, vec3 v)", SPEC_AREA_DECL,
                                     SPEC_AREA_MAIN, specular_arealight_call),
    "shadow": GLSLFamily("shadow", "float visibility(vec3 p, vec3 n, vec4 w)", SHADOW_DECL, SHADOW_MAIN,
                         shadow_call),
    "uberlight": GLSLFamily("uberlight", "vec3 shade(vec3 p, vec3 n, vec3 v, float albedo)", UBER_DECL, UBER_MAIN,
                            uberlight_call),
}


for _name, _text in GLSL_CONTRACTS.items():
    FAMILIES[_name].glsl_contract = _text  # shown by `validate list`, documented in docs/glsl.md
