"""Plug-ins named on the command line (``--plugin``): a ``.glsl`` file, a ``.py`` file or an importable module,
loaded in this process and, on a Dask run, once in every worker (``Context.worker_setup``). A plug-in that declares an
``ENGINE`` (and ``VARIANTS``), as an engine module of ``validate/local_models/render/`` does, has its engines registered
(:func:`validate.local_models.render.registry.register_module`; ``docs/engines.md``)."""

from __future__ import annotations

import importlib
import importlib.util
from pathlib import Path

from ..errors import ValidateError


def load_plugins(specs: tuple[str, ...]) -> None:
    """Import every plug-in (the setup each Dask worker runs once, see ``Context.worker_setup``)."""
    for spec in specs:
        load_plugin(spec)


def load_plugin(spec: str) -> None:
    path = Path(spec)
    if path.suffix == ".glsl":
        if not path.is_file():
            raise ValidateError(f"{spec}: plugin file not found")
        from ..local_models.glsl_technique import load_glsl

        load_glsl(spec)  # compile/link errors: "<file>:<line>: <driver message>"
        return
    try:
        if path.suffix == ".py":
            if not path.is_file():
                raise ValidateError(f"{spec}: plugin file not found")
            mod_spec = importlib.util.spec_from_file_location(f"validate_plugin_{path.stem}", path)
            assert mod_spec and mod_spec.loader
            module = importlib.util.module_from_spec(mod_spec)
            mod_spec.loader.exec_module(module)
        else:
            module = importlib.import_module(spec)
        from ..local_models.render import registry

        registry.register_module(module)
    except ValidateError:
        raise
    except Exception as exc:
        raise ValidateError(f"{spec}: plugin failed to load ({type(exc).__name__}: {exc})") from None
