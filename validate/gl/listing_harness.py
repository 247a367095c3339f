"""Run a textbook listing's vertex + fragment shader pair *unchanged* on llvmpipe, one receiver per pixel.

What the harness adds to a printed listing, and nothing else:

1. **Version glue**: a ``#version`` line where the listing prints none (:func:`glued`), followed by
   ``#line 1`` so the driver's line numbers are the listing file's own.
2. **Edits** (:class:`Edit`): exact, counted text substitutions for what the extracted text cannot
   compile as (extraction damage, the book's own bugs); each says why. The catalogue
   (:mod:`validate.local_models.listings.catalog`) lists them per listing; a stale edit (its text no
   longer in the listing) is an error, not a silent no-op.
3. **Host state** transcribed to Python: uniforms by name (:func:`set_uniform`), vertex attributes
   as client arrays (user ``attribute``/``in`` variables by name, or the legacy ``gl_Vertex``/
   ``gl_Normal``), and fixed-function state (``glLight*``, ``glMaterial*``, ``glMatrixMode``/
   ``glLoadMatrixf``) through a ``setup`` callback that receives PyOpenGL's ``GL`` module.

Receivers are drawn as ``GL_POINTS`` (size 1) into an RGBA32F target of width ``min(N, 256)``; receiver i
lands on pixel (i mod W, i div W) (row 0 = the bottom row, GL's order, as :func:`validate.gl.egl.read_rgba32f`
returns it). A point's varyings are not interpolated: the fragment sees exactly the vertex shader's outputs.

Placing a receiver on its pixel without touching the shader: the listing computes
``gl_Position = U · (M · p)`` with U a matrix that feeds only the clip position (an MVP or
projection uniform, or the fixed-function projection for ``ftransform()``) and M what the lighting
also uses (the model-view, often the identity). Per receiver the harness sets
U_i = translate(ndc_i − M p_i), so that gl_Position = (ndc_i, 1) with ndc_i the pixel centre and z = 0
(:func:`placement_matrix`). Rounding of U_i · (M p) in float32 moves the point by ≲ 10⁻⁶ in NDC,
far below half a pixel (1/512 at W = 256).

**One draw for all receivers** (:func:`batched_vertex_shader`): where the placement is a ``uniform mat4 U;``
declared once in the vertex stage (not in the fragment stage) and no ``per_point`` uniform is asked for, the
harness changes that one declaration — nothing else — into a per-vertex input of the same name and type
(``in mat4 U;``, ``attribute mat4 U;`` below GLSL 1.30) and feeds U_i as a vertex attribute, so that one
``glDrawArrays(GL_POINTS, 0, N)`` draws every receiver. Every statement of the listing is unchanged, and U only
places the point, so every varying — hence every fragment — is the same float32 computation as with a uniform U
and one draw per receiver (``tests/local_models/test_listings.py`` compares the two paths bit for bit). Otherwise
(the fixed-function placement, per-receiver uniforms) one ``glDrawArrays(GL_POINTS, i, 1)`` is made per
receiver, its U_i and ``per_point`` values set before it.

Programs are compiled once per (vertex text, fragment text, names of the uniforms set) and kept for the run
(:func:`_program`): a call sets every uniform it names again, and the names are part of the key, so a kept
program's uniform state is exactly what a freshly linked one would have after the call's writes.

Pixels no receiver reaches keep the clear value −FLT_MAX in all four channels (:data:`UNWRITTEN`), which
no lighting listing writes; :func:`render_points` checks that every receiver wrote its pixel. A NaN the
shader itself computes comes back as NaN (the family contract then names it).
"""

from __future__ import annotations

import math
import re
from collections import OrderedDict
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ValidateError

MAX_WIDTH = 256  # pixels per row of the target
UNWRITTEN = float(-np.finfo(np.float32).max)  # the target's clear value
KIND = "llvmpipe-compat"  # the runtime kind: OpenGL 4.5 compatibility profile (GLSL 1.10 … 4.50, ES 1.00)


@dataclass(frozen=True)
class Edit:
    """Replace ``old`` by ``new`` in one stage's text, exactly ``count`` times (0: every occurrence, ≥ 1)."""

    stage: str  # "vert" | "frag"
    old: str
    new: str
    why: str
    count: int = 1


def apply_edits(text: str, edits: Sequence[Edit], stage: str, who: str) -> str:
    """The listing text with its edits for ``stage``; an edit whose text is absent (or present a different
    number of times than declared) raises :class:`ValidateError` naming the listing."""
    for e in edits:
        if e.stage != stage:
            continue
        n = text.count(e.old)
        if n == 0 or (e.count and n != e.count):
            raise ValidateError(f"{who}: edit {e.old!r} expected {e.count or '≥ 1'} time(s) in the {stage} shader, "
                                f"found {n}")
        text = text.replace(e.old, e.new)
    return text


def glued(text: str, header: str | None) -> str:
    """``header`` (a ``#version`` line) + ``#line 1`` + the text, or the text alone when header is None."""
    return text if header is None else f"{header}\n#line 1\n{text}"


def pixel_layout(n: int) -> tuple[int, int]:
    """(width, height) of the target for n receivers."""
    if n < 1:
        raise ValidateError("listing harness: no receivers")
    w = min(n, MAX_WIDTH)
    return w, math.ceil(n / w)


def pixel_ndc(n: int) -> np.ndarray:
    """(n, 2) NDC of the pixel centre of each receiver: x = (col + ½)/W·2 − 1, y = (row + ½)/H·2 − 1."""
    w, h = pixel_layout(n)
    x = (np.arange(w) + 0.5) / w * 2.0 - 1.0
    y = (np.arange(h) + 0.5) / h * 2.0 - 1.0
    return np.stack([np.tile(x, h)[:n], np.repeat(y, w)[:n]], axis=1)


def placement_matrix(q: np.ndarray, ndc: np.ndarray) -> np.ndarray:
    """U = translate(ndc − q) (4 × 4, row-major): U · (q, 1) = (ndc_x, ndc_y, 0, 1)."""
    u = np.eye(4)
    u[0, 3], u[1, 3], u[2, 3] = ndc[0] - q[0], ndc[1] - q[1], -q[2]
    return u


@dataclass(frozen=True)
class Placement:
    """Which matrix feeds only gl_Position: a mat4 ``uniform`` (by name), or the fixed-function projection
    (``uniform=None``: ``ftransform()``/``gl_ModelViewProjectionMatrix``, with GL_MODELVIEW = ``pre``).
    ``pre`` is the 4 × 4 (row-major) the shader applies to the position before it (default identity)."""

    uniform: str | None
    pre: tuple[tuple[float, ...], ...] | None = None

    def pre_matrix(self) -> np.ndarray:
        return np.eye(4) if self.pre is None else np.asarray(self.pre, dtype=np.float64)


def _gl() -> Any:
    from OpenGL import GL  # noqa: PLC0415 — after validate.gl.egl chose the EGL platform

    return GL


def set_uniform(prog: Any, name: str, value: Any) -> None:
    """Write a uniform through moderngl by its GLSL type: scalars, vectors, matrices given row-major
    (numpy (3, 3)/(4, 4); transposed to GL's column order here), bools and ints. A uniform the
    compiler removed (unused) is skipped. ``name[0]`` also finds an array of one element (moderngl names it
    without the index)."""
    if name not in prog and name.endswith("[0]") and name[:-3] in prog:
        name = name[:-3]
    if name not in prog:
        return
    u = prog[name]
    import moderngl  # noqa: PLC0415

    if not isinstance(u, moderngl.Uniform):  # a vertex input of that name (the batched placement)
        return
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim == 2:
        u.value = tuple(float(x) for x in arr.T.ravel())
    elif arr.ndim == 1:
        u.value = tuple(float(x) for x in arr)
    elif isinstance(value, (bool, np.bool_)):
        u.value = bool(value)
    elif u.fmt.endswith("i") or u.fmt.endswith("I"):
        u.value = int(value)
    else:
        u.value = float(value)


def _bind_attributes(gl: Any, prog: Any, attributes: Mapping[str, np.ndarray], legacy_vertex: np.ndarray | None,
                     legacy_normal: np.ndarray | None) -> list[Any]:
    """Client-side arrays for named attributes and the legacy gl_Vertex / gl_Normal; returns what must stay alive."""
    keep: list[Any] = []
    gl.glBindVertexArray(0)
    gl.glBindBuffer(gl.GL_ARRAY_BUFFER, 0)
    for name, values in attributes.items():
        loc = gl.glGetAttribLocation(prog.glo, name)
        if loc < 0:
            continue  # optimised away by the compiler
        a = np.ascontiguousarray(values, dtype=np.float32)
        gl.glEnableVertexAttribArray(loc)
        gl.glVertexAttribPointer(loc, a.shape[1], gl.GL_FLOAT, gl.GL_FALSE, 0, a)
        keep.append((loc, a))
    if legacy_vertex is not None:
        a = np.ascontiguousarray(legacy_vertex, dtype=np.float32)
        gl.glEnableClientState(gl.GL_VERTEX_ARRAY)
        gl.glVertexPointer(a.shape[1], gl.GL_FLOAT, 0, a)
        keep.append(("vertex", a))
    if legacy_normal is not None:
        a = np.ascontiguousarray(legacy_normal, dtype=np.float32)
        gl.glEnableClientState(gl.GL_NORMAL_ARRAY)
        gl.glNormalPointer(gl.GL_FLOAT, 0, a)
        keep.append(("normal", a))
    return keep


def _unbind(gl: Any, keep: list[Any]) -> None:
    for loc, _ in keep:
        if loc == "vertex":
            gl.glDisableClientState(gl.GL_VERTEX_ARRAY)
        elif loc == "normal":
            gl.glDisableClientState(gl.GL_NORMAL_ARRAY)
        else:
            gl.glDisableVertexAttribArray(loc)


def _raw() -> Any:
    """PyOpenGL's raw (unwrapped, unchecked) entry points: the per-receiver loop calls them N times, where the
    wrapped ones cost ≈ 30 µs each in argument conversion."""
    from OpenGL.raw.GL.VERSION import GL_1_0, GL_1_1, GL_2_0  # noqa: PLC0415

    return GL_1_0, GL_1_1, GL_2_0


def _per_point_setters(gl: Any, prog: Any, per_point: Mapping[str, np.ndarray]) -> list[tuple[Callable, int, Any, int]]:
    """(raw glUniform*fv of the right width, location, base pointer, row stride in bytes) per active uniform,
    over a float32 copy of its (N, k) values (kept alive by the returned tuple)."""
    _, _, gl20 = _raw()
    fns = {1: gl20.glUniform1fv, 2: gl20.glUniform2fv, 3: gl20.glUniform3fv, 4: gl20.glUniform4fv}
    out = []
    for name, values in per_point.items():
        loc = gl.glGetUniformLocation(prog.glo, name)
        if loc < 0:
            continue
        a = np.ascontiguousarray(np.asarray(values, dtype=np.float32).reshape(len(values), -1))
        out.append((fns[a.shape[1]], loc, a, a.strides[0]))
    return out


def _placement_offsets(positions: np.ndarray, placement: Placement) -> np.ndarray:
    """(N, 3) float64 translation ndc − M p of each receiver's U_i (module docstring)."""
    if placement.pre is None:  # M = I: M p = p (the product with I is exact; only a zero's sign could differ)
        q = positions[:, :3]
    else:
        q = (np.c_[positions[:, :3], np.ones(len(positions))] @ placement.pre_matrix().T)[:, :3]
    out = -q
    out[:, :2] += pixel_ndc(len(positions))
    return out


def placement_matrices(positions: np.ndarray, placement: Placement) -> np.ndarray:
    """(N, 4, 4) float32 U_i (row-major) for every receiver (module docstring)."""
    u = np.zeros((len(positions), 4, 4), dtype=np.float32)
    u[:, [0, 1, 2, 3], [0, 1, 2, 3]] = 1.0
    u[:, :3, 3] = _placement_offsets(positions, placement)
    return u


def placement_columns(positions: np.ndarray, placement: Placement) -> np.ndarray:
    """(N, 16) float32: each U_i in GL's column-major order (columns 0–3 = floats 0–3, 4–7, …), the same float32
    values as :func:`placement_matrices`."""
    u = np.zeros((len(positions), 16), dtype=np.float32)
    u[:, [0, 5, 10, 15]] = 1.0
    u[:, 12:15] = _placement_offsets(positions, placement)
    return u


_PRECISION = r"(?:(?:highp|mediump|lowp)\s+)?"


def _glsl_version(text: str) -> int:
    """The number of the stage's ``#version`` line (110 where there is none: GLSL 1.10)."""
    m = re.search(r"^\s*#\s*version\s+(\d+)", text, flags=re.MULTILINE)
    return int(m.group(1)) if m else 110


def batched_vertex_shader(vertex_shader: str, fragment_shader: str, uniform: str | None) -> str | None:
    """The vertex stage with its one ``uniform mat4 <uniform>;`` declaration made a per-vertex input (module
    docstring), or None where that cannot be done: no placement uniform (fixed function), the declaration not
    found exactly once, or the name also in the fragment stage. The line structure is kept (``#line`` numbers
    stay the listing's)."""
    if uniform is None or re.search(rf"\b{re.escape(uniform)}\b", fragment_shader):
        return None
    pat = re.compile(rf"\buniform(\s+{_PRECISION}mat4\s+{re.escape(uniform)}\s*;)")
    if len(pat.findall(vertex_shader)) != 1:
        return None
    v = _glsl_version(vertex_shader)
    word = "attribute" if v < 130 else "in"  # 100: GLSL ES 1.00
    return pat.sub(lambda m: word + m.group(1), vertex_shader)


_KEEP_PROGRAMS = 32  # programs kept per context


def _program(ctx: Any, vertex_shader: str, fragment_shader: str, names: tuple[str, ...]) -> Any:
    """``ctx.program(vert, frag)``, compiled once per (texts, names of the uniforms the call sets) and kept on the
    context (module docstring; they go with it); the least recently used beyond :data:`_KEEP_PROGRAMS` are
    released."""
    kept: OrderedDict[tuple, Any] = ctx.__dict__.setdefault("_listing_programs", OrderedDict())
    key = (vertex_shader, fragment_shader, names)
    prog = kept.get(key)
    if prog is not None:
        kept.move_to_end(key)
        return prog
    prog = ctx.program(vertex_shader, fragment_shader)
    kept[key] = prog
    while len(kept) > _KEEP_PROGRAMS:
        kept.popitem(last=False)[1].release()
    return prog


def _draw_batched(gl: Any, prog: Any, positions: np.ndarray, placement: Placement) -> None:
    """One ``glDrawArrays(GL_POINTS, 0, N)``: U_i (module docstring) fed as the mat4 vertex input of the
    placement's name (four vec4 columns at locations loc … loc + 3, column-major)."""
    import ctypes  # noqa: PLC0415

    _, gl11, gl20 = _raw()
    loc = gl.glGetAttribLocation(prog.glo, placement.uniform)
    if loc < 0:
        raise ValidateError(f"listing harness: placement input {placement.uniform!r} is not active in the program")
    cols = placement_columns(positions, placement)
    base = cols.ctypes.data
    for j in range(4):
        gl.glEnableVertexAttribArray(loc + j)
        gl20.glVertexAttribPointer(loc + j, 4, gl.GL_FLOAT, gl.GL_FALSE, 64, ctypes.c_void_p(base + 16 * j))
    try:
        gl11.glDrawArrays(gl.GL_POINTS, 0, len(positions))
    finally:
        for j in range(4):
            gl.glDisableVertexAttribArray(loc + j)
    del cols


def _draw(gl: Any, prog: Any, positions: np.ndarray, placement: Placement,
          per_point: Mapping[str, np.ndarray] | None = None) -> None:
    """One GL_POINTS draw per receiver with its placement matrix (module docstring) and its ``per_point``
    uniform values (host-side glue for quantities the listing takes as uniforms, e.g. a light direction)."""
    import ctypes  # noqa: PLC0415

    gl10, gl11, gl20 = _raw()
    setters = _per_point_setters(gl, prog, per_point or {})
    loc = None if placement.uniform is None else gl.glGetUniformLocation(prog.glo, placement.uniform)
    if loc is not None and loc < 0:
        raise ValidateError(f"listing harness: placement uniform {placement.uniform!r} is not active in the program")
    u = placement_matrices(positions, placement)
    if loc is None:  # fixed function: glLoadMatrixf takes column-major
        u = np.ascontiguousarray(np.transpose(u, (0, 2, 1)))
        gl.glMatrixMode(gl.GL_MODELVIEW)
        gl.glLoadMatrixf(np.ascontiguousarray(placement.pre_matrix().T, dtype=np.float32))
        gl.glMatrixMode(gl.GL_PROJECTION)
    base = u.ctypes.data
    ptr = [(fn, lc, a.ctypes.data, st) for fn, lc, a, st in setters]
    for i in range(len(positions)):
        m = ctypes.c_void_p(base + 64 * i)
        if loc is None:
            gl10.glLoadMatrixf(m)
        else:
            gl20.glUniformMatrix4fv(loc, 1, 1, m)
        for fn, lc, b, st in ptr:
            fn(lc, 1, ctypes.c_void_p(b + st * i))
        gl11.glDrawArrays(gl.GL_POINTS, i, 1)
    del setters
    if loc is None:
        gl.glLoadIdentity()
        gl.glMatrixMode(gl.GL_MODELVIEW)
        gl.glLoadIdentity()


def render_points(vertex_shader: str, fragment_shader: str, positions: np.ndarray, *, placement: Placement,
                  attributes: Mapping[str, np.ndarray] | None = None, legacy_vertex: np.ndarray | None = None,
                  legacy_normal: np.ndarray | None = None, uniforms: Mapping[str, Any] | None = None,
                  setup: Callable[[Any], None] | None = None, per_point: Mapping[str, np.ndarray] | None = None,
                  who: str = "listing") -> np.ndarray:
    """(N, 4) float32 fragment colour of each receiver (module docstring). ``positions`` (N, 3) or (N, 4)
    place the receivers; pass the same array (w = 1) as the listing's position attribute. A compile or link
    error raises :class:`validate.gl.egl.ShaderError`; a receiver whose pixel kept the clear value raises
    ValidateError."""
    from . import egl, runtime

    pos = np.asarray(positions, dtype=np.float64)
    n = len(pos)
    w, h = pixel_layout(n)
    ctx = runtime.get(KIND)
    batched = None if per_point else batched_vertex_shader(vertex_shader, fragment_shader, placement.uniform)
    with ctx:
        gl = _gl()
        prog = _program(ctx, batched or vertex_shader, fragment_shader, tuple(sorted(uniforms or {})))
        fbo = ctx.float_target(w, h)
        try:
            fbo.clear(UNWRITTEN, UNWRITTEN, UNWRITTEN, UNWRITTEN)
            for name, value in (uniforms or {}).items():
                set_uniform(prog, name, value)
            gl.glUseProgram(prog.glo)
            gl.glDisable(gl.GL_DEPTH_TEST)
            gl.glDisable(gl.GL_PROGRAM_POINT_SIZE)
            gl.glPointSize(1.0)
            if setup is not None:
                setup(gl)
            keep = _bind_attributes(gl, prog, attributes or {}, legacy_vertex, legacy_normal)
            try:
                if batched is not None:
                    _draw_batched(gl, prog, pos, placement)
                else:
                    _draw(gl, prog, pos, placement, per_point)
            finally:
                _unbind(gl, keep)
                gl.glUseProgram(0)
            gl.glFinish()
            out = egl.read_rgba32f(fbo).reshape(-1, 4)[:n]
        finally:
            fbo.release()
    missed = (out == np.float32(UNWRITTEN)).all(axis=1)
    if missed.any():
        raise ValidateError(f"{who}: {int(missed.sum())} of {n} receivers wrote no fragment "
                            f"(first: {int(np.argmax(missed))})")
    return out


def homogeneous(points: np.ndarray) -> np.ndarray:
    """(N, 4) = (x, y, z, 1)."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    return np.c_[p, np.ones(len(p))]


__all__ = ["Edit", "KIND", "Placement", "apply_edits", "batched_vertex_shader", "glued", "homogeneous", "pixel_layout",
           "pixel_ndc", "placement_matrix", "render_points", "set_uniform"]
