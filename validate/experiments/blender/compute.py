"""Numbers only: Blender's renders of the exported scenes, judged per pixel against Mitsuba.

Every scene of the exported set (:func:`validate.scenes.manifest.scene_set`) whose kind both renderers describe
identically — Lambertian sphere and plane under a sun, a point and a spot light; white spheres in the furnace — goes
through Blender's glTF importer (mode ``COMPAT``, :mod:`validate.local_models.render.blender`) into Cycles:
``passes`` frames of independent seeds, their mean and standard error per pixel (``passes − 1`` dof), as the suite's
Mitsuba passes. The truth is the renders experiment's (:func:`validate.experiments.renders.compute.references`, its
samples for the set: the same cache entries), judged with its budgets (:func:`~validate.experiments.renders.compute.
budget`) by :func:`validate.metrics.pixel_z.judge`. The spot has a third reference, ``blender``: the same light with
Blender's own cone — smoothstep between the outer cone and cos θ_b = cos θ_o + (1 − cos θ_o)·blend, blend = 1 −
inner/outer as the importer sets it (Cycles ``spot_attenuation``) — the scene as Blender describes it.

Masks, each stated with its root (report findings): pixels whose centre lies exactly on the plane's shared triangle
edge (row + column = R − 1; :data:`SEAM`) and, on the sphere under the sun or the point light, pixels with
|n·l| < :data:`TERMINATOR_COS` (the terminator band) are judged apart: Blender lights both wrongly, and Mitsuba on the
same exported mesh and normals does not (docs/experiments/blender.md). The power check scales Blender's image by 1.01.
The importer's light conversion is measured: the ``conversion`` scenes rendered again under SPEC and RAW, their
radiance over COMPAT's. Renders are cached by (Blender version, .glb content hash, settings) in the reference cache.
"""

from __future__ import annotations

import hashlib
import json
import math
import tempfile
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ...local_models.render import blender as bl
from ...local_models.render.blender_cycles import ENGINE as CYCLES
from ...local_models.render.blender_eevee import ENGINE as EEVEE
from ...metrics.pixel_z import PixelJudgement, interior_mask, judge
from ...reference import pathtrace
from ...reference.cache import lookup, store
from ...reference.render_reference import render_reference
from ...scenes import render_scenes as rs
from ...scenes.gltf_export import glb_bytes
from ...scenes.manifest import SetScene, scene_set
from ..base import NotRun
from ..renders import settings as renders_settings
from ..renders.compute import budget, references, truth
from . import probes as pr
from . import shadows as sh
from . import world as wd
from .settings import Settings

POWER_SCALE = sh.POWER_SCALE  # the power check: Blender's image 1 % brighter
TERMINATOR_COS = 0.01  # the sun-lit sphere's pixels with |n·l| < this are judged apart (report: the finding)
SEAM = "pixels whose centre lies on the plane's shared triangle edge (row + column = R − 1)"
CONVERSION_SCENES = ("lambert_directional", "point_plane")
WORKER_VERSION = 1  # bump when blender_worker.py changes what it renders


@dataclass
class Judged:
    """One engine's render of one scene against each reference."""

    scene: str
    kind: str
    engine: str
    frames: int
    samples: int
    judgements: dict[str, PixelJudgement]
    power: dict[str, PixelJudgement]  # the image × POWER_SCALE against the same reference
    energy: dict[str, tuple[float, float]]  # reference → (mean Blender / mean truth over the mask, its uncertainty)
    apart: dict[str, dict[str, float]] = field(default_factory=dict)  # masked-out region → its numbers
    lights: list[dict[str, Any]] = field(default_factory=list)  # what the importer made of the lights
    precision: str = "float"


@dataclass
class Measurements:
    settings: Settings
    version: str = ""
    missing: NotRun | None = None
    scenes: list[Judged] = field(default_factory=list)
    conversion: dict[str, dict[str, Any]] = field(default_factory=dict)  # mode → light type → numbers
    costs: dict[str, Any] = field(default_factory=dict)
    world: list[wd.WorldResult] = field(default_factory=list)
    survey: list[wd.WorldResult] = field(default_factory=list)  # EEVEE alone on every other probe (world_survey)
    glossy: list[dict[str, Any]] = field(default_factory=list)  # per roughness (probes.py): cycles, eevee variants
    volume: dict[str, Any] = field(default_factory=dict)  # probes.py's volume-probe scene: EEVEE per variant
    shadows: dict[str, Any] = field(default_factory=dict)  # label → region → numbers (shadows.py)


def truth_settings(s: Settings) -> Any:
    return renders_settings.QUICK if s.scene_set == "quick" else renders_settings.FULL


def selected(s: Settings) -> list[SetScene]:
    items = [it for it in scene_set(s.scene_set, s.resolution) if it.kind in s.kinds]
    return [it for it in items if not s.scenes or it.scene.name in s.scenes]


def blender_spot(scene: rs.RenderScene) -> rs.RenderScene:
    """The spot scene with Blender's cone (module docstring): smoothstep profile, inner cone at cos θ_b."""
    [li] = [x for x in scene.lights if isinstance(x, rs.SpotLight)]
    blend = 1.0 - li.inner_deg / li.outer_deg
    co = math.cos(math.radians(li.outer_deg))
    inner = math.degrees(math.acos(co + (1.0 - co) * blend))
    return replace(scene, lights=(replace(li, profile="smoothstep", inner_deg=inner),))


def job_for(it: SetScene, engine: bl.BlenderEngine, s: Settings, glb: Path, out: Path, mode: str = bl.TRUTH_MODE,
            frames: int | None = None, samples: int | None = None) -> bl.Job:
    furnace = it.kind == "furnace"
    if engine is EEVEE:
        n, spp = s.eevee_passes, s.eevee_samples
    else:
        n, spp = s.passes, (s.furnace_spp if furnace else s.spp)
    n, spp = frames or n, samples or spp
    world = tuple(float(v) for v in it.scene.environment.radiance) if furnace else None
    return bl.Job(str(glb), str(out), engine.engine, it.scene.resolution, spp,
                  tuple(s.seed * 1000 + k for k in range(n)), mode, world)


def cache_parts(job: bl.Job, version: str, digest: str) -> dict[str, Any]:
    d = asdict(job)
    d.pop("glb")
    d.pop("out")
    if d.get("scene"):  # a bpy-built scene: its texture enters by ``digest``, not by its temporary path
        d["scene"] = {k: v for k, v in d["scene"].items() if k != "env_exr"}
    else:
        d.pop("scene")
    if not d.get("extras"):
        d.pop("extras")
    return {"blender": version, "glb_sha256": digest, "worker": WORKER_VERSION, **d}


def render_all(jobs: list[tuple[bl.Job, str]], version: str, work: Path) -> tuple[list[dict], dict[str, Any]]:
    """Every job's frames and lights, from the cache or from one Blender batch of the misses; the batch's costs."""
    out: list[dict | None] = []
    for job, digest in jobs:
        hit = lookup("blender_render", cache_parts(job, version, digest))
        out.append(None if hit is None else {"frames": hit["frames"], "lights": json.loads(str(hit["lights"])),
                                             "frame_s": [], "cached": True})
    misses = [k for k, v in enumerate(out) if v is None]
    costs: dict[str, Any] = {"jobs": len(jobs), "rendered": len(misses)}
    if misses:
        batch = bl.render_batch([jobs[k][0] for k in misses], work)
        costs.update(import_s=batch.import_s, process_wall_s=batch.wall_s,
                     setup_s=[r.setup_s for r in batch.results])
        for k, r in zip(misses, batch.results, strict=True):
            job, digest = jobs[k]
            store("blender_render", cache_parts(job, version, digest),
                  {"frames": r.frames, "lights": np.array(json.dumps(r.lights))})
            out[k] = {"frames": r.frames, "lights": r.lights, "frame_s": r.frame_s, "cached": False}
    return out, costs  # type: ignore[return-value]


def half_stderr(v: np.ndarray) -> np.ndarray:
    """σ = ulp/√12 of a value rounded to binary16 (uniform rounding error)."""
    return np.spacing(np.abs(v).astype(np.float16)).astype(np.float64) / np.sqrt(12.0)


def apart_mask(it: SetScene, tm: np.ndarray) -> tuple[np.ndarray, str]:
    """(R, R) pixels judged apart (module docstring: the seam, a lit sphere's terminator band) and what they are."""
    r = it.scene.resolution
    if it.scene.geometry == "plane":
        return sh.seam_mask(r), SEAM
    if it.scene.geometry == "sphere" and it.kind in ("directional", "point"):
        [li] = it.scene.lights
        p = it.scene.surface_points()  # unit sphere: n = p
        to_light = -li.unit_direction() if it.kind == "directional" else np.asarray(li.position) - p
        cos = np.nan_to_num((p * to_light).sum(-1) / np.linalg.norm(to_light, axis=-1))
        return it.scene.hit_mask() & (np.abs(cos) < TERMINATOR_COS), f"the terminator band (|n·l| < {TERMINATOR_COS:g})"
    return np.zeros((r, r), bool), ""


def judge_scene(it: SetScene, engine: bl.BlenderEngine, res: dict, s: Settings) -> Judged:
    f = res["frames"].astype(np.float64)
    img, cov = f[..., :3].mean(axis=0), f[..., 3].min(axis=0)
    se = f[..., :3].std(axis=0, ddof=1) / math.sqrt(len(f)) if len(f) > 1 else np.zeros_like(img)
    precision = "half" if engine.precision == "half" or bl.half_exact(f[..., :3]) else "float"
    if precision == "half":
        se = np.sqrt(se**2 + half_stderr(img) ** 2)
    ts = truth_settings(s)
    refs, hit = references(it.scene, it.kind, ts)
    if it.kind == "spot":
        refs["blender"] = render_reference(blender_spot(it.scene), ts.spp, ts.passes, ts.seed)
    spp = s.eevee_samples if engine is EEVEE else (s.furnace_spp if it.kind == "furnace" else s.spp)
    j = Judged(it.scene.name, it.kind, engine.name, len(f), spp, {}, {}, {}, lights=res["lights"], precision=precision)
    for k, ref in refs.items():
        tm, ts_err, dof = truth(ref, hit, ts.passes)
        apart, what = apart_mask(it, tm)
        mask = interior_mask(hit, cov) & ~apart
        b, text = budget(it.kind, tm)
        sig = np.sqrt(ts_err**2 + se**2)
        j.judgements[k] = judge(img, tm, sig, dof, mask, b, text)
        j.power[k] = judge(img * POWER_SCALE, tm, sig, dof, mask, b, text)
        j.energy[k] = energy_ratio(img, se, tm, ts_err, mask)
        region = interior_mask(hit, cov) & apart
        if region.any():
            jr = judge(img, tm, sig, dof, region, b, text)
            j.apart[k] = {"what": what, "pixels": int(region.sum()), "fraction_accepted": jr.fraction_accepted,
                          "mean_abs_diff_of_peak": float(np.abs(img - tm)[region].mean() / np.nanmax(tm)),
                          "mean_ratio": float(img[region].sum() / max(tm[region].sum(), 1e-30))}
    return j


def energy_ratio(img: np.ndarray, se: np.ndarray, tm: np.ndarray, ts: np.ndarray, mask: np.ndarray
                 ) -> tuple[float, float]:
    """Mean Blender over mean truth on ``mask``, ± from both standard errors (pixels independent)."""
    a, b = float(img[mask].mean()), float(tm[mask].mean())
    n = img[mask].size
    ua, ub = math.sqrt(float((se[mask] ** 2).sum())) / n, math.sqrt(float((ts[mask] ** 2).sum())) / n
    r = a / b
    return r, r * math.hypot(ua / a, ub / b)


def conversion(items: dict[str, SetScene], results: dict[tuple[str, str, str], dict]) -> dict[str, dict[str, Any]]:
    """Per importer mode and light type: the energy Blender's light got, and the radiance over COMPAT's."""
    out: dict[str, dict[str, Any]] = {}
    for mode in bl.LIGHTING_MODES:
        for name in CONVERSION_SCENES:
            r, ref = results.get((name, mode, "conv")), results.get((name, bl.TRUTH_MODE, "conv"))
            if r is None or ref is None:
                continue
            li = items[name].scene.lights[0]
            mask = items[name].scene.hit_mask() & (ref["frames"][0, ..., 0] > 1e-3)
            ratio = float(r["frames"][0, ..., :3][mask].sum() / ref["frames"][0, ..., :3][mask].sum())
            out.setdefault(mode, {})[r["lights"][0]["type"]] = {
                "gltf_intensity": li.intensity, "gltf_unit": "lx" if r["lights"][0]["type"] == "SUN" else "cd",
                "blender_energy": r["lights"][0]["energy"],
                "blender_unit": "W/m²" if r["lights"][0]["type"] == "SUN" else "W",
                "radiance_over_compat": ratio}
    return out


def shadow_jobs(s: Settings, work: Path, keyed: list) -> None:
    """Append the soft-shadow scenes' jobs to ``keyed``: the sphere light's (Cycles, ``passes`` frames; EEVEE per
    jitter setting and sweep point) and, with ``shadow_disc``, the disc light's (Cycles; EEVEE jitter off and on)."""
    if not s.soft_shadows:
        return
    seeds = tuple(s.seed * 1000 + k for k in range(s.passes))
    scenes = [(sh.scene(s.resolution), [*sh.JITTER, *s.shadow_sweep])]
    if s.shadow_disc:
        scenes.append((sh.disc_scene(s.resolution), list(sh.DISC_LABELS)))
    for sc, eevee in scenes:
        data = glb_bytes(sc)
        glb = work / f"{sc.name}.glb"
        glb.write_bytes(data)
        digest = hashlib.sha256(data).hexdigest()
        keyed.append(((sc.name, "cycles", CYCLES.name), bl.Job(str(glb), str(work / f"{sc.name}_c"), CYCLES.engine,
                                                               s.resolution, s.shadow_spp, seeds, punctual=False,
                                                               extras=sh.extras(sc)), digest))
        for label in eevee:
            ex = sh.extras(sc, sh.eevee_light(label), sh.SCENE.get(label))
            keyed.append(((sc.name, f"eevee_{label}", EEVEE.name),
                          bl.Job(str(glb), str(work / f"{sc.name}_{label}"), EEVEE.engine, s.resolution,
                                 s.shadow_spp, (s.seed,), punctual=False, extras=ex), digest))


def world_jobs(ctx: Any, s: Settings, work: Path, keyed: list) -> list[wd.WorldScene]:
    """Append the world-lit spheres' jobs to ``keyed`` (Cycles, then EEVEE per variant; on the survey's probes EEVEE
    per survey variant alone); the scenes."""
    if not s.world_probes and not s.world_survey:
        return []
    envs = {e.name: e for e in ctx.environments()[0]}
    survey = [n for n in envs if n not in s.world_probes] if s.world_survey else []
    out = []
    for name in [*s.world_probes, *survey]:
        if name not in envs:
            continue  # the probe is not in this run's probes (report: the world section names what ran)
        surveyed = name in survey
        ws = wd.WorldScene(envs[name], s.world_view)
        tex, digest = wd.texture(ws.env)
        exr = work / f"{ws.name}.exr"
        wd.write_exr(exr, tex)
        seeds = tuple(s.seed * 1000 + k for k in range(s.passes))
        if s.world_cycles and not surveyed:
            keyed.append(((ws.name, "cycles", CYCLES.name), wd.job(ws, exr, CYCLES, s.resolution, s.world_spp, seeds,
                                                                   work / f"{ws.name}_c"), digest))
        for v in s.world_survey if surveyed else s.world_variants:
            keyed.append(((ws.name, v, EEVEE.name), wd.job(ws, exr, EEVEE, s.resolution, s.world_eevee_samples,
                                                           (s.seed,), work / f"{ws.name}_{v}", v), digest))
        out.append(ws)
    return out


def probe_jobs(ctx: Any, s: Settings, work: Path, keyed: list) -> tuple[list[pr.GlossyScene], pr.VolumeScene | None]:
    """Append the glossy spheres' (Cycles, EEVEE per variant) and the volume-probe scene's (EEVEE per variant, Cycles)
    jobs."""
    envs = {e.name: e for e in ctx.environments()[0]} if (s.glossy_probe or s.volume_probe) else {}
    glossy: list[pr.GlossyScene] = []
    volume = None
    exrs: dict[str, tuple[Path, str]] = {}

    def texture(env: Any) -> tuple[Path, str]:
        if env.name not in exrs:
            tex, digest = wd.texture(env)
            exr = work / f"probe_{env.name}.exr"
            wd.write_exr(exr, tex)
            exrs[env.name] = (exr, digest)
        return exrs[env.name]

    if s.glossy_probe in envs:
        exr, digest = texture(envs[s.glossy_probe])
        seeds = tuple(s.seed * 1000 + k for k in range(s.glossy_passes))
        for r in s.glossy_roughness:
            gs = pr.GlossyScene(envs[s.glossy_probe], s.world_view, float(r))
            keyed.append(((gs.name, "cycles", CYCLES.name), pr.job(pr.glossy_desc(gs, exr), CYCLES, s.resolution,
                                                                   s.glossy_spp, seeds, work / f"{gs.name}_c"), digest))
            for v in s.glossy_variants:
                keyed.append(((gs.name, v, EEVEE.name), pr.job(pr.glossy_desc(gs, exr, v), EEVEE, s.resolution,
                                                               s.glossy_eevee_samples, (s.seed,),
                                                               work / f"{gs.name}_{v}"), digest))
            glossy.append(gs)
    if s.volume_probe in envs:
        volume = pr.VolumeScene(envs[s.volume_probe])
        exr, digest = texture(volume.env)
        for v in s.volume_variants:
            keyed.append(((volume.name, v, EEVEE.name), pr.job(pr.volume_desc(volume, exr, v), EEVEE, s.resolution,
                                                               s.volume_eevee_samples, (s.seed,),
                                                               work / f"{volume.name}_{v}"), digest))
        if s.volume_cycles:
            seeds = tuple(s.seed * 1000 + k for k in range(s.passes))
            keyed.append(((volume.name, "cycles", CYCLES.name), pr.job(pr.volume_desc(volume, exr, "cycles"), CYCLES,
                                                                       s.resolution, s.volume_spp, seeds,
                                                                       work / f"{volume.name}_c"), digest))
    return glossy, volume


def judge_probes(s: Settings, results: dict, glossy: list[pr.GlossyScene], volume: pr.VolumeScene | None
                 ) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    out = []
    for gs in glossy:
        t = pr.truth("glossy", gs.env, s.resolution, s.glossy_truth_spp, s.passes, s.seed, gs.roughness, gs.view)
        mine = {v: r["frames"] for (n, v, _), r in results.items() if n == gs.name}
        mask = pr.sphere_mask(s.resolution, list(mine.values()))
        row: dict[str, Any] = {"probe": gs.env.name, "roughness": gs.roughness, "alpha": pr.alpha(gs.roughness),
                               "truth": {"spp": t.spp, "passes": t.passes}, "eevee": {}}
        if "cycles" in mine:
            row["cycles"] = wd.cycles_numbers(mine["cycles"], t, mask, POWER_SCALE)
        for v in s.glossy_variants:
            if v in mine:
                row["eevee"][v] = pr.eevee_numbers(mine[v][0, ..., :3].astype(np.float64), t, mask)
        out.append(row)
    vol: dict[str, Any] = {}
    if volume is not None:
        t = pr.truth("volume", volume.env, s.resolution, s.volume_truth_spp, s.passes, s.seed)
        mine = {v: r["frames"] for (n, v, _), r in results.items() if n == volume.name}
        film = pr.film_mask(s.resolution, list(mine.values()))
        on_sphere = pr.sphere_pixels(s.resolution, pr.VOLUME_VIEW, pr.VOLUME_ORTHO)
        cy = mine.pop("cycles", None)
        vol = {"probe": volume.env.name, "truth": {"spp": t.spp, "passes": t.passes, "depth": pr.VOLUME_DEPTH},
               "variants": {v: {"plane": pr.eevee_numbers(f[0, ..., :3].astype(np.float64), t, film & ~on_sphere),
                                "sphere": pr.eevee_numbers(f[0, ..., :3].astype(np.float64), t, film & on_sphere)}
                            for v, f in mine.items()}}
        if cy is not None:
            vol["cycles"] = wd.cycles_numbers(cy, t, film, POWER_SCALE)
    return out, vol


def compute(ctx: Any, s: Settings) -> Measurements:
    version, why = bl.available()
    if version is None:
        what = f"{CYCLES.name}, {EEVEE.name}"
        return Measurements(s, missing=NotRun(what, f"Blender not installed ({why})", bl.FIX))
    t0 = time.perf_counter()
    items = {it.scene.name: it for it in selected(s)}
    conv = {n: it for n, it in ((n, it) for it in scene_set(s.scene_set, s.resolution) for n in [it.scene.name])
            if n in CONVERSION_SCENES}
    with tempfile.TemporaryDirectory(prefix="validate-blender-") as d:
        work = Path(d)
        keyed: list[tuple[tuple[str, str, str], bl.Job, str]] = []
        for name, it in {**items, **conv}.items():
            data = glb_bytes(it.scene)
            glb = work / f"{name}.glb"
            glb.write_bytes(data)
            digest = hashlib.sha256(data).hexdigest()
            if name in items:
                keyed.append(((name, bl.TRUTH_MODE, CYCLES.name), job_for(it, CYCLES, s, glb, work / name), digest))
            if name in s.eevee_scenes:
                keyed.append(((name, bl.TRUTH_MODE, EEVEE.name), job_for(it, EEVEE, s, glb, work / f"{name}_e"),
                              digest))
            if name in conv:
                for mode in bl.LIGHTING_MODES:
                    keyed.append(((name, mode, "conv"), job_for(it, CYCLES, s, glb, work / f"{name}_{mode}", mode,
                                                                 1, s.conversion_spp), digest))
        world_scenes = world_jobs(ctx, s, work, keyed)
        shadow_jobs(s, work, keyed)
        glossy, volume = probe_jobs(ctx, s, work, keyed)
        res, costs = render_all([(j, dg) for _, j, dg in keyed], version, work)
    results = {k: r for (k, _, _), r in zip(keyed, res, strict=True)}
    frame_s = {e: [t for (n, m, eng), r in results.items() if eng == e for t in r["frame_s"]]
               for e in (CYCLES.name, EEVEE.name, "conv")}
    m = Measurements(s, version, conversion=conversion(conv, results),
                     costs={**costs, "frame_s": frame_s, "blender_wall_s": time.perf_counter() - t0})
    for (name, _, eng), r in results.items():
        if eng in (CYCLES.name, EEVEE.name) and name in items:
            m.scenes.append(judge_scene(items[name], CYCLES if eng == CYCLES.name else EEVEE, r, s))
    t1 = time.perf_counter()
    for ws in world_scenes:
        truth = pathtrace.render_lambertian_sphere(ws.env, s.resolution, s.world_truth_spp, s.passes, s.seed, ws.view)
        cyc = results.get((ws.name, "cycles", CYCLES.name))
        ee = {v: (s.world_eevee_samples, r["frames"], r["frame_s"]) for (n, v, e), r in results.items()
              if n == ws.name and e == EEVEE.name}
        judged = wd.judge_world(ws, truth, None if cyc is None else cyc["frames"], ee, POWER_SCALE)
        (m.world if ws.env.name in s.world_probes else m.survey).append(judged)
    m.costs["world_judge_s"] = time.perf_counter() - t1
    ts = truth_settings(s)
    for sc, prefix in ((sh.scene(s.resolution), ""), (sh.disc_scene(s.resolution), sh.DISC)):
        frames = {e: r["frames"] for (n, e, _), r in results.items() if n == sc.name}
        if frames:
            judged = sh.judge_shadow(sc, frames, ts.shadow_spp, ts.passes, ts.seed)
            m.shadows.update({prefix + label: regions for label, regions in judged.items()})
    t2 = time.perf_counter()
    m.glossy, m.volume = judge_probes(s, results, glossy, volume)
    m.costs["probes_judge_s"] = time.perf_counter() - t2
    m.costs["total_s"] = time.perf_counter() - t0
    return m
