"""The llvmpipe GL runtime (validate.gl.egl / validate.gl.runtime): exact float32 round trips, row order,
the compatibility profile's textbook GLSL, one-line shader errors, and the no-GL path.

Skipped, with the reason, where no GL context can be made (``runtime.available`` says why).
"""

from __future__ import annotations

import numpy as np
import pytest

from validate.gl import egl, runtime

OK, WHY = runtime.available("llvmpipe")
pytestmark = pytest.mark.skipif(not OK, reason=f"no llvmpipe GL: {WHY}")

# The measurement on this machine: llvmpipe's sin/cos within 2.4e-7 absolute of float64 over
# [-pi, pi] (the float32 argument itself is exact; the rest is the driver's polynomial). A fallback to a
# half-precision or table approximation errs > 1e-4 and fails this.
SIN_COS_ABS = 2.4e-7

PASS_THROUGH = """#version 450 core
uniform sampler2D u_tex; out vec4 o;
void main() { o = texelFetch(u_tex, ivec2(gl_FragCoord.xy), 0); }
"""


def _render(ctx: egl.Context, fragment: str, size: tuple[int, int], tex: np.ndarray | None = None,
            vertex: str = egl.FULLSCREEN_VERTEX_CORE) -> np.ndarray:
    with ctx:
        prog = ctx.program(vertex, fragment)
        made = None
        if tex is not None:
            made = ctx.float_texture(tex)
            made.use(0)
            if "u_tex" in prog:
                prog["u_tex"].value = 0
        fbo = ctx.float_target(*size)
        ctx.render_fullscreen(prog, fbo)
        out = egl.read_rgba32f(fbo)
        fbo.release()
        if made is not None:
            made.release()
    return out


def test_float32_round_trip_is_bit_exact() -> None:
    """Texel in → fragment out → glReadPixels(GL_FLOAT): every bit pattern of finite floats survives,
    including denormal-free extremes and negative values (no clamping of float targets)."""
    rng = np.random.default_rng(7)
    a = (rng.standard_normal((13, 37, 4)) * 10.0 ** rng.integers(-30, 30, (13, 37, 4))).astype(np.float32)
    a[0, 0] = (np.finfo(np.float32).max, -np.finfo(np.float32).max, np.finfo(np.float32).tiny, -0.0)
    out = _render(runtime.get("llvmpipe"), PASS_THROUGH, (37, 13), a)
    assert out.dtype == np.float32 and out.shape == a.shape
    assert np.array_equal(out.view(np.uint32), a.view(np.uint32))


def test_rows_come_back_bottom_up() -> None:
    """Row 0 of the read-back is gl_FragCoord.y = 0.5 (GL's bottom row); column j is x = j + 0.5."""
    out = _render(runtime.get("llvmpipe"), "#version 450 core\nout vec4 o;\n"
                  "void main() { o = vec4(gl_FragCoord.xy, 0.0, 1.0); }\n", (5, 3))
    assert np.array_equal(out[:, 0, 1], np.array([0.5, 1.5, 2.5], dtype=np.float32))
    assert np.array_equal(out[0, :, 0], np.arange(5, dtype=np.float32) + 0.5)


def test_sin_cos_precision() -> None:
    x = np.linspace(-np.pi, np.pi, 64 * 1024, dtype=np.float32)
    tex = np.zeros((64, 1024, 4), dtype=np.float32)
    tex[..., 0] = x.reshape(64, 1024)
    out = _render(runtime.get("llvmpipe"), "#version 450 core\nuniform sampler2D u_tex; out vec4 o;\n"
                  "void main() { float x = texelFetch(u_tex, ivec2(gl_FragCoord.xy), 0).x;"
                  " o = vec4(sin(x), cos(x), 0.0, 1.0); }\n", (1024, 64), tex).reshape(-1, 4)
    xd = x.astype(np.float64)
    assert np.abs(out[:, 0] - np.sin(xd)).max() <= SIN_COS_ABS
    assert np.abs(out[:, 1] - np.cos(xd)).max() <= SIN_COS_ABS


def test_compat_profile_runs_textbook_glsl() -> None:
    """GLSL 1.20 as the textbooks print it: varying, ftransform(), gl_NormalMatrix, gl_LightSource, gl_FragColor,
    with the fixed-function state set through PyOpenGL (identity matrices: gl_NormalMatrix n = n)."""
    ok, why = runtime.available("llvmpipe-compat")
    if not ok:
        pytest.skip(f"no compatibility profile: {why}")
    from OpenGL import GL

    ctx = runtime.get("llvmpipe-compat")
    with ctx:
        prog = ctx.program("#version 120\nvarying vec3 n;\n"
                           "void main() { n = gl_NormalMatrix * gl_Normal; gl_Position = ftransform(); }\n",
                           "#version 120\nvarying vec3 n;\n"
                           "void main() { gl_FragColor = vec4(n, gl_LightSource[0].diffuse.r); }\n")
        fbo = ctx.float_target(4, 4)
        GL.glLightfv(GL.GL_LIGHT0, GL.GL_DIFFUSE, (0.25, 0.0, 0.0, 1.0))
        GL.glMatrixMode(GL.GL_MODELVIEW)
        GL.glLoadIdentity()
        GL.glUseProgram(prog.glo)
        GL.glBindVertexArray(0)
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, 0)
        GL.glBegin(GL.GL_TRIANGLES)
        for x, y in ((-1.0, -1.0), (3.0, -1.0), (-1.0, 3.0)):
            GL.glNormal3f(0.0, 0.6, 0.8)
            GL.glVertex2f(x, y)
        GL.glEnd()
        out = egl.read_rgba32f(fbo)
        fbo.release()
    assert "Compatibility" in ctx.info["GL_VERSION"]
    assert np.allclose(out[..., :3], np.float32([0.0, 0.6, 0.8]), rtol=0, atol=2 ** -23)
    assert np.all(out[..., 3] == np.float32(0.25))


def test_shader_error_names_the_line() -> None:
    """A syntax error on the file's line 3 (numbered from #line 1) is reported at line 3 with the driver's text."""
    ctx = runtime.get("llvmpipe")
    bad = "#version 450 core\nout vec4 o;\n#line 1\n// one\n// two\nvoid main() { o = vec4(1.0) }\n"
    with ctx, pytest.raises(egl.ShaderError) as err:
        ctx.program(egl.FULLSCREEN_VERTEX_CORE, bad)
    assert err.value.line == 3 and err.value.stage == "fragment"
    assert "syntax error" in err.value.message and "\n" not in str(err.value)


def test_meta_and_restart() -> None:
    """meta() carries GL_RENDERER/GL_VERSION of started runtimes; close → a later get starts a fresh one."""
    first = runtime.get("llvmpipe")
    assert "llvmpipe" in runtime.meta()["llvmpipe"]["GL_RENDERER"]
    runtime.close("llvmpipe")
    assert "llvmpipe" not in runtime.meta()
    second = runtime.get("llvmpipe")
    assert second is not first and runtime.startup_seconds("llvmpipe") is not None
    runtime.close_all()
    runtime.close_all()  # idempotent


def test_no_gl_says_why(monkeypatch: pytest.MonkeyPatch) -> None:
    runtime.close("llvmpipe-compat")
    monkeypatch.setenv("VALIDATE_NO_GL", "1")
    try:
        ok, why = runtime.available("llvmpipe-compat")
        assert not ok and "VALIDATE_NO_GL" in why
        assert runtime.meta()["llvmpipe-compat"] == {"unavailable": why}
    finally:
        runtime.reset_failures()


# SwiftShader's sin/cos on [-pi, pi] (the measurement, 1.9e-4 absolute); the bound is the measurement
# rounded up to 2.5e-4, so a change to a coarser approximation (≥ 1e-3) fails.
SWIFTSHADER_SIN_ABS = 2.5e-4


@pytest.mark.slow
def test_webgl2_round_trip_rows_and_precision() -> None:
    """Chromium WebGL2: RGBA32F in → out bit-exact, rows bottom-up, sin within SwiftShader's bound, and a
    syntax error on line 2 reported at line 2."""
    ok, why = runtime.available("webgl2")
    if not ok:
        pytest.skip(f"no WebGL2: {why}")
    rt = runtime.get("webgl2")
    vs = "#version 300 es\nin vec2 a_pos;\nvoid main() { gl_Position = vec4(a_pos, 0.0, 1.0); }\n"
    prog = rt.compile(vs, "#version 300 es\nprecision highp float;\nuniform highp sampler2D u_in0; out vec4 o;\n"
                      "void main() { vec4 a = texelFetch(u_in0, ivec2(gl_FragCoord.xy), 0);"
                      " o = vec4(a.x, sin(a.y), gl_FragCoord.y, 1.0); }\n")
    a = np.zeros((64, 1024, 4), dtype=np.float32)
    a[..., 0] = (np.random.default_rng(5).standard_normal((64, 1024)) * 1e6).astype(np.float32)
    a[..., 1] = np.linspace(-np.pi, np.pi, 64 * 1024, dtype=np.float32).reshape(64, 1024)
    out = rt.run(prog, (1024, 64), {"u_in0": a}, {}, {})
    assert np.array_equal(out[..., 0].view(np.uint32), a[..., 0].view(np.uint32))
    assert np.array_equal(out[:, 0, 2], np.arange(64, dtype=np.float32) + 0.5)
    assert np.abs(out[..., 1] - np.sin(a[..., 1].astype(np.float64))).max() <= SWIFTSHADER_SIN_ABS
    with pytest.raises(egl.ShaderError) as err:
        rt.compile(vs, "#version 300 es\nprecision highp float; out vec4 o;\n"
                   "#line 1\n//\nvoid main() { o = vec4(1) }\n")
    assert err.value.line == 2
    assert "SwiftShader" in rt.info["GL_RENDERER"] and "WebGL 2.0" in rt.info["GL_VERSION"]
