"""Experiment ``shadows``: every registered shadow technique against Mitsuba's soft shadows of a disc light.

Scene (:mod:`validate.scenes.shadow_scenes`): a ground plane with a floating sphere, a box, a thin
pole and a self-shadowing staircase, lit by a one-sided disc light of radius r (0.02 m, a near-point
light, up to 1 m) 4 m up, with the radiance scaled so that the on-axis irradiance is the same for
every r. Direct lighting only.

Reference (:mod:`validate.reference.shadow_render`): Mitsuba's ``direct`` integrator at the pixel
centres, P independent passes → mean ± standard error per pixel; the G-buffer (position, normal,
albedo) from the ``aov`` integrator; the visible fraction V of the disc per pixel (stratified shadow
rays), which splits the image into lit (V = 1), penumbra and umbra (V = 0).

Techniques: the ``shadow`` family (:mod:`validate.local_models.families`); built-ins ``hard``,
``pcf`` (3×3) and ``pcss`` register in :mod:`validate.local_models.shadow_map`, and a plug-in is one
file with ``@shadow.register``. Each is called as ``shadow.call(tech, shadow_map, light, points,
normals)`` and shaded as ρ/π · E_disc · V′ (E_disc the closed-form unoccluded irradiance). The light's
centre and direction do not change with r, so one shadow map per resolution serves every radius.

Metrics (:mod:`validate.metrics.shadow_error`): |ΔY| / L_norm per pixel (L_norm = mean lit reference
luminance), averaged over the image and per region, false-shadow (acne) and false-light
(peter-panning) areas, light leak, HDR-FLIP — each ± its uncertainty.

Pipeline: :func:`compute` (numbers, :mod:`.shadows_measure`) → :func:`claims` and :func:`findings`
(:mod:`.shadows_claims`) → :func:`sections` (:mod:`.shadows_report`); :func:`run` only wires them.
:func:`check_shadow` measures one function for :mod:`validate.testing`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models import shadow
from ...local_models import shadow_map as smod
from ...local_models.registry import Technique
from ...reference import shadow_render as sr
from . import claims as sc
from . import report as rep
from ..base import Claim, Context, ExperimentResult, Section, register_experiment
from .compute import (
    FULL,
    QUICK,
    Measurements,
    Settings,
    band_test,
    bias_sweep,
    bleeding_case,
    build_frame,
    evaluate,
    fit_rate,
    ground_grid,
    kernel_sweep,
    measure_resolution,
    rate_counts,
    upper_bounds,
)
from ..techniques import CheckResult, Stat, technique_entry

NAME = sc.NAME


def compute(ctx: Context, s: Settings | None = None) -> Measurements:
    """References, every technique at every resolution and radius, the sweeps and the convergence counts."""
    s = s or (QUICK if ctx.quick else FULL)
    for what in (s.default_resolution, s.bias_resolution, s.kernel_resolution):
        if what not in s.resolutions:
            raise ValidateError(f"shadows settings: resolution {what} is not in the sweep {s.resolutions}")
    frame = build_frame(s, s.radii, ctx.seed, lambda it: ctx.progress(it, "shadows: references"))
    m = Measurements(s, frame, list(shadow))
    light = frame.scenes[m.r_pt].light
    geometry = sr.load_scene(frame.scenes[m.r_pt], with_light=False)
    grid_p, grid_n = ground_grid(frame, s.rate_grid)
    exact = sr.point_visibility(geometry, np.array(light.centre), grid_p, grid_n)
    counts: dict[int, int] = {}
    for res in ctx.progress(sorted(s.resolutions), "shadows: shadow-map resolutions"):
        sm = smod.build_shadow_map(geometry, light, frame.position, res)
        m.build_seconds[res] = round(sm.build_seconds, 3)
        measure_resolution(m, sm)
        if "hard" in shadow:
            counts[res] = rate_counts(sm, light, grid_p, grid_n, exact)
        if res == s.bias_resolution:
            m.bias = bias_sweep(sm, frame, m.r_pt, s.bias_scales)
        if res == s.kernel_resolution:
            m.kernels = kernel_sweep(sm, frame, tuple(r for r in s.kernel_radii if r in frame.refs), s.kernels)
        if res == s.default_resolution:
            flat = smod.visibility_pcss(sm, frame.position, frame.normal, m.r_max, receiver_plane=False)
            m.pcss_flat = evaluate(frame, m.r_max, flat.visibility)[0]
            m.bounds = upper_bounds(sm, frame, m.techniques, m.r_max)
        if res == max(s.resolutions) and "hard" in shadow:
            m.band = band_test(sm, frame, geometry, m.r_pt)
        del sm
    if counts:
        m.rate = _rate(counts, s.rate_grid, int(grid_p.shape[0]))
    m.bleeding = bleeding_case(m.techniques)
    return m


def _rate(counts: dict[int, int], side: int, cells: int) -> dict[str, Any]:
    """The fitted slope of the misclassified area against resolution, and the same fit with the top
    resolution capped at the one below it (a texture-size limit or a mip level off by one: the power check)."""
    ress = sorted(counts)
    k = [counts[q] for q in ress]
    b, b_se = fit_rate(ress, k)
    capped = k[:-1] + [k[-2]] if len(k) > 1 else k
    cb, cb_se = fit_rate(ress, capped)
    return {"resolutions": ress, "counts": k, "grid_side": side, "cells": cells, "slope": b, "stderr": b_se,
            "capped_counts": capped, "capped_slope": cb, "capped_stderr": cb_se}


def claims(m: Measurements) -> list[Claim]:
    """Experiment claims (each with its power check), then every technique's declared thresholds."""
    return sc.claims(m)


def findings(m: Measurements) -> list[str]:
    return sc.findings(m)


def sections(m: Measurements, ctx: Context) -> list[Section]:
    return rep.sections(m, ctx)


def technique_entries(m: Measurements) -> dict[str, Any]:
    """``ExperimentResult.techniques``: every metric of every technique at every radius, ± uncertainty."""
    return {t.name: technique_entry(t, {k: {"value": _finite(v.value), "uncertainty": _finite(v.uncertainty)}
                                        for k, v in sc.technique_metrics(m, t.name).items()},
                                    resolution=m.settings.default_resolution,
                                    memory_bytes_per_texel=t.meta.get("memory_bytes_per_texel"))
            for t in m.techniques}


def _finite(x: float) -> float | None:
    """NaN (an empty region, FLIP not computed at that radius) → None, so results.json stays strict JSON."""
    return float(x) if np.isfinite(x) else None


@register_experiment(NAME, "Shadow maps (hard, PCF, PCSS, plug-ins) vs path-traced soft shadows of a disc light",
                     "every registered shadow technique against Mitsuba's direct lighting, by lit / penumbra / "
                     "umbra region, vs shadow-map resolution and light radius; bias and PCF-kernel sweeps", order=50)
def run(ctx: Context) -> ExperimentResult:
    # wall times are not findings (same inputs → same results.json): they are the experiment's wall_time_s
    m = compute(ctx)
    cl, fi, secs = claims(m), findings(m), sections(m, ctx)
    return ExperimentResult(name=NAME, title="Shadow maps vs path-traced soft shadows (disc light)",
                            summary=rep.summary(m), claims=cl, findings=fi, sections=secs, data=rep.data(m),
                            settings=m.settings.__dict__ | {"techniques": [t.name for t in m.techniques]},
                            techniques=technique_entries(m))


# ---------------------------------------------------------------------------------------------- testing API

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
        out[f"r={r:g}"] = sc.check_stats(frame, r, err, approx)
    return CheckResult(tech.name, "shadow", out)


__all__ = ["NAME", "check_shadow", "claims", "compute", "findings", "run", "sections", "technique_entries"]
