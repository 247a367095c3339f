"""Real GL runtimes: Mesa llvmpipe through EGL (:mod:`validate.gl.egl`), Chromium WebGL2
(:mod:`validate.gl.webgl`), started once per run by :mod:`validate.gl.runtime`."""
