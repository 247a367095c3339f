"""The Node side: one long-lived ``node runner.mjs <engine>`` process per engine per Python process.

Importing this module starts nothing. The first call for an engine starts its process (a few tenths
of a second); every later call reuses it: ``project`` sends the six faces once per environment
content (keyed by a hash of the radiance, the face size, the texel format and the clamp setting) and
``evaluate`` sends only the normals. Faces rendered for one environment are shared by the engines
(a small LRU), so a run over many environments costs one face rendering and one projection per
engine per environment. Frames: ``u32 header length · JSON header · raw payload`` (see runner.mjs).
"""

from __future__ import annotations

import atexit
import hashlib
import json
import os
import shutil
import struct
import subprocess
import tempfile
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ....errors import ValidateError
from ....setup import paths
from .cube_faces import render_faces

HERE = Path(__file__).resolve().parent
RUNNER = HERE / "runner.mjs"
ENGINES = {"three": ("three",), "babylon": ("@babylonjs", "core")}
FACE_SIZE = 64  # cube face size handed to the engines (sweep: 32–256 in the engines experiment)
FACE_CACHE = 4  # environments whose faces are kept (LRU)


@dataclass(frozen=True)
class FaceSettings:
    """How faces reach the engine: size N (texels per edge), texel format, Babylon's 4096 clamp."""

    size: int = FACE_SIZE
    dtype: str = "float32"  # "float32" | "float16" (a half-float render target)
    clamp: bool = True  # False: CubeMapToSphericalPolynomialTools.MAX_HDRI_VALUE = ∞ (Babylon only)


def node_executable() -> str | None:
    """The ``node`` on PATH (``VALIDATE_NODE`` overrides), or None."""
    exe = os.environ.get("VALIDATE_NODE") or shutil.which("node")
    return exe if exe and Path(exe).exists() else None


def package_dir(engine: str) -> Path | None:
    """The engine's npm package in the per-user engines folder (:func:`validate.setup.paths.node_modules`)."""
    p = paths.node_modules().joinpath(*ENGINES[engine])
    return p if (p / "package.json").is_file() else None


def unavailable_reason() -> str | None:
    """Why the engines cannot run here (one line), or None when Node and both packages are present."""
    if node_executable() is None:
        return "Node.js not found on PATH (`python -m validate setup --engines` installs it and the engines)"
    missing = [" / ".join(ENGINES[e]).replace(" / ", "/") for e in ENGINES if package_dir(e) is None]
    if missing:
        return (f"npm package(s) {', '.join(missing)} not installed in {paths.node_modules()}: "
                "run `python -m validate setup --engines`")
    return None


def package_version(engine: str) -> str:
    p = package_dir(engine)
    return json.loads((p / "package.json").read_text())["version"] if p else "absent"


class NodeWorker:
    """One ``node runner.mjs <engine>`` process speaking the framed protocol over its stdin/stdout."""

    def __init__(self, engine: str):
        self.engine = engine
        self.proc: subprocess.Popen[bytes] | None = None
        self.keys: dict[str, dict[str, Any]] = {}
        self.pid = os.getpid()
        self._stderr = tempfile.TemporaryFile()

    def _start(self) -> None:
        exe = node_executable()
        if exe is None:
            raise ValidateError(f"engine {self.engine}: {unavailable_reason()}")
        # the scripts run from a copy beside the installed node_modules, so `import 'three'` resolves there
        scripts = paths.node_scripts(HERE)
        self.proc = subprocess.Popen([exe, str(scripts / RUNNER.name), self.engine], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=self._stderr, cwd=str(scripts))
        self.keys.clear()

    def _stderr_tail(self) -> str:
        self._stderr.seek(0)
        lines = self._stderr.read().decode("utf8", "replace").strip().splitlines()
        return lines[-1] if lines else "no message"

    def request(self, header: dict[str, Any], payload: bytes = b"") -> tuple[dict[str, Any], bytes]:
        """Send one frame, read one frame; a dead process or an engine error is a one-line ValidateError."""
        if self.proc is None or self.proc.poll() is not None:
            self._start()
        assert self.proc is not None and self.proc.stdin is not None and self.proc.stdout is not None
        head = json.dumps({**header, "payload_bytes": len(payload)}).encode()
        try:
            self.proc.stdin.write(struct.pack("<I", len(head)) + head + payload)
            self.proc.stdin.flush()
            n = struct.unpack("<I", self._read(4))[0]
            reply = json.loads(self._read(n))
            body = self._read(int(reply.get("payload_bytes", 0)))
        except (BrokenPipeError, EOFError, OSError) as exc:
            self.close()
            raise ValidateError(f"engine {self.engine}: Node process ended ({exc}; {self._stderr_tail()})") from None
        if not reply.get("ok"):
            raise ValidateError(f"engine {self.engine}: {reply.get('error', 'unknown error')}")
        return reply, body

    def _read(self, n: int) -> bytes:
        assert self.proc is not None and self.proc.stdout is not None
        buf = self.proc.stdout.read(n) if n else b""
        if len(buf) != n:
            raise EOFError(f"short read {len(buf)} of {n} bytes")
        return buf

    def close(self) -> None:
        if self.proc is not None:
            try:
                if self.proc.stdin:
                    self.proc.stdin.close()
                self.proc.wait(timeout=5)
            except (OSError, subprocess.TimeoutExpired):
                self.proc.kill()
            self.proc = None
        self.keys.clear()


_WORKERS: dict[str, NodeWorker] = {}
_FACES: OrderedDict[tuple[str, int], np.ndarray] = OrderedDict()


def worker(engine: str) -> NodeWorker:
    """The engine's process for this Python process (a forked child gets its own)."""
    w = _WORKERS.get(engine)
    if w is None or w.pid != os.getpid():
        w = _WORKERS[engine] = NodeWorker(engine)
    return w


@atexit.register
def close_workers() -> None:
    """End every Node process this Python process started."""
    for w in list(_WORKERS.values()):
        if w.pid == os.getpid():
            w.close()
    _WORKERS.clear()


def radiance_digest(radiance: np.ndarray) -> str:
    a = np.ascontiguousarray(radiance, dtype=np.float32)
    digest = hashlib.blake2b(digest_size=16)
    digest.update(memoryview(a.reshape(-1)).cast("B"))  # the buffer itself: no copy of the map
    digest.update(str(a.shape).encode())
    return digest.hexdigest()


def faces_for(radiance: np.ndarray, size: int, digest: str | None = None) -> np.ndarray:
    """Texel-averaged faces (6, N, N, 3) float32 of ``radiance``, cached by content (LRU)."""
    key = (digest or radiance_digest(radiance), size)
    if key in _FACES:
        _FACES.move_to_end(key)
        return _FACES[key]
    faces = render_faces(radiance, size)
    _FACES[key] = faces
    while len(_FACES) > FACE_CACHE:
        _FACES.popitem(last=False)
    return faces


def encode_faces(faces: np.ndarray, dtype: str, engine: str) -> tuple[bytes, str]:
    """RGBA texels in the format the engine reads: float32, or half floats (three.js gets the IEEE half
    bits of a HalfFloatType target; Babylon gets the half-rounded values as float32, as its readPixels
    hands a half-float texture back). Half floats overflow to ∞ above 65504."""
    rgba = np.concatenate([faces, np.ones(faces.shape[:-1] + (1,), np.float32)], axis=-1)
    if dtype == "float32":
        return np.ascontiguousarray(rgba, np.float32).tobytes(), "float32"
    if dtype != "float16":
        raise ValidateError(f"engine faces: texel format {dtype!r} is not float32 or float16")
    with np.errstate(over="ignore"):
        half = rgba.astype(np.float16)
    if engine == "three":
        return np.ascontiguousarray(half).view(np.uint16).tobytes(), "float16"
    return half.astype(np.float32).tobytes(), "float32"


def project(engine: str, radiance: np.ndarray, settings: FaceSettings = FaceSettings(),
            faces: np.ndarray | None = None) -> tuple[str, dict[str, Any]]:
    """Run the engine's projection on the faces of ``radiance`` (or on ``faces`` as given); returns the
    key under which the Node process keeps it and the engine's coefficients."""
    w = worker(engine)
    digest = radiance_digest(radiance if faces is None else faces)
    key = f"{digest}:{settings.size}:{settings.dtype}:{int(settings.clamp)}:{int(faces is not None)}"
    if key not in w.keys:
        f = faces_for(radiance, settings.size, digest) if faces is None else faces
        payload, wire = encode_faces(f, settings.dtype, engine)
        reply, _ = w.request({"op": "project", "key": key, "size": int(f.shape[1]), "type": wire,
                              "clamp": settings.clamp}, payload)
        w.keys[key] = reply["coefficients"]
    return key, w.keys[key]


def evaluate(engine: str, key: str, path: str, normals: np.ndarray) -> np.ndarray:
    """E at ``normals`` (N, 3) through the engine's evaluation ``path``; (N, 3) float64."""
    n = np.ascontiguousarray(normals, dtype=np.float64).reshape(-1, 3)
    _, body = worker(engine).request({"op": "evaluate", "key": key, "path": path, "count": len(n)}, n.tobytes())
    return np.frombuffer(body, dtype=np.float64).reshape(-1, 3).copy()


def engine_irradiance(engine: str, path: str, radiance: np.ndarray, normals: np.ndarray,
                      settings: FaceSettings = FaceSettings(), faces: np.ndarray | None = None) -> np.ndarray:
    """Irradiance E (N, 3) of ``radiance`` at ``normals`` as the engine computes it."""
    key, _ = project(engine, radiance, settings, faces)
    return evaluate(engine, key, path, normals)


__all__ = ["FACE_SIZE", "FaceSettings", "NodeWorker", "engine_irradiance", "evaluate", "faces_for", "node_executable",
           "package_version", "project", "unavailable_reason", "worker", "close_workers"]
