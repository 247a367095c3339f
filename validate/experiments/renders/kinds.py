"""Scene kinds of ``renders`` as objects: what a kind of scene is judged against, with which budget, power references
and engines.

A :class:`SceneKind` carries

* ``needs`` — the scene features an engine must render (``"environment"``, ``"rect"`` …): an engine whose
  ``lacks`` names one is skipped with that reason (:meth:`validate.local_models.render.engine.Engine.skip_reason`);
* ``references`` — the Mitsuba references traced for a scene of the kind (reference name → render, None for the
  closed-form furnace 1), at the settings' sample counts;
* ``budget`` — the per-pixel budget b(mean) of the judgement and its text;
* ``power`` — the references of its power checks (the spot: each profile with the outer cone 1° wider).

The engines rendering a kind are the settings' engines plus the registered variants that name the kind in their
``with_kinds`` (:func:`engine_names`). :data:`KINDS` maps the name a scene list or an exported manifest uses to its
kind; :func:`kind_of` looks one up.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from ...errors import ValidateError
from ...local_models.render import registry
from ...local_models.render.engine import Engine
from ...reference.render_reference import RenderReference, render_reference
from ...scenes import render_scenes as rs
from .budgets import DIRECT_BUDGET_OF_PEAK, FURNACE_BUDGET, PROBE_BUDGET_REL
from .settings import FULL, Settings

SPOT_CONE_OFFSET_DEG = 1.0  # power: a cone falloff off by 1° (the outer angle 30° → 31°)

Budget = tuple["np.ndarray | float", str]
References = dict[str, "RenderReference | None"]


def furnace_budget(mean: np.ndarray) -> Budget:
    return FURNACE_BUDGET, f"{FURNACE_BUDGET:.2e} (2 half-float lookups 2·2⁻¹¹ + SwiftShader trig 2e-4)"


def probe_budget(mean: np.ndarray) -> Budget:
    return PROBE_BUDGET_REL * mean, f"{PROBE_BUDGET_REL:.2e} × the reference (the furnace budget per unit radiance)"


def peak_budget(mean: np.ndarray) -> Budget:
    """The directional margin (:data:`~.budgets.DIRECT_BUDGET_OF_PEAK`): the same per-fragment Lambert shading of a
    tessellated sphere (on the plane, where interpolated positions and normals are exact, the margin is generous)."""
    peak = float(np.nanmax(mean))
    return DIRECT_BUDGET_OF_PEAK * peak, f"{DIRECT_BUDGET_OF_PEAK:.2%} of the peak radiance (measured margin)"


def _traced(samples: str) -> Callable[[rs.RenderScene, Settings], References]:
    """One reference ``mitsuba``: the scene itself at the settings' ``samples`` (an attribute name) per pass."""
    def refs(scene: rs.RenderScene, s: Settings) -> References:
        return {"mitsuba": render_reference(scene, getattr(s, samples), s.passes, s.seed)}
    return refs


def _furnace(scene: rs.RenderScene, s: Settings) -> References:
    """``energy``: the closed-form 1; ``model`` (metal only): glTF's single-scattering metal."""
    refs: References = {"energy": None}
    if scene.material.metallic == 1.0:
        refs["model"] = render_reference(scene, s.spp, s.passes, s.seed)
    return refs


def _furnace_material(scene: rs.RenderScene, s: Settings) -> References:
    return {"energy": None, "gltf": render_reference(scene, s.spp, s.passes, s.seed)}


def _spot(scene: rs.RenderScene, s: Settings) -> References:
    r = scene.resolution
    return {"mitsuba": render_reference(rs.spot_scene(r), s.spp, s.passes, s.seed),
            "smoothstep": render_reference(rs.spot_scene(r, "smoothstep"), s.spp, s.passes, s.seed)}


def _spot_power(scene: rs.RenderScene, s: Settings) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each profile's reference with the outer cone ``SPOT_CONE_OFFSET_DEG`` wider (a power check)."""
    out = {}
    for profile in rs.SPOT_PROFILES:
        r = render_reference(rs.spot_scene(scene.resolution, profile, SPOT_CONE_OFFSET_DEG), s.spp, s.passes, s.seed)
        out[f"{profile} outer +{SPOT_CONE_OFFSET_DEG:g}°"] = (r.mean, r.stderr)
    return out


# ---------------------------------------------------------------- (b) glTF materials: references (i) and (ii)
# Scenes "probe_material": white spheres (baseColor 1) over ``material_metallic`` × ``material_roughness`` under the
# probe. References, kept apart: "gltf" = (i) glTF 2.0 Appendix B as specified (validate.reference.gltf_bsdf, any
# metalness); "multiscatter" = (ii) the random-walk microsurface (validate.reference.microsurface_bsdf) — at metalness
# 1 the walk itself, at metalness m in (0, 1) glTF's linear mix (B.2.1) with the metal lobe replaced by the walk,
# (1 − m)·(i)(m = 0) + m·(ii)(m = 1): the dielectric's F₀ = 0.04 layer keeps its single scattering.
MATERIAL_REFERENCES = {"gltf": "vs (i) glTF as specified", "multiscatter": "vs (ii) multiscatter microsurface"}


def _with_model(scene: rs.RenderScene, metallic: float, model: str) -> rs.RenderScene:
    mat = replace(scene.material, metallic=metallic, model=model)
    return replace(scene, name=f"probe_{model}_m{metallic:g}_r{mat.roughness:g}", material=mat)


def material_references(scene: rs.RenderScene, s: Settings) -> References:
    """(i) always; (ii) where the metal lobe is present (block comment above)."""
    out: References = {"gltf": render_reference(scene, s.probe_spp, s.passes, s.seed)}
    m = scene.material.metallic
    if m == 0.0:
        return out
    walk = render_reference(_with_model(scene, 1.0, "multiscatter"), s.probe_spp, s.passes, s.seed)
    if m == 1.0:
        out["multiscatter"] = walk
        return out
    diel = render_reference(_with_model(scene, 0.0, "gltf"), s.probe_spp, s.passes, s.seed)
    out["multiscatter"] = RenderReference((1 - m) * diel.mean + m * walk.mean,
                                          np.sqrt(((1 - m) * diel.stderr) ** 2 + (m * walk.stderr) ** 2), walk.hit,
                                          walk.spp, walk.passes, walk.seed)
    return out


def _no_power(scene: rs.RenderScene, s: Settings) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    return {}


@dataclass(frozen=True)
class SceneKind:
    """One kind of scene (module docstring)."""

    name: str
    needs: tuple[str, ...]
    references: Callable[[rs.RenderScene, Settings], References] = field(repr=False)
    budget: Callable[[np.ndarray], Budget] = field(repr=False)
    power: Callable[[rs.RenderScene, Settings], dict[str, tuple[np.ndarray, np.ndarray]]] = field(
        default=_no_power, repr=False)

    def __str__(self) -> str:
        return self.name


# (a) furnace; (c) directional, point, spot; (f) hemisphere; (b) probe (metal spheres, the Lambertian limit: the
# hemisphere's sample count, its power check needs ~1 %) and the glTF materials; (d) the rectangular area light (an
# area emitter: next-event estimation on the rectangle, Monte Carlo noise)
FURNACE = SceneKind("furnace", ("furnace",), _furnace, furnace_budget)
FURNACE_MATERIAL = SceneKind("furnace_material", ("furnace",), _furnace_material, furnace_budget)
DIRECTIONAL = SceneKind("directional", ("directional",), _traced("spp"), peak_budget)
POINT = SceneKind("point", ("point",), _traced("spp"), peak_budget)
SPOT = SceneKind("spot", ("spot",), _spot, peak_budget, _spot_power)
HEMISPHERE = SceneKind("hemisphere", ("hemisphere",), _traced("env_spp"), peak_budget)
PROBE = SceneKind("probe", ("environment",), _traced("probe_spp"), probe_budget)
PROBE_LAMBERT = SceneKind("probe_lambert", ("environment",), _traced("env_spp"), peak_budget)
PROBE_MATERIAL = SceneKind("probe_material", ("environment",), material_references, probe_budget)
RECT = SceneKind("rect", ("rect",), _traced("env_spp"), peak_budget)
KINDS = {k.name: k for k in (FURNACE, FURNACE_MATERIAL, DIRECTIONAL, POINT, SPOT, HEMISPHERE, PROBE, PROBE_LAMBERT,
                             PROBE_MATERIAL, RECT)}


def kind_of(kind: SceneKind | str) -> SceneKind:
    """The kind itself, or the kind of that name (a manifest's ``kind``); one line naming the known ones else."""
    if isinstance(kind, SceneKind):
        return kind
    try:
        return KINDS[kind]
    except KeyError:
        raise ValidateError(f"scene kind {kind!r}: not one of {', '.join(KINDS)}") from None


def run_engines(s: Settings) -> tuple[str, ...]:
    """The engines a run renders: the settings' ``engines``, then every other registered engine that renders in this
    process and is not a variant — one the settings of ``FULL`` do not name (an engine added since), so a new engine
    module is judged with no edit elsewhere."""
    named = set(FULL.engines) | set(s.engines)
    extra = [e.name for e in registry.main_engines() if e.name not in named and renders_in_process(e)]
    return (*s.engines, *extra)


def renders_in_process(engine: Engine) -> bool:
    """The engine implements :meth:`~validate.local_models.render.engine.Engine.render` (not only scene files)."""
    return type(engine).render is not Engine.render


def engine_names(kind: SceneKind | str, s: Settings) -> list[str]:
    """The run's engines (:func:`run_engines`), each followed by its registered variants that render this kind
    (``with_kinds``)."""
    k = kind_of(kind).name
    variants = [e for e in registry.engines().values() if k in e.with_kinds]
    return [n for e in run_engines(s) for n in (e, *(v.name for v in variants if v.variant_of == e))]


__all__ = ["SceneKind", "KINDS", "kind_of", "engine_names", "run_engines", "renders_in_process", "furnace_budget",
           "probe_budget", "peak_budget", "material_references", "MATERIAL_REFERENCES", "SPOT_CONE_OFFSET_DEG",
           "FURNACE", "FURNACE_MATERIAL", "DIRECTIONAL", "POINT", "SPOT", "HEMISPHERE", "PROBE", "PROBE_LAMBERT",
           "PROBE_MATERIAL", "RECT"]
