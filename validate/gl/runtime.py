"""The GL runtimes of a run: started once (lazily, on first use), shut down cleanly.

Kinds
-----
``"llvmpipe"``         Mesa llvmpipe, OpenGL 4.5 core profile (:func:`validate.gl.egl.create_context`).
``"llvmpipe-compat"``  the same driver, 4.5 compatibility profile (the textbooks' GLSL 1.10/1.20).
``"webgl2"``           headless Chromium, WebGL2 / GLSL ES 3.00 on SwiftShader (:mod:`validate.gl.webgl`).

:func:`get` returns the one runtime of a kind for this process (a forked child starts its own);
:func:`available` says whether a kind can start, and why not; :func:`close_all` (registered with
``atexit``, and called by the CLI at the end of a command) shuts every started runtime down;
:func:`meta` gives the ``GL_RENDERER``/``GL_VERSION`` strings of the runtimes started, for
``results.json`` ``meta.gl``.

``VALIDATE_NO_GL=1`` in the environment makes every kind unavailable (to exercise the no-GL path).
"""

from __future__ import annotations

import atexit
import os
import threading
import time
from typing import Any

KINDS = ("llvmpipe", "llvmpipe-compat", "webgl2")
DEFAULT_KIND = "llvmpipe"

_lock = threading.RLock()
_started: dict[str, Any] = {}  # kind -> runtime object (egl.Context or webgl.WebGL2)
_startup_s: dict[str, float] = {}  # kind -> seconds its start took
_failed: dict[str, str] = {}  # kind -> reason it could not start
_elsewhere: dict[str, dict[str, str]] = {}  # kind -> meta of a runtime started by another process of this run
_pid = os.getpid()


def _check_kind(kind: str) -> None:
    if kind not in KINDS:
        raise ValueError(f"GL runtime kind must be one of {KINDS}, got {kind!r}")


def _forget_after_fork() -> None:
    global _pid
    if os.getpid() != _pid:  # the parent's contexts/browsers are not ours to use or close
        _started.clear()
        _startup_s.clear()
        _failed.clear()
        _pid = os.getpid()


def _start(kind: str) -> Any:
    if kind == "webgl2":
        from validate.gl import webgl  # noqa: PLC0415

        return webgl.WebGL2()
    from validate.gl import egl  # noqa: PLC0415

    return egl.create_context("core" if kind == "llvmpipe" else "compat")


def get(kind: str = DEFAULT_KIND) -> Any:
    """The started runtime of ``kind`` (starting it on first call); raises GLUnavailable with the reason."""
    from validate.gl.egl import GLUnavailable  # noqa: PLC0415

    _check_kind(kind)
    with _lock:
        _forget_after_fork()
        if kind in _started:
            return _started[kind]
        if os.environ.get("VALIDATE_NO_GL"):
            _failed[kind] = "VALIDATE_NO_GL is set"
        if kind in _failed:
            raise GLUnavailable(_failed[kind])
        t0 = time.perf_counter()
        try:
            rt = _start(kind)
        except Exception as exc:  # any failure to start is "unavailable, because …", never a crash
            _failed[kind] = " ".join(f"{type(exc).__name__}: {exc}".split())
            raise GLUnavailable(_failed[kind]) from exc
        _startup_s[kind] = time.perf_counter() - t0
        _started[kind] = rt
        return rt


def available(kind: str = DEFAULT_KIND) -> tuple[bool, str]:
    """(True, renderer string) when ``kind`` starts here, else (False, the reason)."""
    from validate.gl.egl import GLUnavailable  # noqa: PLC0415

    try:
        rt = get(kind)
    except GLUnavailable as exc:
        return False, str(exc)
    return True, f"{rt.info['GL_RENDERER']}, {rt.info['GL_VERSION']}"


def startup_seconds(kind: str) -> float | None:
    """Wall seconds the start of ``kind`` took in this process (None if not started)."""
    return _startup_s.get(kind)


def meta() -> dict[str, dict[str, str]]:
    """``{kind: {GL_RENDERER, GL_VERSION, GL_SHADING_LANGUAGE_VERSION, GL_VENDOR}}`` of started runtimes,
    plus ``{kind: {"unavailable": reason}}`` of kinds that failed to start."""
    with _lock:
        _forget_after_fork()
        out: dict[str, dict[str, str]] = {k: dict(rt.info) for k, rt in _started.items()}
        out.update({k: {"unavailable": why} for k, why in _failed.items()})
        return {**_elsewhere, **out}


def note_elsewhere(started: dict[str, dict[str, str]]) -> None:
    """Record the :func:`meta` of another process of this run (the second lane of experiments), so this
    process's :func:`meta` lists the runtimes it started too."""
    with _lock:
        _elsewhere.update(started)


def close(kind: str) -> None:
    """Shut down the runtime of ``kind`` if started (a later :func:`get` starts a fresh one)."""
    with _lock:
        _forget_after_fork()
        rt = _started.pop(kind, None)
        _startup_s.pop(kind, None)
        _elsewhere.pop(kind, None)
    if rt is not None:
        rt.release()


def close_all() -> None:
    """Shut down every started runtime (idempotent; registered with atexit, called by the CLI) and forget those
    noted from elsewhere."""
    _elsewhere.clear()
    for kind in list(_started):
        try:
            close(kind)
        except Exception:  # shutting down: a runtime that fails to close must not mask the real result
            pass


def reset_failures() -> None:
    """Forget recorded start failures (tests that toggle VALIDATE_NO_GL)."""
    with _lock:
        _failed.clear()


atexit.register(close_all)
