"""Numbers only: Mitsuba references and every engine's pixels for scenes (a) furnace, (c) directional, point and
spot, and (f) hemisphere.

Furnace (a): two references, kept apart — ``energy``: a white, non-absorbing surface in a uniform
radiance-1 furnace returns exactly 1 (energy conservation; a convex sphere sees only the furnace), and
``model`` (metal only): Mitsuba's ``roughconductor``, glTF's single-scattering metal exactly
(:func:`validate.scenes.render_scenes.mitsuba_bsdf`), whose own energy loss is the multiscatter deficit.
Directional (c): Mitsuba's ``diffuse`` sphere under a ``directional`` emitter of the same lux.
Point and spot (c): Mitsuba's ``point`` / ``spot`` emitters (candela read as W/sr) on the Lambertian plane and
sphere; the spot's falloff is KHR_lights_punctual's reference formula exactly (``mitsuba``), and, kept apart,
three.js's smoothstep profile (``smoothstep``) — :mod:`validate.scenes.spot_profile`. Power references: the
same spot with its outer cone 1° wider (``SPOT_CONE_OFFSET_DEG``).
Hemisphere (f): Mitsuba's ``envmap`` of radiance sky above / ground below the horizon, path-traced with
``env_spp`` samples per pass (Monte Carlo noise, unlike the delta lights, whose passes are noise free).
Probe (b): ``rs.PROBE_FILE`` of ``--probes`` resampled to ``rs.PROBE_SIZE``; Mitsuba's ``envmap`` on the node lattice
of :func:`validate.scenes.render_scenes.mitsuba_envmap_nodes` (its lookup is the engines' bilinear texture exactly)
lights white metal spheres (reference (i): glTF's single-scattering GGX, ``roughconductor``; ``probe_spp``) and
the Lambertian sphere (``env_spp``). Without the probe file the probe scenes are left out with the reason.
Probe materials (b): white spheres over metalness × roughness, references (i) glTF as specified (the suite's
``gltf_metallic_roughness`` plug-in) and (ii) the multiscatter microsurface, kept apart (block at the end); the glTF
BSDF's own checks (χ², albedo quadrature, roughconductor) in ``Measurements.bsdf_checks``.
Rectangular area light (d): Mitsuba's ``rectangle`` with an ``area`` emitter of radiance = the light's nits, over the
Lambertian plane and sphere (``env_spp``): three.js, and Babylon with the substitution its engine notes (its shader,
Heitz's tables); Filament has no area lights (its engine's ``lacks``).
Each kind's references, budget and power references are its :class:`~.kinds.SceneKind`; an engine is skipped for a
kind needing a feature it lacks; engine images come from :mod:`.images` (cached).
"""

from __future__ import annotations

from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...local_models.render import Unavailable, registry
from ...metrics.pixel_z import PixelJudgement, interior_mask, judge
from ...reference.render_reference import RenderReference, render_reference
from ...scenes import render_scenes as rs
from . import images
from . import kinds as K
from .budgets import DIRECT_BUDGET_OF_PEAK, FURNACE_BUDGET, PROBE_BUDGET_REL
from .cdf.compute import cdf_reference, cdf_scene_list, compute_cdf
from .khronos.compute import compute_khronos
from .kinds import MATERIAL_REFERENCES, SPOT_CONE_OFFSET_DEG, SceneKind, engine_names, kind_of, material_references
from .settings import Settings
from .shadows.compute import compute_shadows, shadow_scene_list


@dataclass
class EngineResult:
    image: np.ndarray  # (R, R, 3) row 0 top
    coverage: np.ndarray
    frame_ms: float
    wall_s: float
    version: str
    judgements: dict[str, PixelJudgement] = field(default_factory=dict)  # reference kind → judgement
    energy: float = float("nan")  # mean radiance over the interior mask
    info: dict[str, Any] = field(default_factory=dict)  # the page's extra report (three: light.power in lm)
    stderr: float = 0.0  # the readback's standard uncertainty per value (Filament's 8-bit canvas), radiance


def with_readback(stderr: np.ndarray, er: EngineResult) -> np.ndarray:
    """The reference's standard error and the engine readback's (quantisation) in quadrature, √(s² + σ_q²)."""
    return np.sqrt(stderr**2 + er.stderr**2)


@dataclass
class SceneResult:
    scene: rs.RenderScene
    kind: SceneKind  # which references, budget and engines (validate.experiments.renders.kinds)
    references: dict[str, np.ndarray]  # kind → (R, R, 3) truth image (NaN off the sphere)
    reference_energy: dict[str, tuple[float, float]]  # kind → mean ± standard error over the mask
    mask: np.ndarray
    stderrs: dict[str, np.ndarray] = field(default_factory=dict)  # kind → (R, R, 3) standard error
    engines: dict[str, EngineResult] = field(default_factory=dict)
    skipped: dict[str, str] = field(default_factory=dict)  # engine → reason
    power_refs: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)  # label → (mean, stderr)
    dof: int = 7

    def __post_init__(self) -> None:
        self.kind = kind_of(self.kind)  # a kind's name (a manifest's, a test's) is looked up


@dataclass
class Measurements:
    settings: Settings
    scenes: list[SceneResult]
    reference_wall_s: float = 0.0
    startup: dict[str, Any] = field(default_factory=dict)
    probe_note: str = ""  # which probe (b) rendered, or why none
    bsdf_checks: dict[str, Any] = field(default_factory=dict)  # (b) materials: the glTF BSDF's χ² and closed forms
    shadows: list[Any] = field(default_factory=list)  # (e) shadows.compute.ShadowSceneResult per scene
    cdf: list[Any] = field(default_factory=list)  # (b) cdf.compute.CdfScene: Babylon's CDF irradiance (PR 16247)
    khronos: Any = None  # khronos.compute.KhronosPart: the glTF Sample Viewer on the exported scene files
    missing: Any = None  # Unavailable: the runtime an engine to render could not run without (npm, Chromium), or None


def scene_list(s: Settings, probe: np.ndarray | None = None) -> list[tuple[rs.RenderScene, SceneKind]]:
    out = [(sc, K.FURNACE) for sc in rs.furnace_scenes(s.resolution, s.furnace_roughness)]
    out += [(rs.lambert_sun_scene(s.resolution, s.sun_lux), K.DIRECTIONAL)]
    out += [(sc, K.SPOT if sc.name.startswith("spot") else K.POINT) for sc in rs.punctual_scenes(s.resolution)]
    out += [(rs.hemisphere_scene(s.resolution), K.HEMISPHERE)]
    out += [(sc, K.RECT) for sc in rs.rect_scenes(s.rect_resolution)]
    if probe is None:
        return out
    out += [(sc, K.PROBE) for sc in rs.probe_scenes(probe, "uffizi", s.probe_resolution, s.probe_roughness, (1.0,))]
    out += [(rs.probe_lambert_scene(probe, "uffizi", s.probe_resolution), K.PROBE_LAMBERT)]
    return out + material_scene_list(s, probe)


def load_probe(ctx: Any) -> tuple[np.ndarray | None, str]:
    """The probe texels (``rs.PROBE_FILE`` of ``ctx.probes_dir`` resampled to ``rs.PROBE_SIZE``) or why not."""
    from ...scenes.loaders import load_environment

    if ctx.probes_dir is None:
        return None, "no --probes directory: the probe scenes (b) are not rendered"
    path = ctx.probes_dir / rs.PROBE_FILE
    if not path.is_file():
        return None, f"{path}: not found: the probe scenes (b) are not rendered"
    return rs.resample_probe(load_environment(path, "latlong", False).radiance), f"{rs.PROBE_FILE} → {rs.PROBE_SIZE}"


def references(scene: rs.RenderScene, kind: SceneKind | str,
               s: Settings) -> tuple[dict[str, RenderReference | None], np.ndarray]:
    """The kind's reference renders (None: the closed-form furnace 1) and the hit mask."""
    from ...reference.render_reference import centre_rays

    _, hit = centre_rays(scene)
    return kind_of(kind).references(scene, s), hit


def truth(ref: RenderReference | None, hit: np.ndarray, passes: int) -> tuple[np.ndarray, np.ndarray, int]:
    if ref is not None:
        return ref.mean, ref.stderr, ref.dof
    one = np.where(hit[..., None], 1.0, np.nan) * np.ones(3)
    return one, np.where(hit[..., None], 0.0, np.nan) * np.ones(3), max(passes - 1, 1)


def budget(kind: SceneKind | str, mean: np.ndarray) -> tuple[np.ndarray | float, str]:
    """The kind's per-pixel budget for a reference of mean ``mean``, and its text."""
    return kind_of(kind).budget(mean)


def power_references(scene: rs.RenderScene, kind: SceneKind | str,
                     s: Settings) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The kind's power references (the spot: each profile with the outer cone ``SPOT_CONE_OFFSET_DEG`` wider)."""
    return kind_of(kind).power(scene, s)


Prepared = tuple[dict[str, "RenderReference | None"], np.ndarray, dict[str, tuple[np.ndarray, np.ndarray]]]


def prepare_references(scene: rs.RenderScene, kind: SceneKind, s: Settings) -> Prepared:
    """The scene's references, hit mask and power references (Mitsuba only: no browser, safe on the reference
    thread of :func:`compute`)."""
    refs, hit = references(scene, kind, s)
    return refs, hit, power_references(scene, kind, s)


def skip_reason(name: str, kind: SceneKind) -> str | None:
    """Why the engine ``name`` does not render the kind (a feature it lacks), or None."""
    e = registry.find(name)
    return e.skip_reason(kind.needs) if e is not None else None


def substitution(name: str, kind: SceneKind) -> str | None:
    """The substitution the engine ``name`` renders the kind with (its ``notes``), or None."""
    e = registry.find(name)
    return next((e.notes[f] for f in kind.needs if f in e.notes), None) if e is not None else None


def measure_scene(scene: rs.RenderScene, kind: SceneKind, s: Settings, prepared: Future | None = None) -> SceneResult:
    """Every engine's render of ``scene`` judged against its references; ``prepared``: a future of
    :func:`prepare_references` (computed meanwhile on another thread), else they are computed here. The engines
    render first, so the browser works while the references are traced."""
    rendered: dict[str, Any] = {}  # engine → its render (EngineRender), or why it was skipped
    for name in engine_names(kind, s):
        why = skip_reason(name, kind)
        if why is not None:
            rendered[name] = why
            continue
        try:
            rendered[name] = images.render(name, scene)
        except Exception as exc:  # an engine that cannot start is skipped with its reason, never a crash
            rendered[name] = " ".join(f"{type(exc).__name__}: {exc}".split())[:300]
    refs, hit, power = prepared.result() if prepared is not None else prepare_references(scene, kind, s)
    truths = {k: truth(r, hit, s.passes) for k, r in refs.items()}
    res = SceneResult(scene, kind, {k: t[0] for k, t in truths.items()}, {}, hit, {k: t[1] for k, t in truths.items()},
                      power_refs=power, dof=max(s.passes - 1, 1))
    for name, er in rendered.items():
        if isinstance(er, str):
            res.skipped[name] = er
            continue
        out = EngineResult(er.image[..., :3].astype(np.float64), er.image[..., 3], er.frame_ms, er.wall_s, er.version,
                           info=er.info, stderr=er.stderr)
        note = substitution(name, kind)
        if note is not None:
            out.info["note"] = note
        mask = interior_mask(hit, out.coverage)
        res.mask = mask
        for k, (m, se, dof) in truths.items():
            b, text = budget(kind, m)
            out.judgements[k] = judge(out.image, m, with_readback(se, out), dof, mask, b, text)
        out.energy = float(out.image[mask].mean())
        res.engines[name] = out
    for k, (m, se, _) in truths.items():
        sel = res.mask
        res.reference_energy[k] = (float(m[sel].mean()), float(np.sqrt((se[sel] ** 2).sum()) / se[sel].size))
    return res


def compute(ctx: Any, s: Settings) -> Measurements:
    """Mitsuba's references on one thread, the engines' pages in this one (the playwright sync API is bound to the
    thread that started the browser): the two overlap, the numbers are those of the serial order (each reference is
    seeded and computed alone on its thread; each engine render is the same page call)."""
    from ...gl import browser_page, runtime

    probe, probe_note = load_probe(ctx)
    scenes = scene_list(s, probe)
    shadow_scenes = shadow_scene_list(s)
    cdf_scenes = cdf_scene_list(ctx, s)
    # the engines with an image not in the cache: only their runtimes are checked and their pages opened
    need = to_render(s, scenes)
    missing = next((u for u in (registry.get(n).unavailable() for n in need if n in registry.engines()) if u), None)
    pool = ThreadPoolExecutor(1, thread_name_prefix="renders-references")
    try:
        prepared = [pool.submit(prepare_references, sc, kind, s) for sc, kind in scenes]
        shadow_refs = [pool.submit(render_reference, sc, s.shadow_spp, s.passes, s.seed) for sc in shadow_scenes]
        bsdf = pool.submit(gltf_bsdf_checks, s)
        cdf_refs = [pool.submit(cdf_reference, sc, s) for sc, _ in cdf_scenes]  # traced while the browser renders
        browser_page.preload([p for n in need if n in registry.engines() for p in registry.get(n).pages()])
        out = [measure_scene(sc, kind, s, f)
               for (sc, kind), f in ctx.progress(list(zip(scenes, prepared, strict=True)), "renders: scenes")]
        shadows = compute_shadows(ctx, s, shadow_refs)
        checks = bsdf.result()
        cdf = compute_cdf(ctx, s, cdf_scenes, cdf_refs)
        khronos = compute_khronos(ctx, s, out, budget)
    except BaseException:  # an error or an interrupt: drop the references not yet started, do not wait for them
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown()
    return Measurements(s, out, startup={"webgl2_s": runtime.startup_seconds("webgl2"), **time_info(out)},
                        probe_note=probe_note, bsdf_checks=checks, shadows=shadows, cdf=cdf, khronos=khronos,
                        missing=missing)


def to_render(s: Settings, scenes: list[tuple[rs.RenderScene, SceneKind]]) -> list[str]:
    """The engines (in the order the scenes meet them) with an image of a main scene not in the cache; the shadow and
    CDF parts' engines are counted when their scenes' images are missing too (their pages are then opened as they
    render)."""
    out: dict[str, None] = {}
    for sc, kind in scenes:
        for n in engine_names(kind, s):
            if n not in out and skip_reason(n, kind) is None and (n not in registry.engines()
                                                                   or images.cached(n, sc) is None):
                out[n] = None
    return list(out)


def time_info(scenes: list[SceneResult]) -> dict[str, Any]:
    t: dict[str, Any] = {}
    for sr in scenes:
        for e, r in sr.engines.items():
            t.setdefault(e, {})[sr.scene.name] = {"frame_ms": r.frame_ms, "wall_s": round(r.wall_s, 3)}
    return t


CONTRAST_DRAWS = 64  # parametric draws of the reference noise for the contrast ratio's uncertainty


def contrast_ratio(image: np.ndarray, mean: np.ndarray, stderr: np.ndarray, mask: np.ndarray,
                   seed: int = 0) -> tuple[float, float]:
    """Sharpness of an engine's reflection against the reference: c = std_px(engine) / std_px(truth) of the
    channel-mean radiance over the judged pixels (> 1: the reflection is crisper than the path tracer's, < 1:
    blurrier — three issues 17911/26796, PR 32311). The truth's pixel variance is debiased for its Monte Carlo
    noise, var(truth) = var_px(m) − mean_px(s²) (s = the per-pixel standard error of the channel mean); the
    uncertainty is the standard deviation of c over ``CONTRAST_DRAWS`` parametric redraws m + s·N(0, 1) of the
    reference (each debiased with 2 s², the redraw's noise added to the estimate's own)."""
    e, m = image[mask].mean(axis=-1), mean[mask].mean(axis=-1)
    s2 = (stderr[mask] ** 2).sum(axis=-1) / 9.0  # channel mean of three channels, treated as independent
    sd_e = float(e.std())
    c = sd_e / np.sqrt(max(float(m.var() - s2.mean()), 1e-30))
    rng = np.random.default_rng(seed)
    draws = [sd_e / np.sqrt(max(float((m + np.sqrt(s2) * rng.standard_normal(m.size)).var() - 2 * s2.mean()), 1e-30))
             for _ in range(CONTRAST_DRAWS)]
    return float(c), float(np.std(draws, ddof=1))


# ---------------------------------------------------------------- (b) glTF materials
# Scenes of kind "probe_material" (their references (i) and (ii): validate.experiments.renders.kinds).


def material_scene_list(s: Settings, probe: np.ndarray) -> list[tuple[rs.RenderScene, SceneKind]]:
    """The probe's metalness × roughness grid, and metalness 0.5 in the white furnace (kind "furnace_material":
    references "energy" = 1, a white non-absorbing sphere, and "gltf" = (i))."""
    out = [(sc, K.FURNACE_MATERIAL) for sc in rs.furnace_material_scenes(s.resolution, s.furnace_roughness)]
    return out + [(sc, K.PROBE_MATERIAL) for sc in rs.probe_material_scenes(probe, "uffizi", s.probe_resolution,
                                                                             s.material_roughness, s.material_metallic)]


# the glTF BSDF's own checks (validate.reference.gltf_bsdf): χ² of sample against pdf, the directional albedo through
# sample against a float64 quadrature of the formulas, and metallic 1 against Mitsuba's roughconductor
BSDF_CHI2_CASES = ((0.0, 0.25, 0.6), (0.0, 1.0, 0.3), (0.5, 0.5, 0.6), (1.0, 0.25, 0.6), (1.0, 1.0, 0.3))
BSDF_CHI2_POWER = {"sample_alpha_scale": 1.1}  # a sampler 10 % too rough for its own pdf
BSDF_ALBEDO_BASE = (0.0, 0.5, 1.0)  # R: the specular layer alone, B: white
BSDF_ALBEDO_CASES = ((0.0, 0.25), (0.0, 1.0), (0.5, 0.5), (1.0, 0.25), (1.0, 1.0))
BSDF_ALBEDO_MU = 0.6
BSDF_F0_POWER = 0.05  # the dielectric's F₀ 0.04 → 0.05 (ior 1.5 → 1.57)
BSDF_METAL_ROUGHNESS = (0.25, 0.5, 1.0)


def gltf_bsdf_checks(s: Settings) -> dict[str, Any]:
    """χ² (Šidák over the cases), albedo z-scores and the roughconductor comparison; each with its power case."""
    from ...reference import gltf_bsdf as g

    n, k = s.bsdf_check_samples, len(BSDF_CHI2_CASES)
    chi2 = [g.chi2_gltf(m, r, mu, n, s.seed + 1, test_count=k) for m, r, mu in BSDF_CHI2_CASES]
    m0, r0, mu0 = BSDF_CHI2_CASES[2]
    chi2_power = g.chi2_gltf(m0, r0, mu0, n, s.seed + 1, test_count=k, **BSDF_CHI2_POWER)
    albedo = []
    for m, r in BSDF_ALBEDO_CASES:
        mean, se = g.albedo_sampled(BSDF_ALBEDO_BASE, m, r, BSDF_ALBEDO_MU, n, s.seed + 2)
        q = g.albedo_quadrature(BSDF_ALBEDO_BASE, m, r, BSDF_ALBEDO_MU)
        q_half = g.albedo_quadrature(BSDF_ALBEDO_BASE, m, r, BSDF_ALBEDO_MU, nodes=96)
        qp = g.albedo_quadrature(BSDF_ALBEDO_BASE, m, r, BSDF_ALBEDO_MU, dielectric_f0=BSDF_F0_POWER)
        # uncertainty: the Monte Carlo standard error and the quadrature's own error (192 vs 96 nodes), in quadrature
        unc = [float(np.hypot(e, a - b)) for e, a, b in zip(se, q, q_half, strict=True)]
        albedo.append({"metallic": m, "roughness": r, "mu_i": BSDF_ALBEDO_MU, "sampled": mean, "se": se,
                       "quadrature": q, "quadrature_f0_power": qp, "unc": unc,
                       "z": [(a - b) / u for a, b, u in zip(mean, q, unc, strict=True)],
                       "z_power": [(a - b) / u for a, b, u in zip(mean, qp, unc, strict=True)]})
    metal = [g.metal_vs_roughconductor(r, 20_000, s.seed + 3) for r in BSDF_METAL_ROUGHNESS]
    return {"chi2": chi2, "chi2_power": chi2_power, "albedo": albedo, "metal_vs_roughconductor": metal,
            "samples": n}


def linear_mix(scenes: list[SceneResult], sr: SceneResult, engine: str) -> np.ndarray | None:
    """The engine's own (1 − m)·image(m = 0) + m·image(m = 1) at the roughness of ``sr`` (None when one is missing):
    what glTF's material = mix(dielectric, metal, metallic) [B.2.1] renders at metalness m."""
    m, r = sr.scene.material.metallic, sr.scene.material.roughness
    ends = {s.scene.material.metallic: s for s in scenes if s.kind is K.PROBE_MATERIAL
            and s.scene.material.roughness == r and s.scene.material.metallic in (0.0, 1.0) and engine in s.engines}
    if 0.0 not in ends or 1.0 not in ends:
        return None
    return (1 - m) * ends[0.0].engines[engine].image + m * ends[1.0].engines[engine].image


__all__ = ["Measurements", "SceneResult", "EngineResult", "compute", "scene_list", "references", "truth", "budget",
           "power_references", "engine_names", "measure_scene", "prepare_references", "with_readback", "linear_mix",
           "contrast_ratio", "gltf_bsdf_checks", "material_scene_list", "material_references", "MATERIAL_REFERENCES",
           "SPOT_CONE_OFFSET_DEG", "DIRECT_BUDGET_OF_PEAK", "FURNACE_BUDGET", "PROBE_BUDGET_REL", "to_render",
           "skip_reason", "substitution", "Unavailable"]
