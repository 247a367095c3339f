"""``validate.testing.check_arealight``: a technique against the exact cap irradiance on the experiment's scenes."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models import arealight
from ...local_models.registry import Technique
from ..techniques import CheckResult, Stat
from .compute import ALPHA20, measure_techniques, scene_table, supports


def check_arealight(fn: Callable[..., Any] | str, scenes: Sequence[str] | None = None,
                    shapes: Sequence[str] = ("sphere", "disc"), name: str = "candidate",
                    theta_step_deg: float = 0.25) -> CheckResult:
    """Measure an area-light technique (a function of the ``arealight`` contract, or a registered name)
    against the exact cap irradiance on the experiment's scenes (default: all three, those of ``shapes``).

    Returns a :class:`CheckResult` with, per scene, ``flux`` (|E′ − E| / Φ) and ``peak`` (|E′ − E| / E(0)) as
    mean and max over θ ∈ [0°, 180°] ± the closed form's tolerance; e.g. ``r.flux.max < 0.05``."""
    if isinstance(fn, Technique) or isinstance(fn, str):
        tech = fn if isinstance(fn, Technique) else arealight[fn]
    elif callable(fn):
        tech = Technique(name, "arealight", fn, name, meta={"shapes": tuple(shapes)})
    else:
        raise ValidateError(f"check_arealight: {fn!r} is not callable, a Technique or a registered name")
    table = scene_table(ALPHA20)
    chosen = {k: v for k, v in table.items() if (scenes is None or k in scenes) and supports(tech, v["shape"])}
    th = np.arange(0.0, 180.0 + 1e-9, theta_step_deg)
    per = measure_techniques(chosen, {}, th, [tech])[tech.name]
    return CheckResult(tech.name, "arealight", {
        sc: {metric: Stat(v[f"{metric}.mean"], v[f"{metric}.max"], v[f"{metric}.uncertainty"],
                          v[f"{metric}.uncertainty"]) for metric in ("flux", "peak")} for sc, v in per.items()})


__all__ = ["check_arealight"]
