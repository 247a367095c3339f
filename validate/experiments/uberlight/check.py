"""``validate.testing.check_uberlight``: one überlight function against the projector and the barn doors."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from ...local_models import uberlight as family
from ...local_models.registry import Technique
from ..base import Context
from ..techniques import CheckResult, Stat
from .compute import (
    INTENSITY,
    PROJECTOR_SHAPE,
    barndoor_frames,
    config_key,
    fit_beam,
    fore_june_extra,
    light_mapping,
    projector_errors,
    projector_frame,
)
from .settings import FULL, QUICK


def check_uberlight(fn: Callable[..., Any] | Technique, *, quick: bool = True, name: str | None = None
                    ) -> CheckResult:
    """Measure one überlight function (the ``uberlight`` family's contract; need not be registered).

    ``fn(light, points, normals, views, material, shadow=None) -> (N,)``. Returns a :class:`CheckResult` with
    ``projector``: metric ``projector`` (mean = mean_rel, max = max_rel of |L − L_ref|/peak against Mitsuba's
    projector carrying the mask, edge widths 0, 1/d² expected) and, per barn-door size ``barndoor_r<r>``, metric
    ``barndoor`` (RMS of (L − L_ref)/peak with the least-squares überlight shape of that luminaire; mean = max),
    each ± the reference's uncertainty. Example: ``assert check_uberlight(my_light).projector.max < 1e-5``.
    """
    tech = fn if isinstance(fn, Technique) else Technique(name or getattr(fn, "__name__", "technique"), "uberlight",
                                                          fn, "checked by validate.testing")
    s = QUICK if quick else FULL
    frame, keep = projector_frame(s, PROJECTOR_SHAPE)
    light = light_mapping(frame.scene.luminaire, INTENSITY, PROJECTOR_SHAPE, **fore_june_extra(s))
    e = projector_errors(frame, family.call(tech, light, frame.position, frame.normal, frame.views,
                                               frame.material(), shadow=frame.shadow), keep)
    out = {"projector": {"projector": Stat(e["mean_rel"], e["max_rel"], e["uncertainty"], e["uncertainty"])}}
    for f in barndoor_frames(Context(out_dir=Path("."), quick=quick, show_progress=False), s):
        fit = fit_beam(f)
        lmap = light_mapping(f.scene.luminaire, fit["intensity"], fit["shape"],
                                **{"d0": 0.5, "alpha": 2.0, "max_intensity": fit["intensity"] * 16.0})
        d = (family.call(tech, lmap, f.position, f.normal, f.views, f.material(), shadow=f.shadow) - f.radiance)
        val = math.sqrt(max(float(np.mean((d / f.peak) ** 2) - np.mean((f.uncertainty / f.peak) ** 2)), 0.0))
        unc = math.sqrt(val * val + float(np.std((d / f.peak) ** 2, ddof=1) / math.sqrt(len(d)))) - val
        out[f"barndoor_{config_key(f.scene)}"] = {"barndoor": Stat(val, val, unc, unc)}
    return CheckResult(tech.name, "uberlight", out)


__all__ = ["check_uberlight"]
