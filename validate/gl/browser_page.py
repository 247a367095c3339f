"""A page in the run's one headless Chromium that can import ES modules from ``node_modules``.

:mod:`validate.gl.webgl` starts the browser (SwiftShader WebGL2) with an ``about:blank`` page holding a
raw WebGL2 canvas; engines (three.js, Babylon.js) need ES-module imports, so this module serves two
folders over a loopback HTTP server started once per process — ``/node_modules/`` (the project's
pinned npm engines of :func:`validate.setup.paths.node_modules`) and ``/pages/`` (the engine scripts of
:mod:`validate.local_models.render`) — and opens one extra tab per page in the *same* browser
(:func:`validate.gl.runtime.get` ``("webgl2")``), so a run still starts one browser.

Arrays cross the page boundary as base64 float32 bytes, unchanged (as in :mod:`validate.gl.webgl`).
The playwright sync API is bound to its thread: use a page from the thread that started the runtime.
"""

from __future__ import annotations

import base64
import functools
import http.server
import threading
from pathlib import Path
from typing import Any

import numpy as np

from ..setup import paths
from . import runtime
from .egl import GLUnavailable

PAGES = Path(__file__).resolve().parents[1] / "local_models" / "render"

_server: dict[str, Any] = {}
_pages: dict[str, Any] = {}
_pending: dict[str, tuple[Any, list[str]]] = {}  # name → (page still loading, its errors)
_lock = threading.RLock()


class _Handler(http.server.SimpleHTTPRequestHandler):
    """Static files of the served root, only under /node_modules/ and /validate/local_models/render/; quiet."""

    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map, ".js": "text/javascript",
                      ".mjs": "text/javascript"}

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 - the base class's name
        pass

    def end_headers(self) -> None:
        self.send_header("Cache-Control", "max-age=3600")
        super().end_headers()


def served_root() -> Path:
    """A private temporary folder holding links to node_modules and the pages, and ``data/`` (published files)."""
    with _lock:
        if "root" not in _server:
            import atexit
            import shutil
            import tempfile

            root = Path(tempfile.mkdtemp(prefix="validate-pages-"))
            atexit.register(shutil.rmtree, root, True)
            (root / "node_modules").symlink_to(paths.node_modules())
            (root / "validate" / "local_models").mkdir(parents=True)
            (root / "validate" / "local_models" / "render").symlink_to(PAGES)
            (root / "data").mkdir()
            _server["root"] = root
        return Path(_server["root"])


def publish(name: str, data: bytes) -> str:
    """Serve ``data`` at ``/data/<name>`` (written once per name); returns the URL path."""
    path = served_root() / "data" / name
    if not path.exists():
        tmp = path.with_suffix(path.suffix + ".part")
        tmp.write_bytes(data)
        tmp.replace(path)
    return f"/data/{name}"


def base_url() -> str:
    """``http://127.0.0.1:PORT`` of the static server (started on first call, a daemon thread)."""
    with _lock:
        if "url" not in _server:
            if not (paths.node_modules() / "three").exists():
                raise GLUnavailable(f"{paths.node_modules()}: npm engines not installed "
                                    "(run `python -m validate setup --engines`)")
            handler = functools.partial(_Handler, directory=str(served_root()))
            srv = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
            threading.Thread(target=srv.serve_forever, daemon=True).start()
            _server.update(server=srv, url=f"http://127.0.0.1:{srv.server_address[1]}")
        return str(_server["url"])


def _navigate(name: str, timeout_s: float) -> tuple[Any, list[str]]:
    """A new tab of the run's browser navigated to the page (returns once the navigation commits: the page's
    modules then load in the browser while Python goes on) and the list its page errors are appended to."""
    rt = runtime.get("webgl2")
    browser = getattr(rt, "_browser", None)  # TODO(merge): a public WebGL2.new_page() on branch gl
    if browser is None:
        raise GLUnavailable("webgl2 runtime has no browser")
    page = browser.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(f"{base_url()}/validate/local_models/render/{name}", wait_until="commit", timeout=timeout_s * 1000)
    return page, errors


def preload(names: list[str], timeout_s: float = 300.0) -> None:
    """Start loading the pages ``names`` (each once per process) without waiting for them: the browser loads their
    modules side by side, and :func:`open_page` later waits for each. Nothing is raised here — a page or runtime
    that cannot start is reported by :func:`open_page`, as without a preload."""
    with _lock:
        for name in dict.fromkeys(names):
            if name in _pages or name in _pending:
                continue
            try:
                _pending[name] = _navigate(name, timeout_s)
            except Exception:  # open_page tries again and raises the reason
                return


def open_page(name: str, timeout_s: float = 300.0) -> Any:
    """The playwright page for ``validate/local_models/render/<name>`` (opened once per process).

    The page must set ``window.ready = true`` (or ``window.ready = "error text"``) once its modules
    have loaded. Raises :class:`GLUnavailable` with the reason when Chromium or the page cannot start.
    """
    with _lock:
        if name in _pages:
            return _pages[name]
        page, errors = _pending.pop(name, None) or _navigate(name, timeout_s)
        try:
            page.wait_for_function("window.ready !== undefined", timeout=timeout_s * 1000)
        except Exception as exc:
            raise GLUnavailable(f"{name}: page did not load ({'; '.join(errors) or exc})") from exc
        ready = page.evaluate("window.ready")
        if ready is not True:
            raise GLUnavailable(f"{name}: {ready}")
        _pages[name] = page
        return page


def call(name: str, function: str, arg: Any, timeout_s: float = 300.0) -> Any:
    """``await window[function](arg)`` on page ``name``; a returned ``{error}`` raises GLUnavailable."""
    page = open_page(name)
    page.set_default_timeout(timeout_s * 1000)
    r = page.evaluate(f"(a) => window.{function}(a)", arg)
    if isinstance(r, dict) and "error" in r:
        raise GLUnavailable(f"{name}: {r['error']}")
    return r


def decode_f32(data: str, shape: tuple[int, ...]) -> np.ndarray:
    """base64 float32 bytes → array of ``shape`` (a copy)."""
    return np.frombuffer(base64.b64decode(data), dtype=np.float32).reshape(shape).copy()


def encode_f32(a: np.ndarray) -> str:
    """Array → base64 float32 bytes."""
    return base64.b64encode(np.ascontiguousarray(a, dtype=np.float32).tobytes()).decode("ascii")


__all__ = ["base_url", "publish", "served_root", "preload", "open_page", "call", "decode_f32", "encode_f32", "PAGES"]
