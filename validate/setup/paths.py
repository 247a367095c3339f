"""Where the suite's runtimes outside Python live: one per-user data folder, the same for a checkout and a wheel.

``home()`` is ``$VALIDATE_HOME``, else ``$XDG_DATA_HOME/validate``, else ``~/.local/share/validate``. Under it:

* ``engines/`` — the npm engines: ``package.json`` and ``package-lock.json`` copied from this package
  (:data:`ENGINE_LOCK`, the pinned versions) and ``node_modules/`` written by ``npm ci``;
  ``engines/scripts-<hash>/`` holds copies of the package's Node scripts, so that Node resolves their bare
  imports (``import 'three'``) from ``engines/node_modules`` wherever the package itself is installed.
* ``blender-venv/`` — Blender as a Python module (``bpy``, :data:`BLENDER_BPY`) in a virtual environment of its own,
  made with the system's Python 3.11 (the only Python the bpy wheels are built for); it holds numpy < 2, which is
  why it is never the suite's own environment. The Blender engines run its interpreter as a child process.

The suite's cache (``cache_dir()``): ``$VALIDATE_CACHE`` if set (``off`` disables it), else
``$XDG_CACHE_HOME/validate`` (``~/.cache/validate``); :func:`array_digest` is the content hash its keys use.

Nothing here installs anything (:mod:`validate.setup.install` does); it only says where things are.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path
from typing import Any

ENGINE_LOCK = Path(__file__).resolve().parent / "engines"  # package.json + package-lock.json, shipped
BLENDER_BPY = "bpy==5.0.1"  # Blender 5.0.1 as a Python module: ≈1 GB installed, CPython 3.11 wheels only
BLENDER_PYTHON = "python3.11"  # the interpreter the bpy wheel needs (looked up on PATH)


def cache_dir() -> Path | None:
    """The cache folder (module docstring), or None when ``VALIDATE_CACHE=off``."""
    env = os.environ.get("VALIDATE_CACHE")
    if env == "off":
        return None
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "validate"


def array_digest(a: Any) -> str:
    """SHA-256 of an array's bytes, shape and dtype (24 hex digits): the content part of a cache key."""
    import numpy as np

    a = np.ascontiguousarray(a)
    return hashlib.sha256(a.tobytes() + str(a.shape).encode() + str(a.dtype).encode()).hexdigest()[:24]


def home() -> Path:
    """The per-user data folder (not created)."""
    if os.environ.get("VALIDATE_HOME"):
        return Path(os.environ["VALIDATE_HOME"]).expanduser()
    base = os.environ.get("XDG_DATA_HOME") or str(Path.home() / ".local" / "share")
    return Path(base) / "validate"


def engines_dir() -> Path:
    return home() / "engines"


def node_modules() -> Path:
    """Where ``npm ci`` puts the engines (``python -m validate setup --engines``)."""
    return engines_dir() / "node_modules"


def blender_venv() -> Path:
    """The Blender engines' own virtual environment (``python -m validate setup --blender``)."""
    return home() / "blender-venv"


def blender_python() -> Path:
    """The interpreter of :func:`blender_venv` (it imports ``bpy``); may not exist."""
    return blender_venv() / "bin" / "python"


def lock_digest() -> str:
    """Hash of the shipped package.json + package-lock.json: an install is current when its stamp holds it."""
    h = hashlib.sha256()
    for name in ("package.json", "package-lock.json"):
        h.update((ENGINE_LOCK / name).read_bytes())
    return h.hexdigest()


def stamp() -> Path:
    return node_modules() / ".validate-setup"


def pinned_versions() -> dict[str, str]:
    """Package → the version the lock file pins (the direct dependencies)."""
    return dict(json.loads((ENGINE_LOCK / "package.json").read_text())["dependencies"])


def installed_version(package: str) -> str | None:
    """The version of ``package`` in :func:`node_modules`, or None when it is not installed."""
    p = node_modules() / package / "package.json"
    try:
        return str(json.loads(p.read_text())["version"])
    except (OSError, ValueError, KeyError):
        return None


def node_scripts(src: Path) -> Path:
    """A copy of the ``.mjs`` files of ``src`` inside :func:`engines_dir` (made once per content), so their bare
    imports resolve from the installed ``node_modules``; returns that folder."""
    files = sorted(src.glob("*.mjs"))
    h = hashlib.sha256()
    for f in files:
        h.update(f.name.encode() + b"\0" + f.read_bytes())
    dst = engines_dir() / f"scripts-{src.name}-{h.hexdigest()[:16]}"
    if not dst.is_dir():
        engines_dir().mkdir(parents=True, exist_ok=True)
        tmp = dst.with_name(dst.name + f".part{os.getpid()}")
        shutil.rmtree(tmp, ignore_errors=True)
        tmp.mkdir()
        for f in files:
            shutil.copyfile(f, tmp / f.name)
        try:
            tmp.rename(dst)
        except OSError:  # another process made it first: the same content
            shutil.rmtree(tmp, ignore_errors=True)
    return dst
