"""Headless OpenGL through EGL on Mesa's llvmpipe: float32 render targets read back exactly.

A context is made with PyOpenGL's EGL bindings on the surfaceless platform
(``EGL_PLATFORM=surfaceless``, no window system, no GPU) and wrapped in a ``moderngl.Context`` that
drives it, so both profiles share one API:

* ``create_context("core")``   — OpenGL 4.5 core profile (GLSL 1.40 … 4.50, ``#version 450 core``);
* ``create_context("compat")`` — OpenGL 4.5 *compatibility* profile: GLSL 1.10/1.20 as the textbooks
  print it (``varying``, ``gl_FragColor``, ``ftransform()``, ``gl_NormalMatrix``, ``gl_LightSource``,
  ``gl_ModelViewMatrix``); PyOpenGL's ``OpenGL.GL`` fixed-function calls (``glLightfv``,
  ``glMatrixMode`` …) act on it while it is current.

Conventions
-----------
* Render targets are RGBA32F textures (``dtype='f4'``) read with ``glReadPixels(GL_FLOAT)``: the bits a
  fragment shader writes come back unchanged (no clamping: ``GL_CLAMP_READ_COLOR`` and
  ``GL_CLAMP_FRAGMENT_COLOR`` are ``GL_FALSE``/``GL_FIXED_ONLY``).
* **Rows come back bottom-up**: row 0 of :func:`read_rgba32f` is the bottom row of the framebuffer,
  i.e. ``gl_FragCoord.y = 0.5``. Texel (x, y) of an input texture uploaded with
  :meth:`Context.float_texture` is ``texelFetch(tex, ivec2(x, y), 0)`` with array row y, so an
  array laid out row-major as receivers ``i = y*W + x`` maps one-to-one onto ``gl_FragCoord`` with no
  flip.
* A context is current on one thread at a time (EGL rule); :meth:`Context.make_current` makes it
  current on the calling thread, :meth:`Context.done_current` releases it so another thread can take it.

Precision (measured on this machine, Mesa 22.3.6 llvmpipe, float32 arguments against float64):
``sin``/``cos`` ≤ 7.4e-8 absolute on [−π, π] (the issue's bound: 2.4e-7); ``exp`` ≤ 5 ulp, ``sqrt`` ≤ 1 ulp;
but **``acos`` errs up to 1.6e-4 rad, ``asin`` 3.9e-4 rad and ``atan`` 3.3e-6 rad** (Mesa lowers them
to short polynomials). A shader that needs angles to float32 precision refines ``atan`` with one Newton
step on the precise sin/cos (see ``atan2_precise`` in :mod:`validate.local_models.glsl_adapter`).
Texture filtering with ``texture()`` quantises the bilinear weights (≈ 2e-5 of a texel step): read
float data with ``texelFetch`` and interpolate in the shader.

References
----------
[1] Khronos, EGL 1.5 specification, §3.7 (contexts), EGL_KHR_surfaceless_context, EGL_MESA_platform_surfaceless.
[2] Khronos, OpenGL 4.5 compatibility profile specification, §18.2 (glReadPixels, clamping).
"""

from __future__ import annotations

import ctypes
import os
import re
import threading
from collections import deque
from dataclasses import dataclass, field
from typing import Any

import numpy as np

os.environ.setdefault("EGL_PLATFORM", "surfaceless")
os.environ.setdefault("PYOPENGL_PLATFORM", "egl")

PROFILES = ("core", "compat")
GL_MAJOR, GL_MINOR = 4, 5


class GLUnavailable(RuntimeError):
    """No usable GL: the message says why (missing package, no EGL display, no 4.5 context)."""


@dataclass
class ShaderError(Exception):
    """A GLSL compile or link error, parsed from the driver's log.

    ``line`` is the first line the driver names (in the numbering set by ``#line``), ``None`` when the
    log names none (a link error); ``message`` the driver's text for it; ``log`` the whole log.
    """

    stage: str
    line: int | None
    message: str
    log: str = field(repr=False, default="")

    def __str__(self) -> str:
        where = f"{self.line}: " if self.line is not None else ""
        return f"{where}{self.message}"


_MESA_LINE = re.compile(r"^\s*\d+:(\d+)\((\d+)\):\s*(?:error|ERROR):\s*(.*)$")
_OTHER_LINE = re.compile(r"^\s*(?:ERROR|error):\s*\d+:(\d+):\s*(.*)$")


def parse_shader_log(stage: str, log: str) -> ShaderError:
    """First error of a driver log as a :class:`ShaderError`.

    Mesa writes ``0:LINE(COL): error: text``; ANGLE/others ``ERROR: 0:LINE: text``.
    """
    for raw in log.splitlines():
        m = _MESA_LINE.match(raw) or _OTHER_LINE.match(raw)
        if m:
            return ShaderError(stage, int(m.group(1)), m.groups()[-1].strip(), log)
    text = next((s.strip() for s in log.splitlines() if "error" in s.lower()), log.strip() or "link failed")
    return ShaderError(stage, None, " ".join(text.split()), log)


class _EglLoader:
    """moderngl loader resolving GL entry points with ``eglGetProcAddress`` of the current context."""

    def __init__(self, egl: Any):
        self._proc = egl.eglGetProcAddress

    def load_opengl_function(self, name: str) -> int:
        fn = self._proc(name.encode())
        return ctypes.cast(fn, ctypes.c_void_p).value or 0

    def release(self) -> None:  # moderngl calls this on Context.release
        return None


def _egl_module() -> Any:
    try:
        from OpenGL import EGL  # noqa: PLC0415 — import only when a context is asked for
    except Exception as exc:  # ImportError, or a PyOpenGL platform already chosen otherwise
        raise GLUnavailable(f"PyOpenGL EGL bindings unavailable ({type(exc).__name__}: {exc})") from exc
    return EGL


def _initialize_display(egl: Any) -> Any:
    dpy = egl.eglGetDisplay(egl.EGL_DEFAULT_DISPLAY)
    major, minor = egl.EGLint(), egl.EGLint()
    if not dpy or not egl.eglInitialize(dpy, ctypes.pointer(major), ctypes.pointer(minor)):
        raise GLUnavailable("eglInitialize failed (no EGL display; is libegl-mesa0 installed?)")
    if not egl.eglBindAPI(egl.EGL_OPENGL_API):
        raise GLUnavailable("eglBindAPI(EGL_OPENGL_API) failed")
    return dpy


def _create_egl_context(egl: Any, dpy: Any, profile: str) -> Any:
    config, count = egl.EGLConfig(), egl.EGLint()
    attrs = (egl.EGLint * 5)(egl.EGL_RENDERABLE_TYPE, egl.EGL_OPENGL_BIT, egl.EGL_SURFACE_TYPE,
                             egl.EGL_PBUFFER_BIT, egl.EGL_NONE)
    if not egl.eglChooseConfig(dpy, attrs, ctypes.pointer(config), 1, ctypes.pointer(count)) or count.value < 1:
        raise GLUnavailable("eglChooseConfig found no OpenGL config")
    mask = (egl.EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT if profile == "core"
            else egl.EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT)
    cattrs = (egl.EGLint * 7)(egl.EGL_CONTEXT_MAJOR_VERSION, GL_MAJOR, egl.EGL_CONTEXT_MINOR_VERSION, GL_MINOR,
                              egl.EGL_CONTEXT_OPENGL_PROFILE_MASK, mask, egl.EGL_NONE)
    ctx = egl.eglCreateContext(dpy, config, egl.EGL_NO_CONTEXT, cattrs)
    if not ctx:
        raise GLUnavailable(f"eglCreateContext: no OpenGL {GL_MAJOR}.{GL_MINOR} {profile} context")
    return ctx


def _gl_strings() -> dict[str, str]:
    from OpenGL import GL  # noqa: PLC0415

    names = ("GL_RENDERER", "GL_VERSION", "GL_SHADING_LANGUAGE_VERSION", "GL_VENDOR")
    return {n: GL.glGetString(getattr(GL, n)).decode() for n in names}


def _wrap_moderngl(egl: Any) -> Any:
    try:
        import moderngl  # noqa: PLC0415
    except ImportError as exc:
        raise GLUnavailable(f"moderngl not installed ({exc})") from exc
    mctx = moderngl.Context.__new__(moderngl.Context)
    mctx.mglo, mctx.version_code = moderngl.mgl.create_context(context=_EglLoader(egl))
    mctx._info, mctx._extensions, mctx.extra, mctx._gc_mode = None, None, None, None
    mctx._objects, mctx._screen, mctx.fbo = deque(), None, None
    mctx.clear_errors()  # moderngl's init probes leave GL_INVALID_VALUE on compatibility contexts
    return mctx


class Context:
    """One EGL OpenGL 4.5 context (``profile`` "core" or "compat") and the moderngl object driving it.

    Attributes: ``profile``; ``gl`` (``moderngl.Context``; call its methods only while this context is
    current); ``info`` (``GL_RENDERER``, ``GL_VERSION``, ``GL_SHADING_LANGUAGE_VERSION``, ``GL_VENDOR``);
    ``lock`` (an ``RLock`` to hold around make_current … done_current when threads share it).
    """

    def __init__(self, profile: str):
        if profile not in PROFILES:
            raise ValueError(f"profile must be one of {PROFILES}, got {profile!r}")
        self.profile = profile
        self.lock = threading.RLock()
        self._egl = _egl_module()
        self._dpy = _initialize_display(self._egl)
        self._ctx = _create_egl_context(self._egl, self._dpy, profile)
        self.pid = os.getpid()
        self.make_current()
        self.gl = _wrap_moderngl(self._egl)
        self.info = _gl_strings()
        self.done_current()

    def make_current(self) -> None:
        """Make this context current on the calling thread (no surface: EGL_KHR_surfaceless_context)."""
        egl = self._egl
        if self._ctx is None:
            raise GLUnavailable("context already released")
        if not egl.eglMakeCurrent(self._dpy, egl.EGL_NO_SURFACE, egl.EGL_NO_SURFACE, self._ctx):
            raise GLUnavailable(f"eglMakeCurrent failed (EGL error 0x{egl.eglGetError():x})")

    def done_current(self) -> None:
        """Release the calling thread's current context so another thread may make this one current."""
        egl = self._egl
        egl.eglMakeCurrent(self._dpy, egl.EGL_NO_SURFACE, egl.EGL_NO_SURFACE, egl.EGL_NO_CONTEXT)

    def __enter__(self) -> Context:
        self.lock.acquire()
        self.make_current()
        return self

    def __exit__(self, *exc: object) -> None:
        try:
            self.done_current()
        finally:
            self.lock.release()

    def release(self) -> None:
        """Destroy the context (idempotent). Objects made with ``gl`` are invalid afterwards."""
        if self._ctx is None:
            return
        if self.pid == os.getpid():  # a forked child must not destroy its parent's context
            egl = self._egl
            egl.eglMakeCurrent(self._dpy, egl.EGL_NO_SURFACE, egl.EGL_NO_SURFACE, egl.EGL_NO_CONTEXT)
            egl.eglDestroyContext(self._dpy, self._ctx)
        self._ctx = None

    # --- helpers (call while current) -----------------------------------------------------------------

    def program(self, vertex_shader: str, fragment_shader: str) -> Any:
        """Compile and link; a compile/link failure raises :class:`ShaderError` (stage, line, message)."""
        import moderngl  # noqa: PLC0415

        try:
            return self.gl.program(vertex_shader=vertex_shader, fragment_shader=fragment_shader)
        except moderngl.Error as exc:
            text = str(exc)
            stage = "fragment" if "fragment_shader" in text else "vertex" if "vertex_shader" in text else "link"
            raise parse_shader_log(stage, text) from None

    def float_texture(self, array: np.ndarray) -> Any:
        """Upload an (H, W, 4) float32 array as an RGBA32F texture, NEAREST filtering (texelFetch-exact)."""
        import moderngl  # noqa: PLC0415

        a = np.ascontiguousarray(array, dtype=np.float32)
        if a.ndim != 3 or a.shape[2] != 4:
            raise ValueError(f"float_texture wants (H, W, 4), got {a.shape}")
        tex = self.gl.texture((a.shape[1], a.shape[0]), 4, a.tobytes(), dtype="f4")
        tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
        return tex

    def float_target(self, width: int, height: int) -> Any:
        """An RGBA32F framebuffer of width × height, bound and with its viewport set."""
        tex = self.gl.texture((width, height), 4, dtype="f4")
        fbo = self.gl.framebuffer(color_attachments=[tex])
        fbo.use()
        return fbo

    def render_fullscreen(self, program: Any, fbo: Any) -> None:
        """Draw one triangle covering ``fbo`` with ``program`` (vertex input ``in vec2 a_pos`` if any)."""
        import moderngl  # noqa: PLC0415

        fbo.use()
        tri = np.array([-1.0, -1.0, 3.0, -1.0, -1.0, 3.0], dtype=np.float32)
        vbo = self.gl.buffer(tri.tobytes())
        content = [(vbo, "2f", "a_pos")] if "a_pos" in program else []
        vao = self.gl.vertex_array(program, content) if content else self.gl.vertex_array(program, [])
        vao.render(moderngl.TRIANGLES, vertices=3)
        vao.release()
        vbo.release()


def read_rgba32f(fbo: Any) -> np.ndarray:
    """Read an RGBA32F framebuffer as an (H, W, 4) float32 array, **row 0 = bottom row** (GL order)."""
    width, height = fbo.size
    data = fbo.read(components=4, dtype="f4", alignment=4)
    return np.frombuffer(data, dtype=np.float32).reshape(height, width, 4).copy()


def create_context(profile: str = "core") -> Context:
    """A fresh llvmpipe OpenGL 4.5 context of ``profile`` "core" or "compat" (raises GLUnavailable)."""
    return Context(profile)


FULLSCREEN_VERTEX_CORE = """#version 450 core
in vec2 a_pos;
void main() { gl_Position = vec4(a_pos, 0.0, 1.0); }
"""

FULLSCREEN_VERTEX_COMPAT = """#version 120
attribute vec2 a_pos;
void main() { gl_Position = vec4(a_pos, 0.0, 1.0); }
"""
