"""Local lighting models: one small module per technique (numpy or drjit), registered by name in its family.

Families (all defined in :mod:`.families`): ``irradiance``, ``specular``, ``arealight``, ``shadow``, ``brdf``,
``light``, ``specular_arealight``, ``uberlight``; a plug-in may define another with
:func:`.registry.define_family`. To compare your own technique, write one function in one file and register it
with its family's decorator::

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

Layout: one folder per family (``irradiance/``, ``specular/``, ``arealight/``, ``shadow/``, ``brdf/``,
``light/``, ``specular_arealight/``, ``uberlight/``), one file per technique, the family's shared code in
modules of the folder that register nothing; every family is defined in :mod:`.families`. Each folder's
package stands for its family (``from validate.local_models import irradiance`` then ``irradiance.register``)
and imports its own modules, so a new built-in is one new file in its family's folder and nothing else.
"""

from __future__ import annotations

import importlib

from . import families
from .registry import FAMILIES, Family, Technique, define_family, family, find_technique


def register_irradiance_model(name: str, description: str = "", **kwargs):  # noqa: ANN201 (decorator)
    """Shorthand for ``irradiance.register`` (the original plug-in API)."""
    return irradiance.register(name, description, **kwargs)


def load_builtins() -> None:
    """Import every family folder, in :data:`.families.__all__` order (each imports its technique files),
    then the GLSL built-ins (``<family>/*.glsl``), which
    register after the Python techniques they transcribe so every family keeps its order."""
    for name in families.__all__:
        importlib.import_module(f"{__name__}.{name}")
    importlib.import_module(f"{__name__}.glsl_technique").register_builtins()


load_builtins()

from . import (  # noqa: E402 (the family packages, loaded just above)
    arealight,
    brdf,
    irradiance,
    light,
    shadow,
    specular,
    specular_arealight,
    uberlight,
)
from .irradiance import sh  # noqa: E402 (the SH toolkit of the plug-in API: `from validate.local_models import sh`)

__all__ = ["FAMILIES", "Family", "Technique", "arealight", "brdf", "define_family", "family", "find_technique",
           "irradiance", "light", "register_irradiance_model", "sh", "shadow", "specular", "specular_arealight",
           "uberlight"]
