"""GLSL techniques: a ``.glsl`` file implementing a family's GLSL entry point becomes a registered technique.

A file starts with header lines ``// validate: key=value``:

``family``       brdf | irradiance | specular | light | arealight | specular_arealight | shadow | uberlight (required)
``name``         the technique's name (default: the file's stem)
``description``  one line
``thresholds``   JSON object ``{"metric": limit, ...}`` (the family's metric names, as for Python techniques)
``source``       where the thresholds / the formula come from
``runtime``      ``llvmpipe`` (default, desktop GLSL 4.50 core) or ``webgl2`` (GLSL ES 3.00, SwiftShader)
``seed``         optional: the seed text and section the shader transcribes (shown by ``validate list``)
``lights``       light family only: the light types modelled, comma-separated (point, spot, directional)
``shapes``       arealight / specular_arealight: the shapes modelled, comma-separated (disc, sphere, rectangle, tube)
``brdf``         specular family only: the BRDF models handled, comma-separated (phong, ggx, ggx_plastic)

Entry points and the uniforms the harness declares (do not redeclare them; see docs/glsl.md):

* brdf:       ``vec3 brdf(vec3 n, vec3 l, vec3 v)`` → the *cosine-weighted* BRDF f_r(l, v)·max(0, n·l),
  the same quantity as the Python contract (n, l, v unit, any frame); zero below either horizon.
  Uniforms ``vec3 u_albedo, u_ks, u_eta, u_k``; ``float u_exponent, u_phong_exponent, u_alpha, u_sigma,
  u_minnaert_k``; ``int u_distribution`` (0 beckmann, 1 ggx) — the ``params`` mapping, defaults as in
  :data:`validate.local_models.brdf.common.DEFAULTS`.
* irradiance: ``vec3 irradiance(vec3 n)`` → E(n) = ∫ L max(0, n·ω) dω (not E/π). Uniforms
  ``vec3 u_sh[9]``: the environment's radiance SH coefficients L_lm from
  :func:`validate.local_models.irradiance.sh.project_environment` (real SH without Condon–Shortley phase, world
  (x, y, z) polynomial, order L00, L1m1, L10, L11, L2m2, L2m1, L20, L21, L22, orthonormal:
  ∫ Y_k Y_k' dω = δ_kk'); ``sampler2D u_radiance``: the lat-long map (RGB in .rgb, array row i = texel
  row i, NEAREST: read it with ``texelFetch``), in Mitsuba's ``envmap`` convention
  (:mod:`validate.scenes.latlong`): row 0 is the zenith (+y), row H−1 the nadir, column j at
  φ = 2π(j + ½)/W, φ = atan2(x, −z); ``ivec2 u_radiance_size`` (W, H); and the helper
  ``vec3 env_radiance(vec3 d)``, Mitsuba's bilinear lookup in float32.
* light:      ``vec3 shade(vec3 p, vec3 n, vec3 v)`` → the *unshadowed* irradiance E (W/m², not E/π) in
  every channel (the harness reads .r); v = n (the family has no viewer). Uniforms ``int u_light_type``
  (0 point, 1 spot, 2 directional); ``vec3 u_light_position, u_light_direction`` (direction: the way the
  light travels, unit); ``float u_light_intensity`` (W/sr), ``u_light_irradiance`` (W/m², directional),
  ``u_light_cutoff_angle``, ``u_light_beam_width`` (degrees), ``u_light_exponent``, ``u_light_range``.
  The shadow term V is the host's, as for the Python techniques: the scene's shadow-ray test toward the
  light's position (point, spot) or against its direction (directional) multiplies the result.
* arealight:  ``vec3 shade(vec3 p, vec3 n, vec3 v)`` → irradiance E (W/m², .r read, v = n) from the area
  light; uniforms ``int u_area_shape`` (0 disc, 1 sphere, 2 rectangle), ``vec3 u_area_center, u_area_normal``
  (the emitting side's normal), ``u_area_tangent``, ``float u_area_radius``, ``vec2 u_area_size``,
  ``float u_area_radiance`` (W/(m² sr)); no shadowing (the family's scenes have no occluders).
* specular:   ``vec3 specular(vec3 n, vec3 v)`` → outgoing radiance L_o (RGB) toward unit v. The environment
  as for irradiance (``u_sh``, ``u_radiance``, ``u_radiance_size``, ``env_radiance``); the BRDF mapping as
  ``int u_brdf_model`` (0 phong, 1 ggx, 2 ggx_plastic), ``float u_exponent, u_reflectance, u_alpha, u_f0, u_eta,
  u_rho``; ``sampler2D u_prefiltered``, ``int u_prefiltered_face``: the model's prefiltered cube map (GGX P_α of
  split_sum, Phong P_{s+1} of phong_prefiltered; padded faces stacked, face f texel (x, f(N+2) + y)) with the
  helper ``vec3 prefiltered_radiance(vec3 d)`` (CubeMap.lookup in float32); ``sampler2D u_dfg``, ``int
  u_dfg_size``: the DFG table (.rg = A, B at μ_i, α_j) with ``vec2 env_brdf(float mu, float alpha)``
  (DFGTable.lookup). Both are built only when the program reads them.
* specular_arealight: ``vec3 shade(vec3 p, vec3 n, vec3 v)`` → outgoing radiance (RGB) of a GGX BRDF; the
  arealight uniforms with ``u_area_shape`` 3 = tube, ``vec3 u_area_axis``, ``float u_area_length``; ``float
  u_alpha`` (GGX α), ``vec3 u_f0``.
* uberlight:  ``vec3 shade(vec3 p, vec3 n, vec3 v, float albedo)`` → the unshadowed outgoing radiance (.r read; the
  host multiplies by ``shadow``); every light key as ``u_light_<key>`` (``vec3 u_light_position``, the ``axes`` rows
  ``vec3 u_light_x, u_light_y, u_light_z``; ``float u_light_intensity, u_light_width, u_light_height,
  u_light_width_edge, u_light_height_edge, u_light_roundness, u_light_near, u_light_far, u_light_near_edge,
  u_light_far_edge, u_light_d0, u_light_alpha, u_light_max_intensity``), the material's ``float u_ks,
  u_specular_exponent``; helper ``vec3 light_coordinates(vec3 p)``.
* shadow:     ``float visibility(vec3 p, vec3 n, vec4 w)`` → V′ ∈ [0, 1]; w = (x, y, z_w, z), the receiver's
  continuous texel coordinates (texel (i, j) covers [i, i+1) × [j, j+1)), window depth clamped to [0, 1] and
  view depth (:meth:`~validate.local_models.shadow.shadow_map.ShadowMap.window_coords`). Uniforms ``sampler2D
  u_shadow_map`` (R × R: .r the stored window depth D, 1 = empty; .g the depth slope DZ per texel; texel
  (i, j) = ``texelFetch(u_shadow_map, ivec2(i, j), 0)``), ``int u_shadow_resolution``; ``float u_texel_tan,
  u_near, u_far, u_depth_scale, u_offset_factor, u_offset_units, u_depth_lsb`` (glPolygonOffset(2, 4) on a
  D24 buffer: o = factor·DZ + units·2⁻²⁴); ``vec3 u_light_position, u_light_normal; float u_light_radius``
  (the disc light).

Evaluation: receiver i is texel (i mod W, i div W) of an RGBA32F framebuffer of width W = min(N, 1024);
its inputs are float32 textures read with ``texelFetch`` at ``gl_FragCoord``; the output is read back
(bit-exact float32) and goes through the family's :meth:`~.registry.Family.call` contract like any
Python technique. Inputs are rounded to float32 on upload: a GLSL transcription can match its float64
Python original only to float32 precision (the tests state the bound per family).
"""

from __future__ import annotations

import json
import re
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ValidateError
from . import glsl_adapter
from .registry import FAMILIES, Technique

HEADER = re.compile(r"^\s*//\s*validate:\s*([A-Za-z_]+)\s*=\s*(.*?)\s*$")
RUNTIMES = ("llvmpipe", "webgl2")
MAX_WIDTH = 1024  # receivers per framebuffer row (llvmpipe's limit is 16384; 1024 keeps rows cache-friendly)
BUILTIN_DIR = Path(__file__).parent  # built-ins are <family>/<name>.glsl, beside the Python techniques
STATUS: dict[str, str] = {}  # runtime -> "" (available) or the reason GLSL techniques of it are not registered


@dataclass
class GLSLSource:
    """A parsed ``.glsl`` technique file: header fields and the shader text (whole file, header included)."""

    path: str
    text: str
    family: str
    name: str
    runtime: str = "llvmpipe"
    description: str = ""
    thresholds: dict[str, float] = field(default_factory=dict)
    source: str = ""
    meta: dict[str, Any] = field(default_factory=dict)


def parse_glsl(path: str | Path, text: str | None = None) -> GLSLSource:
    """Read and parse a technique file's ``// validate:`` header (bad header → ValidateError naming the file)."""
    where = str(path)
    if text is None:
        try:
            text = Path(path).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise ValidateError(f"{where}: cannot read ({type(exc).__name__}: {exc})") from None
    fields: dict[str, str] = {}
    for line in text.splitlines():
        m = HEADER.match(line)
        if m:
            fields[m.group(1).lower()] = m.group(2)
    fam = fields.pop("family", "")
    if fam not in glsl_adapter.SPECS:
        raise ValidateError(f"{where}: header '// validate: family=...' must name one of "
                            f"{', '.join(glsl_adapter.SPECS)} (got {fam!r})")
    src = GLSLSource(where, text, fam, fields.pop("name", Path(where).stem))
    src.runtime = fields.pop("runtime", "llvmpipe")
    if src.runtime not in RUNTIMES:
        raise ValidateError(f"{where}: runtime={src.runtime!r}; expected one of {', '.join(RUNTIMES)}")
    src.description = fields.pop("description", "")
    src.source = fields.pop("source", "")
    src.thresholds = _thresholds(where, fields.pop("thresholds", ""))
    for key in ("lights", "shapes", "brdf"):  # light types / area shapes / BRDF models the technique handles
        if key in fields:
            src.meta[key] = tuple(s.strip() for s in fields.pop(key).split(",") if s.strip())
    src.meta.update({k: _meta_value(v) for k, v in fields.items()})  # seed=…, memory_bytes_per_texel=4, …
    return src


def _meta_value(raw: str) -> Any:
    """A header value as JSON where it parses (numbers, true/false), else the string."""
    try:
        return json.loads(raw)
    except json.JSONDecodeError:
        return raw


def _thresholds(where: str, raw: str) -> dict[str, float]:
    if not raw:
        return {}
    try:
        value = json.loads(raw)
    except json.JSONDecodeError as exc:
        raise ValidateError(f"{where}: thresholds= is not JSON ({exc.msg} at column {exc.pos + 1})") from None
    if not isinstance(value, dict) or not all(isinstance(v, (int, float)) for v in value.values()):
        raise ValidateError(f"{where}: thresholds= must be a JSON object of numbers, e.g. {{\"metric\": 0.01}}")
    return {str(k): float(v) for k, v in value.items()}


# -- shader assembly ------------------------------------------------------------------------------------------
_VERSION = re.compile(r"^\s*#\s*version\b.*$", re.MULTILINE)
PRELUDE = {
    "llvmpipe": "#version 450 core\n",
    "webgl2": "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n",
}
MAIN_LINE = 100000  # #line of the harness's main(): an error there is the harness's, not the user's


def fragment_source(src: GLSLSource) -> str:
    """The full fragment shader: version, the family's declarations, ``#line 1`` + the file, main()."""
    spec = glsl_adapter.SPECS[src.family]
    body = _VERSION.sub("// (#version set by the harness)", src.text)
    return (PRELUDE[src.runtime] + spec.declarations + "\n#line 1\n" + body
            + f"\n#line {MAIN_LINE}\n" + spec.main + "\n")


def vertex_source(runtime: str) -> str:
    """A full-screen triangle from ``a_pos`` (clip coordinates)."""
    inp = "in vec2 a_pos;"
    return PRELUDE[runtime] + inp + "\nvoid main() { gl_Position = vec4(a_pos, 0.0, 1.0); }\n"


# -- evaluation -----------------------------------------------------------------------------------------------
_programs: dict[tuple[int, str, str], tuple[Any, Any]] = {}  # key → (runtime, program)
_programs_lock = threading.Lock()


def _runtime(kind: str) -> Any:
    from ..gl import runtime  # noqa: PLC0415
    from ..gl.egl import GLUnavailable  # noqa: PLC0415

    try:
        return runtime.get(kind)
    except GLUnavailable as exc:
        raise ValidateError(f"GL runtime {kind}: unavailable ({exc})") from None


def compile_check(src: GLSLSource) -> None:
    """Compile and link on the file's runtime now; an error is ``<file>:<line>: <driver message>``, no GL
    ``<file>: GL runtime <kind> unavailable: <reason>``."""
    ok, why = gl_status(src.runtime)
    if not ok:
        raise ValidateError(f"{src.path}: GL runtime {src.runtime} unavailable: {why}")
    _program(src)


def _program(src: GLSLSource) -> Any:
    """The file's program on the current runtime object (a restarted runtime recompiles)."""
    rt = _runtime(src.runtime)
    key = (id(rt), src.runtime, src.path + "\0" + src.text)
    with _programs_lock:
        hit = _programs.get(key)
        if hit is not None and hit[0] is rt:
            return hit[1]
        prog = _compile_webgl(rt, src) if src.runtime == "webgl2" else _compile_egl(rt, src)
        _programs[key] = (rt, prog)
        return prog


def _compile_webgl(rt: Any, src: GLSLSource) -> Any:
    from ..gl.egl import ShaderError  # noqa: PLC0415

    try:
        return rt.compile(vertex_source(src.runtime), fragment_source(src))
    except ShaderError as err:
        raise shader_error(src, err) from None


def _compile_egl(rt: Any, src: GLSLSource) -> Any:
    from ..gl.egl import ShaderError  # noqa: PLC0415

    with rt:
        try:
            return rt.program(vertex_source(src.runtime), fragment_source(src))
        except ShaderError as err:
            raise shader_error(src, err) from None


def shader_error(src: GLSLSource, err: Any) -> ValidateError:
    """``<file>:<line>: <driver message>`` (a line past the file is the harness's main: said so)."""
    if err.line is not None and err.line >= MAIN_LINE:
        return ValidateError(f"{src.path}: the {src.family} entry point does not match the documented signature "
                             f"({err.message})")
    where = f"{src.path}:{err.line}" if err.line is not None else src.path
    return ValidateError(f"{where}: {err.message}")


def layout(n: int) -> tuple[int, int]:
    """(W, H) of the framebuffer holding n receivers, one per texel, row-major from the bottom row."""
    w = max(1, min(n, MAX_WIDTH))
    return w, max(1, -(-n // w))


def pack(values: np.ndarray, w: int, h: int) -> np.ndarray:
    """(N, ≤4) float array → (H, W, 4) float32 texture, receiver i at row i div W, column i mod W."""
    a = np.zeros((w * h, 4), dtype=np.float32)
    v = np.asarray(values, dtype=np.float64).reshape(len(values), -1)
    a[: len(v), : v.shape[1]] = v
    return a.reshape(h, w, 4)


def evaluate(src: GLSLSource, inputs: list[np.ndarray], uniforms: Mapping[str, Any],
             textures: Mapping[str, np.ndarray] | None = None) -> np.ndarray:
    """Run the file's entry point on N receivers; returns (N, 4) float32 (the fragment colour)."""
    prog = _program(src)
    n = len(inputs[0])
    w, h = layout(n)
    packed = {f"u_in{k}": pack(a, w, h) for k, a in enumerate(inputs)}
    if src.runtime == "webgl2":  # a lazy (callable) texture or uniform is built here: every one is bound
        out = _runtime("webgl2").run(prog, (w, h), packed, {k: _value(a) for k, a in (textures or {}).items()},
                                     {k: _value(a) for k, a in uniforms.items()})
    else:
        out = _run_egl(_runtime(src.runtime), prog, (w, h), packed, dict(textures or {}), uniforms)
    return out.reshape(-1, 4)[:n]


def _value(value: Any) -> Any:
    """A texture or uniform value; a callable one (the specular family's prefiltered map) is built on use."""
    return value() if callable(value) else value


def _run_egl(rt: Any, prog: Any, size: tuple[int, int], packed: dict[str, np.ndarray],
             textures: dict[str, np.ndarray], uniforms: Mapping[str, Any]) -> np.ndarray:
    from ..gl import egl  # noqa: PLC0415

    with rt:
        made = []
        bound = list(packed.items()) + [(k, a) for k, a in textures.items() if k in prog]  # unused: not uploaded
        for unit, (name, arr) in enumerate(bound):
            tex = rt.float_texture(_value(arr))  # NEAREST; read with texelFetch (bilinear: env_radiance, in float32)
            tex.use(location=unit)
            made.append(tex)
            if name in prog:
                prog[name].value = unit
        for name, value in uniforms.items():
            if name in prog:
                prog[name].write(glsl_adapter.uniform_bytes(_value(value)))
        fbo = rt.float_target(*size)
        rt.render_fullscreen(prog, fbo)
        out = egl.read_rgba32f(fbo)
        for obj in [*made, fbo, *fbo.color_attachments]:
            obj.release()
    return out


# -- registration ---------------------------------------------------------------------------------------------
def make_fn(src: GLSLSource) -> Callable[..., np.ndarray]:
    """The technique function: the family's Python contract, evaluated by the shader."""
    spec = glsl_adapter.SPECS[src.family]

    def fn(*args: Any, **kwargs: Any) -> np.ndarray:
        _check_handled(src, args, kwargs)
        return spec.call(lambda inputs, uniforms, textures=None: evaluate(src, inputs, uniforms, textures),
                         *args, **kwargs)
    fn.__module__ = f"validate.local_models.{src.family}" if src.meta.get("builtin") else "glsl_plugin"
    fn.__qualname__ = fn.__name__ = src.name
    fn.__doc__ = src.description or f"GLSL technique {src.path}"
    return fn


HANDLED = {"specular": ("brdf", 1, "model", "BRDF model"), "specular_arealight": ("light", 0, "shape", "light shape")}


def _check_handled(src: GLSLSource, args: tuple, kwargs: Mapping[str, Any]) -> None:
    """A specular (specular_arealight) file whose header lists ``brdf=`` (``shapes=``) refuses another BRDF model
    (light shape), one line naming the file, as the Python techniques refuse what they do not model."""
    if src.family not in HANDLED:
        return
    arg, pos, key, what = HANDLED[src.family]
    listed = src.meta.get("brdf" if src.family == "specular" else "shapes")
    given = kwargs.get(arg, args[pos] if len(args) > pos else None)
    value = given.get(key) if isinstance(given, Mapping) else None
    if listed and value not in listed:
        raise ValidateError(f"technique '{src.name}' ({src.family}, {src.path}): {what} {value!r}; the file's header "
                            f"lists {', '.join(listed)}")


def technique_from_file(path: str | Path, family_name: str | None = None, *, runtime: str | None = None,
                        name: str | None = None) -> Technique:
    """A compiled, *unregistered* :class:`Technique` from a ``.glsl`` file (``validate.testing``'s checks);
    ``family_name`` given: the file's header must name that family; ``runtime``/``name`` override the header's
    (the same file on the other runtime: ``bench``, the cross-runtime tests)."""
    if not Path(path).is_file():
        raise ValidateError(f"{path}: GLSL file not found")
    src = parse_glsl(path)
    if runtime is not None:
        if runtime not in RUNTIMES:
            raise ValidateError(f"{path}: runtime={runtime!r}; expected one of {', '.join(RUNTIMES)}")
        src.runtime = runtime
    src.name = name or src.name
    if family_name is not None and src.family != family_name:
        raise ValidateError(f"{path}: a {src.family} technique (header family=), not {family_name}")
    compile_check(src)
    meta = dict(src.meta, glsl=str(path), runtime=src.runtime)
    return Technique(src.name, src.family, make_fn(src), src.description, src.thresholds, src.source, meta)


def load_glsl(path: str | Path, *, builtin: bool = False) -> Technique:
    """Parse, compile (errors: ``<file>:<line>: <message>``) and register a ``.glsl`` technique."""
    src = parse_glsl(path)
    if builtin:
        src.meta["builtin"] = True
    compile_check(src)
    fam = FAMILIES[src.family]
    meta = dict(src.meta, glsl=str(path), runtime=src.runtime)
    fam.register(src.name, src.description, thresholds=src.thresholds, source=src.source, **meta)(make_fn(src))
    return fam[src.name]


def gl_status(runtime: str = "llvmpipe") -> tuple[bool, str]:
    """(available, renderer or reason) of the runtime GLSL techniques need."""
    from ..gl import runtime as rt  # noqa: PLC0415

    return rt.available(runtime)


def register_builtins() -> None:
    """Register every ``<family>/*.glsl`` shipped with the suite whose runtime starts here; record why not.
    Called by :func:`validate.local_models.load_builtins` after every Python built-in, so GLSL
    transcriptions follow their originals in each family's order."""
    for path in sorted(BUILTIN_DIR.glob("*/*.glsl")):
        src = parse_glsl(path)
        ok, why = gl_status(src.runtime)
        STATUS[src.runtime] = "" if ok else why
        if ok and src.name not in FAMILIES[src.family]:
            load_glsl(path, builtin=True)

