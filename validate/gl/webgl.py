"""WebGL2 in headless Chromium (SwiftShader through ANGLE): GLSL ES 3.00 shaders, float32 read-back.

Debian's ``chromium`` driven by Python ``playwright`` (``executable_path``: no browser download), flags
``--use-angle=swiftshader --enable-unsafe-swiftshader --ignore-gpu-blocklist`` so WebGL2 runs on the
CPU. The page holds one WebGL2 canvas with ``EXT_color_buffer_float``: render targets are RGBA32F
textures read with ``readPixels(…, RGBA, FLOAT)``; inputs are RGBA32F textures (NEAREST, read with
``texelFetch``). Arrays cross the page boundary as base64 float32 bytes, unchanged.

Conventions as :mod:`validate.gl.egl`: **rows bottom-up** (row 0 = ``gl_FragCoord.y = 0.5``), texel
(x, y) = array row y, column x. Precision (measured): SwiftShader's ``sin``/``cos`` within 1.9e-4
absolute (the issue's measurement), far coarser than llvmpipe's.

The playwright *sync* API is bound to the thread that started it: use a :class:`WebGL2` from one thread.

References
----------
[1] Khronos, WebGL 2.0 specification, §5.14 (readPixels), EXT_color_buffer_float.
[2] Khronos, The OpenGL ES Shading Language 3.00.6.
"""

from __future__ import annotations

import base64
import os
import shutil
import threading
from typing import Any

import numpy as np

from .egl import GLUnavailable, ShaderError, parse_shader_log

CHROMIUM = os.environ.get("VALIDATE_CHROMIUM", "/usr/bin/chromium")
FLAGS = ("--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist", "--headless",
         "--no-sandbox", "--disable-gpu-sandbox", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", "--no-first-run")

PAGE = """<!doctype html><html><body><canvas id="c" width="1" height="1"></canvas><script>
const gl = document.getElementById('c').getContext('webgl2', {antialias: false});
const ext = gl && gl.getExtension('EXT_color_buffer_float');
const progs = [];
function b64ToF32(s) { const b = atob(s); const u = new Uint8Array(b.length);
  for (let i = 0; i < b.length; i++) u[i] = b.charCodeAt(i); return new Float32Array(u.buffer); }
function f32ToB64(f) { const u = new Uint8Array(f.buffer); let s = '';
  for (let i = 0; i < u.length; i += 0x8000) s += String.fromCharCode.apply(null, u.subarray(i, i + 0x8000));
  return btoa(s); }
window.info = function() {
  if (!gl) return {error: 'no WebGL2 context'};
  if (!ext) return {error: 'EXT_color_buffer_float unavailable'};
  const dbg = gl.getExtension('WEBGL_debug_renderer_info');
  return {GL_RENDERER: dbg ? gl.getParameter(dbg.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER),
          GL_VERSION: gl.getParameter(gl.VERSION),
          GL_SHADING_LANGUAGE_VERSION: gl.getParameter(gl.SHADING_LANGUAGE_VERSION),
          GL_VENDOR: dbg ? gl.getParameter(dbg.UNMASKED_VENDOR_WEBGL) : gl.getParameter(gl.VENDOR)};
};
window.compile = function(vs, fs) {
  const out = {};
  const sh = [[gl.VERTEX_SHADER, vs, 'vertex'], [gl.FRAGMENT_SHADER, fs, 'fragment']].map(([t, src, name]) => {
    const s = gl.createShader(t); gl.shaderSource(s, src); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS) && !out.stage) {
      out.stage = name; out.log = gl.getShaderInfoLog(s); }
    return s; });
  if (out.stage) return out;
  const p = gl.createProgram(); gl.attachShader(p, sh[0]); gl.attachShader(p, sh[1]);
  gl.bindAttribLocation(p, 0, 'a_pos'); gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) return {stage: 'link', log: gl.getProgramInfoLog(p)};
  const types = {};
  for (let i = 0; i < gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS); i++) {
    const u = gl.getActiveUniform(p, i); types[u.name.replace(/\\[0\\]$/, '')] = u.type; }
  progs.push({p: p, types: types}); return {id: progs.length - 1};
};
function tex(w, h, data) {
  const t = gl.createTexture(); gl.bindTexture(gl.TEXTURE_2D, t);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, data); return t; }
window.run = function(id, w, h, textures, uniforms) {
  const pr = progs[id], p = pr.p; gl.useProgram(p);
  const made = [];
  textures.forEach((t, unit) => { gl.activeTexture(gl.TEXTURE0 + unit);
    made.push(tex(t.w, t.h, b64ToF32(t.data)));
    const loc = gl.getUniformLocation(p, t.name); if (loc) gl.uniform1i(loc, unit); });
  for (const [name, v] of Object.entries(uniforms)) {
    const loc = gl.getUniformLocation(p, name), ty = pr.types[name]; if (!loc) continue;
    const a = v.int ? new Int32Array(v.values) : new Float32Array(v.values);
    switch (ty) {
      case gl.FLOAT: gl.uniform1fv(loc, a); break; case gl.FLOAT_VEC2: gl.uniform2fv(loc, a); break;
      case gl.FLOAT_VEC3: gl.uniform3fv(loc, a); break; case gl.FLOAT_VEC4: gl.uniform4fv(loc, a); break;
      case gl.INT: case gl.BOOL: gl.uniform1iv(loc, a); break; case gl.INT_VEC2: gl.uniform2iv(loc, a); break;
      case gl.INT_VEC3: gl.uniform3iv(loc, a); break; case gl.INT_VEC4: gl.uniform4iv(loc, a); break;
      case gl.FLOAT_MAT3: gl.uniformMatrix3fv(loc, false, a); break;
      case gl.FLOAT_MAT4: gl.uniformMatrix4fv(loc, false, a); break;
    } }
  gl.activeTexture(gl.TEXTURE0 + textures.length);
  const target = tex(w, h, null); const fb = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
  if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE)
    return {error: 'float framebuffer incomplete'};
  gl.viewport(0, 0, w, h);
  const buf = gl.createBuffer(); gl.bindBuffer(gl.ARRAY_BUFFER, buf);
  gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
  gl.enableVertexAttribArray(0); gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);
  gl.drawArrays(gl.TRIANGLES, 0, 3);
  const out = new Float32Array(w * h * 4); gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, out);
  const err = gl.getError();
  gl.deleteBuffer(buf); gl.deleteFramebuffer(fb); gl.deleteTexture(target); made.forEach(t => gl.deleteTexture(t));
  return err ? {error: 'GL error 0x' + err.toString(16)} : {data: f32ToB64(out)};
};
</script></body></html>"""


def _b64(a: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(a, dtype=np.float32).tobytes()).decode("ascii")


def _uniform(value: Any) -> dict[str, Any]:
    arr = np.asarray(value)
    return {"int": arr.dtype.kind in "iub", "values": arr.astype(np.float64).ravel().tolist()}


class WebGL2:
    """One headless Chromium with a WebGL2 page (``info``, ``compile``, ``run``, ``release``)."""

    def __init__(self) -> None:
        if not shutil.which(CHROMIUM) and not os.path.exists(CHROMIUM):
            raise GLUnavailable(f"{CHROMIUM} not found (Debian package chromium)")
        try:
            from playwright.sync_api import sync_playwright  # noqa: PLC0415
        except ImportError as exc:
            raise GLUnavailable(f"Python playwright not installed ({exc})") from exc
        self.lock = threading.RLock()
        self._pw = sync_playwright().start()
        try:
            self._browser = self._pw.chromium.launch(executable_path=CHROMIUM, headless=True, args=list(FLAGS))
            self._page = self._browser.new_page()
            self._page.set_content(PAGE)
            info = self._page.evaluate("info()")
        except Exception:
            self.release()
            raise
        if "error" in info:
            self.release()
            raise GLUnavailable(f"chromium WebGL2: {info['error']}")
        self.info = {k: str(v) for k, v in info.items()}

    def compile(self, vertex_shader: str, fragment_shader: str) -> int:
        """Compile and link; returns a program id; a failure raises :class:`~.egl.ShaderError`."""
        with self.lock:
            r = self._page.evaluate("([vs, fs]) => compile(vs, fs)", [vertex_shader, fragment_shader])
        if "id" not in r:
            raise parse_shader_log(r.get("stage", "link"), r.get("log") or "")
        return int(r["id"])

    def run(self, program: int, size: tuple[int, int], packed: dict[str, np.ndarray],
            textures: dict[str, np.ndarray], uniforms: dict[str, Any]) -> np.ndarray:
        """Draw ``program`` over a width × height RGBA32F target; (H, W, 4) float32, row 0 = bottom."""
        w, h = size
        texs = [{"name": k, "w": int(a.shape[1]), "h": int(a.shape[0]), "data": _b64(a)}
                for k, a in list(packed.items()) + list(textures.items())]
        unis = {k: _uniform(v) for k, v in uniforms.items()}
        with self.lock:
            r = self._page.evaluate("([id, w, h, t, u]) => run(id, w, h, t, u)", [program, w, h, texs, unis])
        if "error" in r:
            raise GLUnavailable(f"chromium WebGL2: {r['error']}")
        return np.frombuffer(base64.b64decode(r["data"]), dtype=np.float32).reshape(h, w, 4).copy()

    def release(self) -> None:
        """Close the browser and stop playwright (idempotent)."""
        for name in ("_browser", "_pw"):
            obj = getattr(self, name, None)
            if obj is not None:
                try:
                    obj.close() if name == "_browser" else obj.stop()
                except Exception:  # already gone (the process exits, the pipe broke): nothing left to free
                    pass
                setattr(self, name, None)

    # the same context-manager shape as egl.Context, so callers can hold the lock alike
    def __enter__(self) -> WebGL2:
        self.lock.acquire()
        return self

    def __exit__(self, *exc: object) -> None:
        self.lock.release()


__all__ = ["WebGL2", "ShaderError", "GLUnavailable", "FLAGS", "CHROMIUM"]
