"""Numbers only: export the scene set, render it through the engines' own glTF loaders, judge the folder, and set
each judgement beside the hand-built path's.

Quick: three.js and Filament (Babylon.js in full runs, as the parent) on the scenes the hand-built path renders
without an environment (the Lambertian sphere under a KHR
directional light, a point light over the plane and beside the sphere, a spot light over the plane) through
three.js's ``GLTFLoader`` and Filament's ``gltfio`` — an environment costs three's PMREM ~14 s per map on
SwiftShader's 2 cores (measured), so the furnace, the hemisphere light and the authored glTF scenes (whose truth is
traced from the files, minutes cold) are the extended run's. Full: the same engines and scenes, judged against the
full run's references (cached by the parent); with ``VALIDATE_EXTENDED=1`` (:data:`..settings.EXTENDED`) Babylon.js
too and every exported scene each engine supports.
Power: the judged image × 1.02 (a light 2 % off) through the same judge (:func:`validate.judge.folder.judge_against`),
and, for Filament's orthographic scenes, gltfio's own orthographic projection (the page's correction off).
"""

from __future__ import annotations

import shutil
import tempfile
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ....judge.images import read_engine_image
from ....local_models.render import babylon_gltf, filament_gltf, three_gltf
from ....metrics.pixel_z import MIN_ACCEPTED, PixelJudgement
from ....scenes.manifest import export_scenes, load_manifest, manifest_scenes
from ..settings import EXTENDED

# loader engine → the hand-built engine of the parent (the same product, fed the suite's own scene JSON)
ENGINES = {"three_gltf": (three_gltf.ENGINE, "three"), "filament_gltf": (filament_gltf.ENGINE, "filament"),
           "babylon_gltf": (babylon_gltf.ENGINE, "babylon")}
# the parent's quick run has no Babylon (its page and first prefilter cost ~80 s on 2 cores): nor has this part's
FULL_ONLY = ("babylon_gltf",)
QUICK_SCENES = ("lambert_directional", "point_plane", "point_sphere", "spot_plane")
POWER_SCALE = 1.02  # a light 2 % off: the image × 1.02
# Filament's orthographic scenes rendered once more with gltfio's own projection (the page's correction off)
ORTHO_POWER_SCENE = "lambert_directional"


@dataclass
class LoaderScene:
    """One scene × loader engine: the loader path's judgement beside the hand-built path's (same reference)."""

    scene: str
    engine: str  # the loader engine (three_gltf …)
    hand: str  # the hand-built engine (three …)
    judged_by: str
    loader: PixelJudgement | None
    hand_judgement: PixelJudgement | None
    loader_passed: bool
    diagnoses: dict[str, Any] = field(default_factory=dict)
    max_diff_of_peak: float = float("nan")  # max |loader − hand-built| over the judged pixels / the truth's peak
    power: dict[str, float] = field(default_factory=dict)  # perturbation → fraction accepted
    note: str = ""


@dataclass
class LoaderMeasurements:
    scenes: list[LoaderScene]
    renders: dict[str, dict[str, Any]]  # engine → version, wall, startup, skipped, info
    skipped: dict[str, str]  # engine → why it did not run
    missing: list[str]  # (engine, scene) the judge found no image for, "engine: scene"
    export_s: float = 0.0
    judge_s: float = 0.0
    quick: bool = True


def _hand_judgement(parent: Any, scene: str, engine: str, ref: str) -> tuple[PixelJudgement | None, np.ndarray | None]:
    for sr in getattr(parent, "scenes", []):
        if sr.scene.name == scene and engine in sr.engines:
            er = sr.engines[engine]
            return er.judgements.get(ref), er.image
    return None, None


def _scene_names(doc: dict[str, Any], quick: bool) -> list[str]:
    names = [e["name"] for e in doc["scenes"] + doc.get("gltf_scenes", [])]
    return [n for n in names if n in QUICK_SCENES] if quick else names


def measure(ctx: Any, s: Any, parent: Any = None) -> LoaderMeasurements:
    """Export → engines → judge (module docstring); ``parent``: the renders measurements (the hand-built path)."""
    quick = bool(getattr(ctx, "quick", True))
    work = Path(tempfile.mkdtemp(prefix="validate-loaders-"))
    try:
        return _measure(work, s, parent, quick)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _measure(work: Path, s: Any, parent: Any, quick: bool) -> LoaderMeasurements:
    # at call time: validate.judge.folder imports the renders package, whose __init__ imports this part
    from ....judge.folder import judge_against, judge_folder, truth_settings

    t0 = time.perf_counter()
    scenes_dir = work / "scenes"
    export_scenes(scenes_dir, "quick" if quick else "full", s.resolution)
    doc = load_manifest(scenes_dir)
    export_s = time.perf_counter() - t0
    names = _scene_names(doc, quick or not EXTENDED)
    out = LoaderMeasurements([], {}, {}, [], export_s, quick=quick)
    items = dict((e["name"], item) for e, item in manifest_scenes(doc, scenes_dir / "manifest.json"))
    ts = truth_settings(doc)
    for name, (engine, hand) in ENGINES.items():
        if (quick or not EXTENDED) and name in FULL_ONLY:
            continue
        why = engine.unavailable()
        if why is not None:
            out.skipped[name] = f"{why.piece}: {why.why} ({why.fix})"
            continue
        images = work / name
        r = engine.render_folder(scenes_dir, names, images)
        out.renders[name] = {"version": r.version, "wall_s": round(r.wall_s, 3), "startup_s": round(r.startup_s, 3),
                             "skipped": r.skipped, "frame_ms": r.frame_ms, "info": r.info}
        if not r.images:
            continue
        t1 = time.perf_counter()
        jr = judge_folder(images, name, scenes_dir)
        out.judge_s += time.perf_counter() - t1
        out.missing += [f"{name}: {n}" for n in jr.missing if n in names and n not in r.skipped]
        for sj in jr.scenes:
            j = sj.judgements.get(sj.judged_by)
            hj, himg = _hand_judgement(parent, sj.name, hand, sj.judged_by)
            ls = LoaderScene(sj.name, name, hand, sj.judged_by, j, hj, sj.passed, sj.diagnoses, note=sj.note)
            if sj.name in items:  # the renders experiment's scenes: the same judge, perturbed images
                item = items[sj.name]
                img = read_engine_image(r.images[sj.name], sj.engine.shape[1], sj.engine.shape[0])
                pert = replace(img, rgb=img.rgb * POWER_SCALE, readback_stderr=img.readback_stderr * POWER_SCALE)
                ls.power[f"image × {POWER_SCALE:g}"] = judge_against(item, pert, ts)[0][sj.judged_by].fraction_accepted
                if himg is not None and j is not None:
                    sel = np.isfinite(j.z_image)
                    peak = float(np.nanmax(sj.truth[sel])) if sel.any() else float("nan")
                    ls.max_diff_of_peak = float(np.abs(img.rgb - himg)[sel].max() / peak) if sel.any() else float("nan")
            out.scenes.append(ls)
        if name == "filament_gltf" and ORTHO_POWER_SCENE in r.images:
            _ortho_power(out, engine, scenes_dir, work, items, ts)
    return out


def _ortho_power(out: LoaderMeasurements, engine: Any, scenes_dir: Path, work: Path, items: dict[str, Any],
                 ts: Any) -> None:
    """gltfio's own orthographic projection (the page's correction off) on one scene, through the same judge."""
    from ....judge.folder import judge_against

    raw = replace(engine, options={**engine.options, "orthoHalfExtent": False})
    r = raw.render_folder(scenes_dir, [ORTHO_POWER_SCENE], work / "filament_gltf_raw")
    item = items[ORTHO_POWER_SCENE]
    img = read_engine_image(r.images[ORTHO_POWER_SCENE], item.scene.resolution, item.scene.resolution)
    frac = judge_against(item, img, ts)[0][item.references[0]].fraction_accepted
    for ls in out.scenes:
        if ls.engine == "filament_gltf" and ls.scene == ORTHO_POWER_SCENE:
            ls.power["gltfio's own orthographic projection (2/xmag)"] = frac


def agree(ls: LoaderScene) -> bool | None:
    """Whether the loader path and the hand-built path judge the scene alike: the same verdict and fractions
    accepted within their binomial uncertainty (2σ of the pooled fraction over the pixels judged, at least one
    pixel); None without the hand-built judgement."""
    if ls.loader is None or ls.hand_judgement is None:
        return None
    a, b = ls.loader.fraction_accepted, ls.hand_judgement.fraction_accepted
    n = max(ls.loader.n_pixels, 1)
    p = 0.5 * (a + b)
    tol = 2.0 * np.sqrt(max(p * (1 - p), 0.0) * 2.0 / n) + 1.0 / n
    return (a >= MIN_ACCEPTED) == (b >= MIN_ACCEPTED) and abs(a - b) <= tol


__all__ = ["ENGINES", "QUICK_SCENES", "LoaderScene", "LoaderMeasurements", "measure", "agree"]
