"""Local lighting models: one small drjit module per technique, registered by name in its family.

Families (:mod:`.families`): ``irradiance``, ``specular``, ``arealight``, ``shadow``; later families
define themselves the same way (:func:`.registry.define_family`). To compare your own technique,
write one function in one file and register it with its family's decorator::

    import numpy as np
    from validate.local_models import irradiance

    @irradiance.register("my_sh4", "SH up to l = 4",
                         thresholds={"flux_luminance.max": 0.05}, source="R&H 2001 §4: max < 5 % of Φ")
    def my_sh4(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
        ...  # radiance: (H, W, 3) lat-long in Mitsuba's convention; normals: (N, 3) unit, y-up
        return E  # (N, 3) irradiance

then ``python -m validate all --plugin my_module.py``: every experiment of the family gives it a row
in its comparison tables, ``results.json`` entries at ``experiments.<exp>.techniques.my_sh4`` and one
claim per declared threshold. Built-ins register exactly this way: every module of this package is
imported at start-up and registers its own techniques.
"""

from __future__ import annotations

import importlib
import pkgutil

from .families import arealight, irradiance, shadow, specular
from .registry import FAMILIES, Family, Technique, define_family, family, find_technique

_NOT_TECHNIQUES = {"registry", "families"}


def register_irradiance_model(name: str, description: str = "", **kwargs):  # noqa: ANN201 (decorator)
    """Shorthand for ``irradiance.register`` (the original plug-in API)."""
    return irradiance.register(name, description, **kwargs)


def load_builtins() -> None:
    """Import every module (and sub-package) of this package: each registers its own built-ins, so a new
    built-in technique is one new file here and nothing else."""
    for mod in pkgutil.iter_modules(__path__):
        if mod.name not in _NOT_TECHNIQUES and not mod.name.startswith("_"):
            importlib.import_module(f"{__name__}.{mod.name}")
    from .glsl_technique import register_builtins  # glsl/*.glsl, after the Python built-ins they transcribe

    register_builtins()


load_builtins()

__all__ = ["FAMILIES", "Family", "Technique", "arealight", "define_family", "family", "find_technique",
           "irradiance", "register_irradiance_model", "shadow", "specular"]
