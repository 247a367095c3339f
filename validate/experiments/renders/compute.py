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
Lambertian plane and sphere (``env_spp``): three.js, and Babylon as ``KIND_NOTE`` states (its shader, Heitz's
tables); Filament has no area lights (``KIND_SKIP``).
"""

from __future__ import annotations

from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...local_models import render as engines
from ...metrics.pixel_z import PixelJudgement, interior_mask, judge
from ...reference.render_reference import RenderReference, render_reference
from ...scenes import render_scenes as rs
from .budgets import FURNACE_BUDGET, PROBE_BUDGET_REL
from .cdf.compute import cdf_reference, cdf_scene_list, compute_cdf
from .khronos.compute import compute_khronos
from .settings import Settings
from .shadows.compute import compute_shadows, shadow_scene_list

# Directional budget, a measured margin: the engines shade a 512×256 tessellated sphere; three's largest
# |engine − Mitsuba| over the 2336 interior pixels of the 64² image was 1.76e-3 = 0.18 % of the peak ρE/π =
# 0.955 (rows 9–46, scattered, not at the outline); b = 0.25 % of the peak radiance ρE/π.
DIRECT_BUDGET_OF_PEAK = 2.5e-3
# Scenes judged with that budget: the same per-fragment Lambert shading of a tessellated sphere (on the plane, where
# interpolated positions and normals are exact, the margin is generous).
PEAK_BUDGET_KINDS = ("directional", "point", "spot", "hemisphere", "probe_lambert", "rect")
SPOT_CONE_OFFSET_DEG = 1.0  # power: a cone falloff off by 1° (the outer angle 30° → 31°)
# engines rendering only some kinds: three's LightProbe built as its removed HemisphereLightProbe did (issue 26668)
KIND_ENGINES = {"hemisphere": {"three": ("three_probe",)}}
# engines left out of a kind, with the reason (reported as skipped)
FILAMENT_NO_IBL = ("Filament 1.53.4's npm package has no IBL prefilter (cmgen/libibl are not in the WebAssembly "
                   "build): IndirectLight.Builder takes only precomputed irradianceSh and a prefiltered reflections "
                   "cubemap, so an environment cannot go through Filament's own pipeline")
KIND_SKIP = {"rect": {"filament": "Filament has no area lights (LightManager types: SUN, DIRECTIONAL, POINT, "
                                  "FOCUSED_SPOT, SPOT)"},
             "furnace": {"filament": FILAMENT_NO_IBL}, "hemisphere": {"filament": FILAMENT_NO_IBL},
             "probe": {"filament": FILAMENT_NO_IBL}, "probe_lambert": {"filament": FILAMENT_NO_IBL},
             # the glTF material scenes are lit by the furnace / the probe only: Filament was rendered there and
             # failed each with "black image" after its exposure search (no IBL), 12 page calls of waste
             "furnace_material": {"filament": FILAMENT_NO_IBL}, "probe_material": {"filament": FILAMENT_NO_IBL}}
# engines rendered with a stated substitution, by kind: the label travels with the engine's info, the report row and
# the claims. Babylon 9.35's RectAreaLight loads its LTC tables from assets.babylonjs.com
# (Lights/LTC/ltcTextureTool.js: Tools.LoadFileAsync of areaLightsLTC.bin) and the render machine has no network;
# babylon_render.mjs puts Heitz et al. 2016's GGX tables (three.js's RectAreaLightTexturesLib LTC_MAT_1 / LTC_MAT_2)
# where AreaLight looks for them (scene._ltcTextures, @internal: 9.35 has no public LTC provider) in the channel
# layout its ltcHelperFunctions reads. The Lambertian scenes' diffuse term is LTCEvaluate with the identity matrix
# (the rectangle's form factor) and their specular term is 0 (R0 = 0), so their pixels do not depend on the table
# (measured: bit-identical with a constant table; a dielectric with F0 = 0.04 at roughness 0.5 is not).
RECT_LTC_LABEL = ("Babylon's RectAreaLight shader with Heitz's tables (Babylon's own areaLightsLTC.bin is not "
                  "obtainable offline)")
KIND_NOTE = {"rect": {"babylon": RECT_LTC_LABEL}}


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
    kind: str  # "furnace" | "directional" | "point" | "spot" | "hemisphere" | "probe" | "probe_lambert"
    references: dict[str, np.ndarray]  # kind → (R, R, 3) truth image (NaN off the sphere)
    reference_energy: dict[str, tuple[float, float]]  # kind → mean ± standard error over the mask
    mask: np.ndarray
    stderrs: dict[str, np.ndarray] = field(default_factory=dict)  # kind → (R, R, 3) standard error
    engines: dict[str, EngineResult] = field(default_factory=dict)
    skipped: dict[str, str] = field(default_factory=dict)  # engine → reason
    power_refs: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)  # label → (mean, stderr)
    dof: int = 7


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
    missing: Any = None  # engines.Missing: the runtime no engine could run without (npm engines, Chromium), or None


def scene_list(s: Settings, probe: np.ndarray | None = None) -> list[tuple[rs.RenderScene, str]]:
    out = [(sc, "furnace") for sc in rs.furnace_scenes(s.resolution, s.furnace_roughness)]
    out += [(rs.lambert_sun_scene(s.resolution, s.sun_lux), "directional")]
    out += [(sc, "spot" if sc.name.startswith("spot") else "point") for sc in rs.punctual_scenes(s.resolution)]
    out += [(rs.hemisphere_scene(s.resolution), "hemisphere")]
    out += [(sc, "rect") for sc in rs.rect_scenes(s.rect_resolution)]
    if probe is None:
        return out
    out += [(sc, "probe") for sc in rs.probe_scenes(probe, "uffizi", s.probe_resolution, s.probe_roughness, (1.0,))]
    out += [(rs.probe_lambert_scene(probe, "uffizi", s.probe_resolution), "probe_lambert")]
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


def references(scene: rs.RenderScene, kind: str,
               s: Settings) -> tuple[dict[str, RenderReference | None], np.ndarray]:
    """Reference renders by kind (None: the closed-form furnace 1) and the hit mask."""
    from ...reference.render_reference import centre_rays

    _, hit = centre_rays(scene)
    if kind in ("directional", "point"):
        return {"mitsuba": render_reference(scene, s.spp, s.passes, s.seed)}, hit
    if kind == "hemisphere":
        return {"mitsuba": render_reference(scene, s.env_spp, s.passes, s.seed)}, hit
    if kind == "probe":
        return {"mitsuba": render_reference(scene, s.probe_spp, s.passes, s.seed)}, hit
    if kind == "rect":  # an area emitter: next-event estimation on the rectangle, Monte Carlo noise
        return {"mitsuba": render_reference(scene, s.env_spp, s.passes, s.seed)}, hit
    if kind == "probe_material":
        return material_references(scene, s), hit
    if kind == "furnace_material":
        return {"energy": None, "gltf": render_reference(scene, s.spp, s.passes, s.seed)}, hit
    if kind == "probe_lambert":  # the diffuse limit: the hemisphere's sample count (its power check needs ~1 %)
        return {"mitsuba": render_reference(scene, s.env_spp, s.passes, s.seed)}, hit
    if kind == "spot":
        r = scene.resolution
        return {"mitsuba": render_reference(rs.spot_scene(r), s.spp, s.passes, s.seed),
                "smoothstep": render_reference(rs.spot_scene(r, "smoothstep"), s.spp, s.passes, s.seed)}, hit
    refs: dict[str, RenderReference | None] = {"energy": None}
    if scene.material.metallic == 1.0:
        refs["model"] = render_reference(scene, s.spp, s.passes, s.seed)
    return refs, hit


def truth(ref: RenderReference | None, hit: np.ndarray, passes: int) -> tuple[np.ndarray, np.ndarray, int]:
    if ref is not None:
        return ref.mean, ref.stderr, ref.dof
    one = np.where(hit[..., None], 1.0, np.nan) * np.ones(3)
    return one, np.where(hit[..., None], 0.0, np.nan) * np.ones(3), max(passes - 1, 1)


def budget(kind: str, mean: np.ndarray) -> tuple[np.ndarray | float, str]:
    if kind in ("probe", "probe_material"):
        return PROBE_BUDGET_REL * mean, f"{PROBE_BUDGET_REL:.2e} × the reference (the furnace budget per unit radiance)"
    if kind in PEAK_BUDGET_KINDS:
        peak = float(np.nanmax(mean))
        return DIRECT_BUDGET_OF_PEAK * peak, f"{DIRECT_BUDGET_OF_PEAK:.2%} of the peak radiance (measured margin)"
    return FURNACE_BUDGET, f"{FURNACE_BUDGET:.2e} (2 half-float lookups 2·2⁻¹¹ + SwiftShader trig 2e-4)"


def power_references(scene: rs.RenderScene, kind: str, s: Settings) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Spot: each profile's reference with the outer cone ``SPOT_CONE_OFFSET_DEG`` wider (a power check)."""
    if kind != "spot":
        return {}
    out = {}
    for profile in rs.SPOT_PROFILES:
        r = render_reference(rs.spot_scene(scene.resolution, profile, SPOT_CONE_OFFSET_DEG), s.spp, s.passes, s.seed)
        out[f"{profile} outer +{SPOT_CONE_OFFSET_DEG:g}°"] = (r.mean, r.stderr)
    return out


def engine_names(kind: str, s: Settings) -> list[str]:
    """The settings' engines plus the variants that render only this kind (``KIND_ENGINES``)."""
    extra = KIND_ENGINES.get(kind, {})
    return [n for e in s.engines for n in (e, *extra.get(e, ()))]


Prepared = tuple[dict[str, "RenderReference | None"], np.ndarray, dict[str, tuple[np.ndarray, np.ndarray]]]


def prepare_references(scene: rs.RenderScene, kind: str, s: Settings) -> Prepared:
    """The scene's references, hit mask and power references (Mitsuba only: no browser, safe on the reference
    thread of :func:`compute`)."""
    refs, hit = references(scene, kind, s)
    return refs, hit, power_references(scene, kind, s)


def measure_scene(scene: rs.RenderScene, kind: str, s: Settings, prepared: Future | None = None) -> SceneResult:
    """Every engine's render of ``scene`` judged against its references; ``prepared``: a future of
    :func:`prepare_references` (computed meanwhile on another thread), else they are computed here. The engines
    render first, so the browser works while the references are traced."""
    rendered: dict[str, engines.EngineRender | str] = {}  # engine → its render, or why it was skipped
    for name in engine_names(kind, s):
        if name in KIND_SKIP.get(kind, {}):
            rendered[name] = KIND_SKIP[kind][name]
            continue
        try:
            rendered[name] = engines.render(name, scene)
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
        if name in KIND_NOTE.get(kind, {}):
            out.info["note"] = KIND_NOTE[kind][name]
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

    missing = engines.missing_runtime()
    probe, probe_note = load_probe(ctx)
    scenes = scene_list(s, probe)
    shadow_scenes = shadow_scene_list(s)
    cdf_scenes = cdf_scene_list(ctx, s)
    pool = ThreadPoolExecutor(1, thread_name_prefix="renders-references")
    try:
        prepared = [pool.submit(prepare_references, sc, kind, s) for sc, kind in scenes]
        shadow_refs = [pool.submit(render_reference, sc, s.shadow_spp, s.passes, s.seed) for sc in shadow_scenes]
        bsdf = pool.submit(gltf_bsdf_checks, s)
        cdf_refs = [pool.submit(cdf_reference, sc, s) for sc, _ in cdf_scenes]  # traced while the browser renders
        browser_page.preload([engines.ENGINES[n][0] for kind in dict.fromkeys(k for _, k in scenes)
                              for n in engine_names(kind, s) if n not in KIND_SKIP.get(kind, {})])
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


# ---------------------------------------------------------------- (b) glTF materials: references (i) and (ii)
# Scenes "probe_material": white spheres (baseColor 1) over ``material_metallic`` × ``material_roughness`` under the
# probe. References, kept apart: "gltf" = (i) glTF 2.0 Appendix B as specified (validate.reference.gltf_bsdf, any
# metalness); "multiscatter" = (ii) the random-walk microsurface (validate.reference.microsurface_bsdf) — at metalness
# 1 the walk itself, at metalness m in (0, 1) glTF's linear mix (B.2.1) with the metal lobe replaced by the walk,
# (1 − m)·(i)(m = 0) + m·(ii)(m = 1): the dielectric's F₀ = 0.04 layer keeps its single scattering.
MATERIAL_REFERENCES = {"gltf": "vs (i) glTF as specified", "multiscatter": "vs (ii) multiscatter microsurface"}


def material_scene_list(s: Settings, probe: np.ndarray) -> list[tuple[rs.RenderScene, str]]:
    """The probe's metalness × roughness grid, and metalness 0.5 in the white furnace (kind "furnace_material":
    references "energy" = 1, a white non-absorbing sphere, and "gltf" = (i))."""
    out = [(sc, "furnace_material") for sc in rs.furnace_material_scenes(s.resolution, s.furnace_roughness)]
    return out + [(sc, "probe_material") for sc in rs.probe_material_scenes(probe, "uffizi", s.probe_resolution,
                                                                             s.material_roughness, s.material_metallic)]


def _with_model(scene: rs.RenderScene, metallic: float, model: str) -> rs.RenderScene:
    from dataclasses import replace

    mat = replace(scene.material, metallic=metallic, model=model)
    return replace(scene, name=f"probe_{model}_m{metallic:g}_r{mat.roughness:g}", material=mat)


def material_references(scene: rs.RenderScene, s: Settings) -> dict[str, RenderReference | None]:
    """(i) always; (ii) where the metal lobe is present (module block comment above)."""
    out: dict[str, RenderReference | None] = {"gltf": render_reference(scene, s.probe_spp, s.passes, s.seed)}
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
    ends = {s.scene.material.metallic: s for s in scenes if s.kind == "probe_material"
            and s.scene.material.roughness == r and s.scene.material.metallic in (0.0, 1.0) and engine in s.engines}
    if 0.0 not in ends or 1.0 not in ends:
        return None
    return (1 - m) * ends[0.0].engines[engine].image + m * ends[1.0].engines[engine].image
