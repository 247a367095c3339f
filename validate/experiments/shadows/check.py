"""``validate.testing.check_shadow``: one shadow function on this experiment's scene."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models import shadow
from ...local_models.registry import Technique
from ...local_models.shadow import shadow_map as smod
from ...metrics import shadow_error as se
from ...reference import shadow_render as sr
from ...scenes.latlong import luminance
from ..techniques import CheckResult, Stat
from .claims import error_metrics
from .compute import (
    Frame,
    build_frame,
    evaluate,
)
from .settings import FULL, QUICK


def check_shadow(fn: Callable[..., Any] | Technique, radius: float | Iterable[float] = 1.0, *,
                 resolution: int = 1024, quick: bool = True, seed: int = 1234, name: str | None = None
                 ) -> CheckResult:
    """Measure one shadow function (the ``shadow`` family's contract) on this experiment's scene.

    ``fn(shadow_map, light, points, normals) -> (N,)`` visibility in [0, 1] (need not be registered);
    ``radius`` one or several light radii in metres (≤ half the light's 4.6 m distance); ``resolution``
    the shadow map's side. Returns a :class:`CheckResult` keyed ``r=<radius>``, with the metrics
    ``total``, ``lit``, ``penumbra``, ``umbra`` (|ΔY|/L_norm: mean over the region and the worst pixel,
    each ± the reference's uncertainty), ``false_shadow``, ``false_light``, ``leak`` (fractions, ± binomial
    standard error; mean = max) and ``flip``. Example: ``assert check_shadow(my_pcss).penumbra.mean < 0.1``.
    """
    tech = fn if isinstance(fn, Technique) else Technique(name or getattr(fn, "__name__", "technique"), "shadow",
                                                          fn, "checked by validate.testing")
    radii = (float(radius),) if isinstance(radius, (int, float)) else tuple(float(r) for r in radius)
    if not radii:
        raise ValidateError("check_shadow: no light radius given")
    s = QUICK if quick else FULL
    frame = build_frame(s, radii, seed, flip_radii=radii)
    r_pt = min(radii)
    geometry = sr.load_scene(frame.scenes[r_pt], with_light=False)
    sm = smod.build_shadow_map(geometry, frame.scenes[r_pt].light, frame.position, resolution)
    out: dict[str, dict[str, Stat]] = {}
    for r in radii:
        vis = shadow.call(tech, sm, frame.scenes[r].light, frame.position, frame.normal)
        err, approx = evaluate(frame, r, vis, flip=True)
        out[f"r={r:g}"] = check_stats(frame, r, err, approx)
    return CheckResult(tech.name, "shadow", out)


__all__ = ["check_shadow"]


def check_stats(frame: Frame, r: float, err: se.ShadowErrors, approx: np.ndarray) -> dict[str, Stat]:
    """:class:`Stat` per metric for :func:`~validate.experiments.shadows.check_shadow`: regions give the mean
    and the worst pixel (± that pixel's σ/L_norm); fractions and FLIP give mean = max."""
    rad, unc, v_ref = frame.ref(r)
    e = se.pixel_error(rad, approx, frame.norm[r])
    d = luminance(unc) / frame.norm[r]
    masks = {"total": np.ones(e.size, dtype=bool), **se.region_masks(v_ref)}
    out: dict[str, Stat] = {}
    for k, (v, u) in error_metrics(err, frame.flip_noise[r]).items():
        if k in masks and masks[k].any():
            i = int(np.argmax(np.where(masks[k], e, -np.inf)))
            out[k] = Stat(v, float(e[i]), u, float(d[i]))
        elif k not in masks:
            out[k] = Stat(v, v, u, u)
    return out
