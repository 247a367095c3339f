"""The registry of engines under test: every module of this folder that declares an ``ENGINE``.

Discovery reads the folder's ``*.py`` files and imports only those whose source assigns ``ENGINE`` (or
``VARIANTS``) at module level — so a script this interpreter cannot import (``blender_worker.py``, run by Blender's
own Python) is never imported; by the same rule a module whose name starts with ``_`` or ends with ``_worker`` is
never an engine module. A module's ``ENGINE`` is one :class:`~.engine.Engine`; its optional ``VARIANTS`` are more
(three's ``three_probe``, Babylon's ``babylon_lambert`` and CDF sizes), each naming the engine it is a variant of.

:func:`register` adds an engine declared elsewhere (a ``--plugin`` file or module that declares ``ENGINE``: the
same attributes, :func:`register_module`), so an engine can live outside this folder too. Everything that lists
or drives engines asks here: the ``renders`` experiment and its claims, ``bench``, ``judge --engine``,
``python -m validate list``.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path
from types import ModuleType

from ...errors import ValidateError
from .engine import Engine

HERE = Path(__file__).resolve().parent
DECLARES = re.compile(r"^(ENGINE|VARIANTS)\s*(:[^=]*)?=", re.MULTILINE)
_found: dict[str, Engine] | None = None
_extra: dict[str, Engine] = {}


def engine_modules(folder: Path = HERE) -> list[str]:
    """The module names of ``folder`` that declare an engine (module docstring), sorted."""
    return sorted(p.stem for p in folder.glob("*.py")
                  if not p.stem.startswith("_") and not p.stem.endswith("_worker")
                  and DECLARES.search(p.read_text(encoding="utf-8")))


def declared(module: ModuleType) -> list[Engine]:
    """The engines a module declares: its ``ENGINE`` then its ``VARIANTS``."""
    out = [getattr(module, "ENGINE", None), *getattr(module, "VARIANTS", ())]
    engines = [e for e in out if e is not None]
    for e in engines:
        if not isinstance(e, Engine):
            raise ValidateError(f"{module.__name__}: ENGINE/VARIANTS hold {type(e).__name__}, not an Engine")
    return engines


def _discover() -> dict[str, Engine]:
    found: dict[str, Engine] = {}
    for name in engine_modules():
        for e in declared(importlib.import_module(f"{__package__}.{name}")):
            if e.name in found:
                raise ValidateError(f"engine {e.name!r} declared twice ({name}.py)")
            found[e.name] = e
    return found


def engines() -> dict[str, Engine]:
    """Every engine: this folder's (discovered once per process), then the registered ones; name → engine."""
    global _found
    if _found is None:
        _found = _discover()
    return {**_found, **_extra}


def register(engine: Engine) -> Engine:
    """Add an engine declared outside this folder (a plug-in, a test); a second one of a name replaces the first."""
    if not isinstance(engine, Engine):
        raise ValidateError(f"register: {type(engine).__name__} is not an Engine")
    _extra[engine.name] = engine
    return engine


def unregister(name: str) -> None:
    """Drop an engine :func:`register` added (a test's)."""
    _extra.pop(name, None)


def register_module(module: ModuleType) -> list[Engine]:
    """Register the engines ``module`` declares (``ENGINE``, ``VARIANTS``); [] when it declares none."""
    return [register(e) for e in declared(module)]


def get(name: str) -> Engine:
    """The engine of that name; one line naming the known ones else."""
    found = engines()
    if name not in found:
        raise ValidateError(f"engine {name!r}: not a registered engine (known: {', '.join(sorted(found))})")
    return found[name]


def find(name: str) -> Engine | None:
    """The engine of that name, or None."""
    return engines().get(name)


def product(name: str) -> str:
    """What an engine name renders with, for a person (``babylon_cdf64_shipped`` → Babylon.js); the name itself
    when no engine of it is registered."""
    e = find(name)
    if e is None:
        return name
    base = find(e.variant_of) if e.variant_of else None
    return (base or e).product


def main_engines() -> list[Engine]:
    """The engines that are not variants of another, in discovery order."""
    return [e for e in engines().values() if not e.variant_of]


__all__ = ["engines", "get", "find", "product", "register", "unregister", "register_module", "engine_modules",
           "declared", "main_engines"]
