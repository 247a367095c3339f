"""Named inputs of the ``validate.testing`` checks: built-in environments and light probes by name.

Shared by :mod:`validate.testing` (``check_irradiance``) and the experiments' ``check`` modules (e.g.
:func:`validate.experiments.ibl.check.check_specular`), so that nothing below ``testing`` imports it.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from ..errors import ValidateError
from ..scenes import procedural
from ..scenes.loaders import load_environment

PROBE_EXTENSIONS = (".hdr", ".exr", ".pfm")


class MissingProbe(ValidateError):
    """A probe named in ``environments`` was not found (one line: the name and where it was looked for)."""


def probe_dirs() -> list[Path]:
    """Where probe names are looked up, in order: ``$VALIDATE_PROBES``, else the checkout's
    ``../shared/probes``, else ``./../shared/probes`` (relative to the working folder)."""
    env = os.environ.get("VALIDATE_PROBES")
    if env:
        return [Path(env)]
    checkout = Path(__file__).resolve().parents[2]  # validate/experiments/inputs.py → the checkout
    return [checkout.parent / "shared" / "probes", Path.cwd().parent / "shared" / "probes"]


def find_probe(name: str) -> Path:
    """The probe file for ``name`` (a path, or a stem looked up in :func:`probe_dirs`); else MissingProbe."""
    as_path = Path(name)
    if as_path.suffix.lower() in PROBE_EXTENSIONS or as_path.parent != Path("."):
        if as_path.is_file():
            return as_path
        raise MissingProbe(f"{name}: probe file not found")
    dirs = probe_dirs()
    for d in dirs:
        for ext in PROBE_EXTENSIONS:
            if (d / f"{name}{ext}").is_file():
                return d / f"{name}{ext}"
    where = ", ".join(str(d) for d in dirs)
    raise MissingProbe(f"{name}: light probe not found (looked for {name}.hdr/.exr/.pfm in {where}); "
                       "set VALIDATE_PROBES to the folder holding it")


def load_named_environment(name: str) -> Any:
    """A built-in environment (full size) or a probe (:func:`find_probe`) as an Environment."""
    if name in procedural.BUILTIN_NAMES:
        return procedural.builtin_environment(name)
    return load_environment(find_probe(name))


__all__ = ["PROBE_EXTENSIONS", "MissingProbe", "find_probe", "load_named_environment", "probe_dirs"]
