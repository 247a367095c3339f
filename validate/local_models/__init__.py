"""Local lighting models (one small drjit module per technique) and the plug-in registry.

To compare your own approximation, write one function and register it::

    import numpy as np
    from validate.local_models import register_irradiance_model

    @register_irradiance_model("my_sh4", description="SH up to l = 4")
    def my_sh4(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
        ...  # radiance: (H, W, 3) lat-long in Mitsuba's convention; normals: (N, 3) unit, y-up
        return irradiance  # (N, 3)

then run ``python -m validate run sh9 --plugin my_module.py`` (or import it before calling
:func:`validate.experiments.run_experiment`): every registered model gets a row in the report's
model comparison and an entry in ``results.json`` with no edits elsewhere.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

IrradianceFn = Callable[[np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class IrradianceModel:
    name: str
    fn: IrradianceFn
    description: str
    builtin: bool = False


IRRADIANCE_MODELS: dict[str, IrradianceModel] = {}


def register_irradiance_model(name: str, description: str = "", builtin: bool = False
                              ) -> Callable[[IrradianceFn], IrradianceFn]:
    """Decorator: register ``fn(radiance (H,W,3), normals (N,3)) -> irradiance (N,3)``."""
    def deco(fn: IrradianceFn) -> IrradianceFn:
        IRRADIANCE_MODELS[name] = IrradianceModel(name, fn, description or (fn.__doc__ or "").strip()
                                                  .split("\n")[0], builtin)
        return fn
    return deco


def _register_builtins() -> None:
    from . import sh

    @register_irradiance_model("sh9", "SH order 2 (9 coeffs), R&H 2001 quadratic form", builtin=True)
    def sh9(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
        return sh.render_irradiance_rh2001(sh.project_environment(radiance, 2), normals)

    @register_irradiance_model("sh1", "SH order 1 (4 coeffs, 'ambient + directional')", builtin=True)
    def sh1(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
        return sh.render_irradiance(sh.project_environment(radiance, 1), normals)

    @register_irradiance_model("sh4", "SH order 4 (25 coeffs)", builtin=True)
    def sh4(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
        return sh.render_irradiance(sh.project_environment(radiance, 4), normals)


_register_builtins()
