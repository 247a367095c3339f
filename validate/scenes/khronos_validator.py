"""Khronos's glTF Validator on glTF files: the standard's own tool, run through Node.js.

The validator is npm ``gltf-validator`` (Khronos's Dart implementation compiled to JavaScript), pinned in the
engines' lock (``validate/setup/engines/package.json``) and installed by ``python -m validate setup --engines``;
``khronos_validator/validate_gltf.mjs`` runs it from the engines folder (:func:`validate.setup.paths.node_scripts`)
and prints, per file, the counts of errors, warnings, infos and hints and the messages (code, severity 0 = error …
3 = hint, JSON pointer, text) [1].

[1] Khronos, glTF-Validator (https://github.com/KhronosGroup/glTF-Validator), "Validation report" format.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path
from typing import Any

from ..errors import ValidateError
from ..setup.paths import installed_version, node_scripts

PACKAGE = "gltf-validator"
SCRIPT = Path(__file__).resolve().parent / "khronos_validator"
TIMEOUT_S = 120


def unavailable() -> str | None:
    """Why the validator cannot run here (no Node.js, the package not installed), or None when it can."""
    node = os.environ.get("VALIDATE_NODE") or shutil.which("node")
    if not node or not Path(node).exists():
        return "Node.js not found (VALIDATE_NODE or node on PATH)"
    if installed_version(PACKAGE) is None:
        return f"npm {PACKAGE} not installed: python -m validate setup --engines"
    return None


def validate_files(paths: list[Path]) -> list[dict[str, Any]]:
    """The validator's report of each file (module docstring); a ValidateError when it cannot run."""
    why = unavailable()
    if why:
        raise ValidateError(f"glTF Validator: {why}")
    node = os.environ.get("VALIDATE_NODE") or shutil.which("node")
    folder = node_scripts(SCRIPT)
    try:
        done = subprocess.run([str(node), str(folder / "validate_gltf.mjs"), *(str(Path(p).resolve()) for p in paths)],
                              capture_output=True, text=True, timeout=TIMEOUT_S, cwd=folder)
    except subprocess.TimeoutExpired:
        raise ValidateError(f"glTF Validator: no answer within {TIMEOUT_S} s") from None
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["(no output)"])[-1]
        raise ValidateError(f"glTF Validator: exit {done.returncode}: {last[:200]}")
    return list(json.loads(done.stdout))
