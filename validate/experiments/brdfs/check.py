"""Experiment ``brdfs``: the textbooks' shading models (Phong, Blinn–Phong, Cook–Torrance, Oren–Nayar, Minnaert,
Lambert) against physics.

Techniques: the ``brdf`` family (:mod:`validate.local_models.classic_brdfs`; contract: cosine-weighted BRDF
q = f_r(l, v)·max(0, n·l)). Every registered technique is measured on every material.

References
  * Mitsuba's BSDFs evaluated directly (:func:`validate.reference.brdf_render.eval_bsdf`):
    ``roughconductor`` Beckmann and GGX (coloured conductor, mirror F = 1, dielectric interface),
    ``diffuse``, and the suite's normalised modified Phong (:mod:`validate.reference.ibl_render`);
  * geometry, not a formula, for the rough diffuse models: a Lambertian V-groove microsurface path-traced
    with inter-reflections (:func:`validate.reference.brdf_render.vgroove_brdf`).

Metrics (:mod:`.brdfs_measure`): ``rel_l1.<material>``, ``max_rel.<material>``, ``albedo_error.<material>``,
each ± uncertainty, with the power perturbation "output × 1.02".

Pipeline: :func:`compute` → :func:`.brdfs_claims.claims` / :func:`.brdfs_claims.findings` →
:func:`.brdfs_report.sections`; :func:`run` wires them.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import partial
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models import family
from ...local_models.registry import Technique
from . import claims as bc
from . import compute as bm
from . import report as rep
from ..base import Context, ExperimentResult, register_experiment
from ..techniques import CheckResult, Stat, technique_entry

NAME = bc.NAME
LIGHT_DIR = (0.5, 0.6, 0.62)  # the sphere images' light direction (world, viewer at +z)


def compute(ctx: Context, s: bm.Settings | None = None) -> bm.Measurements:
    """Every technique on every Mitsuba material (grid and furnace), the term-by-term Cook–Torrance path,
    the energy sweep, the V-groove surfaces and the sphere images."""
    s = s or (bm.QUICK if ctx.quick else bm.FULL)
    m = bm.Measurements(s, list(family("brdf")))
    mats = bm.materials(s)
    m.materials = [x.name for x in mats]
    for metrics, furnace in ctx.map(partial(_material_metrics, s, m.techniques), mats, "brdfs: Mitsuba materials"):
        for name, values in metrics.items():  # tasks return their numbers (they may run on Dask workers)
            m.metrics.setdefault(name, {}).update(values)
        m.furnace.update(furnace)
    bm.term_analysis(m, mats)
    bm.energy_sweep(m)
    bm.vgroove_metrics(m, ctx.seed)
    bm.gouraud_analysis(m, LIGHT_DIR)
    bm.env_analysis(m, mats)
    bm.plane_analysis(m, mats)
    for mat in mats[:1] + [x for x in mats if x.name.startswith("diffuse")]:
        m.images[mat.name] = bm.sphere_images(m, mat, LIGHT_DIR)
    return m


def _material_metrics(s: bm.Settings, techniques: list[Technique], mat: Any) -> tuple[dict, dict]:
    """One material's grid and furnace metrics of every technique (a task: returns, never mutates)."""
    scratch = bm.Measurements(s, techniques)
    bm.grid_metrics(scratch, mat)
    bm.furnace_metrics(scratch, mat)
    return scratch.metrics, scratch.furnace


def entries(m: bm.Measurements) -> dict[str, Any]:
    return {t.name: technique_entry(t, {k: {"value": v["value"], "uncertainty": v["uncertainty"]}
                                        for k, v in m.metrics.get(t.name, {}).items()}) for t in m.techniques}


def data(m: bm.Measurements) -> dict[str, Any]:
    """The JSON-able numbers (no images)."""
    return {"materials": m.materials, "furnace": m.furnace, "energy_sweep": m.sweep, "cook_torrance_terms": m.terms,
            "gouraud": m.gouraud, "plane_highlight_elongation": m.plane.get("elongation", {}),
            "environment": {k: {"reference_noise": v["reference_noise"]} for k, v in m.env.items()},
            "vgroove": {k: {kk: vv for kk, vv in v.items() if kk != "techniques"}
                        for k, v in m.vgroove.get("sigmas", {}).items()}}


@register_experiment(NAME, "Textbook shading models vs physics (Phong, Blinn–Phong, Cook–Torrance, Oren–Nayar, "
                     "Minnaert)", "every brdf technique vs Mitsuba BSDFs and path-traced V-grooves", order=70)
def run(ctx: Context) -> ExperimentResult:
    m = compute(ctx)
    s = m.settings
    return ExperimentResult(
        name=NAME, title="Textbook shading models vs physics",
        summary=("Every registered brdf technique — textbook Phong and Blinn–Phong, their normalised forms, "
                 "Cook–Torrance as Ganovelli prints it and in the corrected microfacet form, Oren–Nayar "
                 "(qualitative and full), Minnaert, Lambert — against Mitsuba's BSDFs evaluated directly, and the "
                 "rough diffuse models against "
                 "a path-traced Lambertian V-groove surface; white-furnace albedo of each."),
        claims=bc.claims(m), findings=bc.findings(m), sections=rep.sections(m, ctx), data=data(m),
        settings={k: (list(v) if isinstance(v, tuple) else v) for k, v in vars(s).items()},
        techniques=entries(m))


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
    s = bm.QUICK if quick else bm.FULL
    m = bm.Measurements(s, [tech])
    mats = {x.name: x for x in bm.materials(s)}
    wanted = list(materials) if materials is not None else list(mats)
    vgroove = [w for w in wanted if w.startswith("vgroove_")]
    unknown = [w for w in wanted if w not in mats and w not in {f"vgroove_s{x:g}" for x in s.sigmas_deg}]
    if unknown:
        raise ValidateError(f"check_brdf: unknown material(s) {', '.join(unknown)}; available: "
                            f"{', '.join(list(mats) + [f'vgroove_s{x:g}' for x in s.sigmas_deg])}")
    for w in wanted:
        if w in mats:
            bm.grid_metrics(m, mats[w])
            bm.furnace_metrics(m, mats[w])
    if vgroove:
        bm.vgroove_metrics(m, seed)
    out: dict[str, dict[str, Stat]] = {}
    for key, v in m.metrics.get(tech.name, {}).items():
        metric, _, mat = key.partition(".")
        if mat in wanted:
            out.setdefault(mat, {})[metric] = Stat(v["value"], v["value"], v["uncertainty"], v["uncertainty"])
    return CheckResult(tech.name, "brdf", out)


__all__ = ["NAME", "check_brdf", "compute", "run"]
