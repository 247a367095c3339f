"""``validate.testing.check_brdf``: one ``brdf`` function on this experiment's materials."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ...errors import ValidateError
from ...local_models.registry import Technique
from ..techniques import CheckResult, Stat
from .compute import Measurements, furnace_metrics, grid_metrics, vgroove_metrics
from .compute import materials as experiment_materials
from .settings import FULL, QUICK


def check_brdf(fn: Callable[..., np.ndarray] | Technique, materials: Sequence[str] | None = None, *,
               quick: bool = True, seed: int = 1234, name: str | None = None) -> CheckResult:
    """Measure one ``brdf`` function (need not be registered) on this experiment's materials.

    ``fn(params, normals, lights, views) -> (N, 3)`` cosine-weighted BRDF; ``materials`` names among the Mitsuba
    materials (e.g. ``conductor_beckmann_a0.2``, ``conductor_ggx_a0.3``, ``mirror_beckmann_a0.2``,
    ``dielectric_beckmann_a0.3``, ``diffuse_r0.8``, ``modphong_s20``) and the V-groove surfaces
    (``vgroove_s2``, ``vgroove_s20``, ``vgroove_s40``); default: every Mitsuba material. Returns a
    :class:`CheckResult` keyed by material with the metrics ``rel_l1``, ``max_rel`` and ``albedo_error`` (Mitsuba
    materials) or ``rel_l1`` (V-grooves); mean = max = the value, ± its uncertainty. Example:
    ``assert check_brdf(my_ggx, ["conductor_ggx_a0.3"]).max_rel.max < 1e-3``."""
    tech = fn if isinstance(fn, Technique) else Technique(name or getattr(fn, "__name__", "technique"), "brdf", fn,
                                                          "checked by validate.testing")
    s = QUICK if quick else FULL
    m = Measurements(s, [tech])
    mats = {x.name: x for x in experiment_materials(s)}
    wanted = list(materials) if materials is not None else list(mats)
    vgroove = [w for w in wanted if w.startswith("vgroove_")]
    unknown = [w for w in wanted if w not in mats and w not in {f"vgroove_s{x:g}" for x in s.sigmas_deg}]
    if unknown:
        raise ValidateError(f"check_brdf: unknown material(s) {', '.join(unknown)}; available: "
                            f"{', '.join(list(mats) + [f'vgroove_s{x:g}' for x in s.sigmas_deg])}")
    for w in wanted:
        if w in mats:
            grid_metrics(m, mats[w])
            furnace_metrics(m, mats[w])
    if vgroove:
        vgroove_metrics(m, seed)
    out: dict[str, dict[str, Stat]] = {}
    for key, v in m.metrics.get(tech.name, {}).items():
        metric, _, mat = key.partition(".")
        if mat in wanted:
            out.setdefault(mat, {})[metric] = Stat(v["value"], v["value"], v["uncertainty"], v["uncertainty"])
    return CheckResult(tech.name, "brdf", out)


__all__ = ["check_brdf"]
