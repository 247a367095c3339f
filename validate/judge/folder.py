"""``python -m validate judge IMAGES_DIR --engine NAME``: a folder of images rendered anywhere against Mitsuba.

For every scene of the manifest (``--scenes DIR``, default IMAGES_DIR; :mod:`validate.scenes.manifest`) the image
``<scene>.exr`` or ``<scene>.pfm`` of IMAGES_DIR (:mod:`validate.judge.images`) is judged per pixel against each
reference of the scene's truth, exactly as the ``renders`` experiment judges a hosted engine: the references,
masks and budgets of :mod:`validate.experiments.renders.compute` at the manifest's samples, the per-pixel z-test
with Šidák's correction of :func:`validate.metrics.pixel_z.judge`, the readback's quantisation (half floats) in
quadrature with the truth's standard error. A scene passes when its deciding reference (the manifest's
``judged_by``) accepts at least ``MIN_ACCEPTED`` of its pixels.

The manifest's ``gltf_scenes`` (the scenes the suite authors as glTF files, :mod:`validate.scenes.gltf_scenes`)
are judged the way ``judge --gltf`` judges a user's file (:func:`judge_gltf_scene`): the truth traced from the
``.glb`` itself (:mod:`validate.reference.gltf_truth`) under its environment file, at the entry's samples, with
the budget of the suite's direct-lit scenes. An entry whose truth is the full light transport and which lists the
direct-only truth under ``truth.also`` (the room lit through a skylight) is judged against both: the full truth
decides; the direct-only one gives a figure (:func:`global_illumination`, :mod:`validate.metrics.transport_share`):
the share of the full radiance that global illumination carries, the share the image misses, and whether the
image matches direct-only lighting ("matches direct-only lighting: misses X % ± Y % (global illumination)").

A failed scene gets the diagnoses people need first (:func:`diagnose`): the global scale k that fits the image
to the truth, named when it matches π, 1/π, 4π, 683 … (:mod:`validate.metrics.diagnoses`), and whether dividing
by it passes; for a scene with an environment that is not uniform, the turn, mirror or flip of the environment
that would pass (:mod:`validate.scenes.env_orientation`: the truth rendered with the environment so turned); a
half-pixel shift of the raster that would pass.

Outputs, into ``--out`` (default ``reports/judge_<engine>``): ``results.json`` (the judgements as measured
values under ``experiments.judge.scenes.<scene>.engines.<engine>.judgements``, which ``validate compare``
reads) and ``index.html`` (truth | engine | z-map per scene). Images missing for a scene and image files that
name no scene are listed. Every input is read and checked before anything is traced or written: bad input is
one line, exit 2, nothing written.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..atomic import write_text
from ..errors import ValidateError
from ..experiments.renders.compute import budget, references, truth
from ..experiments.renders.settings import QUICK
from ..metrics.diagnoses import SHIFTS, global_scale, named_factor, shifted
from ..metrics.pixel_z import MIN_ACCEPTED, PixelJudgement, interior_mask, judge
from ..metrics.transport_share import UNLIT_OF_PEAK, missing_share, unlit_mask
from ..reference.gltf_truth import GltfTruth, render_gltf_truth
from ..scenes.env_orientation import VARIANTS, turned_scene, turned_texels, variants_of
from ..scenes.gltf_export import check_glb
from ..scenes.gltf_import import GltfScene, read_gltf
from ..scenes.manifest import SetScene, load_manifest, manifest_scenes, read_exr_rgb
from ..stats import Measured, measured_json, sidak_critical
from .images import IMAGE_SUFFIXES, REFUSED_SUFFIXES, EngineImage, read_engine_image

RESULTS_SCHEMA = "validate-judge/1"
# A half-pixel shift is named when the image resampled back by it accepts this share of the pixels and more than
# any other shift. Not "passes": the bilinear resampling errs by ~f''h²/8, most at the terminator's kink — measured
# on the exact Lambert sphere under the sun sampled ½ px off: 96.7 % accepted at 16², 97.7 % at 32² for the right
# shift, at most 21 % for the seven wrong ones and 6–18 % unshifted.
SHIFT_NAMED_MIN = 0.95
ENGINE_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+-]{0,63}$")


@dataclass
class SceneJudgement:
    """One scene: its judgements by reference, whether it passed, and (when it failed) the diagnoses."""

    name: str
    kind: str
    judged_by: str
    image_file: str
    precision: str
    judgements: dict[str, PixelJudgement]
    truth: np.ndarray  # (R, R, 3) the deciding reference's mean (NaN off the geometry)
    engine: np.ndarray  # (R, R, 3)
    passed: bool
    diagnoses: dict[str, Any] = field(default_factory=dict)
    note: str = ""
    figures: dict[str, Any] = field(default_factory=dict)  # findings that are no verdict (global illumination)
    also: dict[str, np.ndarray] = field(default_factory=dict)  # the means of the truths judged beside (the page)


@dataclass
class JudgeResult:
    engine: str
    scenes: list[SceneJudgement]
    missing: list[str]  # scene names without an image
    extra: list[str]  # image files that name no scene
    manifest: dict[str, Any]
    out: Path | None = None

    @property
    def failed(self) -> list[str]:
        return [s.name for s in self.scenes if not s.passed]

    @property
    def passed(self) -> bool:
        return not self.failed and not self.missing

    def summary(self) -> str:
        n = len(self.scenes)
        return (f"{self.engine}: {n - len(self.failed)}/{n} scenes pass"
                + (f"; failed: {', '.join(self.failed)}" if self.failed else "")
                + (f"; missing images: {', '.join(self.missing)}" if self.missing else "")
                + (f"; extra files: {', '.join(self.extra)}" if self.extra else ""))


def check_engine_name(name: str) -> None:
    """A well-formed name: a registered engine's (:mod:`validate.local_models.render.registry`) or an outside one's."""
    if not isinstance(name, str) or not ENGINE_NAME.fullmatch(name):
        raise ValidateError(f"--engine {name!r}: not an engine name (letters, digits, _ . + -; at most 64, "
                            f"starting with a letter or digit)")


def engine_identity(name: str) -> dict[str, Any] | None:
    """What the registry knows of the engine ``name`` (product, version, precision, known defects), or None for an
    engine the suite does not host (judged all the same: its images say what they are)."""
    from ..local_models.render import registry

    e = registry.find(name)
    if e is None:
        return None
    return {"product": registry.product(name), "version": e.version(), "precision": e.precision,
            "defects": dict(e.defects)}


def find_images(images_dir: Path, entries: list[dict[str, Any]],
                ignore: set[str]) -> tuple[dict[str, Path], list[str], list[str]]:
    """(scene → its image file, scenes without one, files that name no scene); ``ignore``: the scene folder's own
    files (environments) when it is the image folder."""
    if not images_dir.is_dir():
        raise ValidateError(f"{images_dir}: no such folder" if not images_dir.exists() else
                            f"{images_dir}: not a folder")
    files = {p.name: p for p in images_dir.iterdir() if p.is_file()}
    found: dict[str, Path] = {}
    missing: list[str] = []
    used: set[str] = set()
    for e in entries:
        cands = [f"{e['name']}{s}" for s in (*IMAGE_SUFFIXES, *REFUSED_SUFFIXES)]
        have = [c for c in cands if c in files]
        if len(have) > 1:
            raise ValidateError(f"{images_dir}: scene {e['name']!r} has {len(have)} images ({', '.join(have)}): "
                                f"keep one")
        if have:
            found[e["name"]] = files[have[0]]
            used.add(have[0])
        else:
            missing.append(e["name"])
    image_like = (*IMAGE_SUFFIXES, *REFUSED_SUFFIXES)
    extra = sorted(n for n, p in files.items() if p.suffix.lower() in image_like and n not in used and n not in ignore)
    return found, missing, extra


def truth_settings(manifest: dict[str, Any]) -> Any:
    """The renders settings the truth is traced at (the manifest's ``truth_samples``)."""
    return replace(QUICK, **{k: int(v) for k, v in manifest["truth_samples"].items()})


def judge_against(item: SetScene, img: EngineImage, s: Any, scene: Any = None
                  ) -> tuple[dict[str, PixelJudgement], dict[str, tuple[np.ndarray, np.ndarray, int]], np.ndarray]:
    """Judgements of ``img`` against every reference of ``item`` (of ``scene`` when given: a turned variant);
    also the truths and the mask."""
    sc = scene if scene is not None else item.scene
    refs, hit = references(sc, item.kind, s)
    truths = {k: truth(refs[k], hit, s.passes) for k in item.references}
    mask = interior_mask(hit, img.coverage)
    out = {}
    for k, (m, se, dof) in truths.items():
        b, text = budget(item.kind, m)
        out[k] = judge(img.rgb, m, np.sqrt(se**2 + img.readback_stderr**2), dof, mask, b, text)
    return out, truths, mask


def _passes(j: PixelJudgement) -> bool:
    return j.fraction_accepted >= MIN_ACCEPTED


def scale_diagnosis(img: EngineImage, m: np.ndarray, se: np.ndarray, dof: int, mask: np.ndarray,
                    b: np.ndarray | float, text: str) -> dict[str, Any]:
    """The global scale k of the image against the truth m ± se (named when it matches a constant) and whether
    the image divided by it passes."""
    n = int(mask.sum())
    zc = sidak_critical(3 * n, 0.01)
    sig = np.sqrt(se**2 + img.readback_stderr**2 + (np.broadcast_to(np.asarray(b, float), m.shape) / zc) ** 2)
    k, u = global_scale(img.rgb, m, sig, mask)
    name = named_factor(k, u)
    j = judge(img.rgb / k, m, np.sqrt(se**2 + (img.readback_stderr / k) ** 2), dof, mask, b, text)
    return {"factor": Measured(k, u).to_json(), "named": name, "passes_when_divided": _passes(j),
            "fraction_accepted_when_divided": j.fraction_accepted,
            "text": (f"the image is {k:.4g} ± {u:.2g} × the truth" + (f" (= {name})" if name else "")
                     + ("; divided by it, it passes" if _passes(j) else "; dividing by it does not pass"))}


def shift_diagnosis(img: EngineImage, m: np.ndarray, se: np.ndarray, dof: int, mask: np.ndarray,
                    b: np.ndarray | float, text: str) -> dict[str, Any]:
    """The half-pixel shifts of the raster tried (:data:`SHIFTS`) and the one named (:data:`SHIFT_NAMED_MIN`)."""
    inner = interior_mask(mask, np.ones(mask.shape), edge_px=1)  # resampling mixes in the next pixel
    tried = []
    for dy, dx in SHIFTS:
        js = judge(shifted(img.rgb, dy, dx), m, np.sqrt(se**2 + shifted(img.readback_stderr, dy, dx) ** 2), dof,
                   inner, b, text)
        tried.append({"dy": dy, "dx": dx, "fraction_accepted": js.fraction_accepted, "passes": _passes(js)})
    best = max(tried, key=lambda t: t["fraction_accepted"])
    named = best if best["fraction_accepted"] >= SHIFT_NAMED_MIN else None
    return {"tried": tried, "named": None if named is None else [named["dy"], named["dx"]], "text": (
        f"the image matches the truth shifted by ({named['dy']:+g}, {named['dx']:+g}) px (rows, columns): engine "
        f"pixel (i, j) shows the truth at (i {named['dy']:+g}, j {named['dx']:+g}) ({named['fraction_accepted']:.1%} "
        f"of the pixels accepted once resampled back)" if named else "no half-pixel shift explains it")}


def diagnose(item: SetScene, img: EngineImage, s: Any, truths: dict[str, tuple[np.ndarray, np.ndarray, int]],
             mask: np.ndarray) -> dict[str, Any]:
    """Scale, environment orientation and raster shift (module docstring) for the deciding reference."""
    key = item.references[0]
    m, se, dof = truths[key]
    b, text = budget(item.kind, m)
    out: dict[str, Any] = {"scale": scale_diagnosis(img, m, se, dof, mask, b, text)}
    env = []
    for variant in variants_of(item.scene):
        jv, _, _ = judge_against(item, img, s, turned_scene(item.scene, variant))
        env.append({"variant": variant, "fraction_accepted": jv[key].fraction_accepted, "passes": _passes(jv[key])})
    if env:
        hits = [e["variant"] for e in env if e["passes"]]
        out["environment"] = {"tried": env, "passes_with": hits,
                              "text": (f"the image matches the truth with the environment {hits[0]}" if hits else
                                       "no turn, mirror or flip of the environment passes")}
    out["raster_shift"] = shift_diagnosis(img, m, se, dof, mask, b, text)
    return out


GLTF_BUDGET_KIND = "directional"  # the budget of the suite's direct-lit scenes (0.25 % of the peak radiance)


def global_illumination(img: EngineImage, direct: GltfTruth, full: GltfTruth, mask: np.ndarray,
                        jd: PixelJudgement) -> dict[str, Any]:
    """The figure of a scene judged against its full-transport truth with the direct-only one beside
    (:mod:`validate.metrics.transport_share`): the share of the full radiance the direct-only truth lacks (global
    illumination) over the judged pixels and over those the direct light does not reach, the share the image
    misses over both, and whether the image matches the direct-only truth (``jd``, its judgement). A finding,
    never a verdict."""
    unlit = unlit_mask(direct.mean, mask)
    regions = {"image": mask, **({"unlit": unlit} if unlit.any() else {})}
    hit = full.hit  # the passes are stored over the hit pixels; both truths trace the same rays
    rgb, readback = img.rgb[hit], np.broadcast_to(np.asarray(img.readback_stderr, np.float64), img.rgb.shape)[hit]
    share = {k: missing_share(direct.pass_values, full.pass_values, m[hit]) for k, m in regions.items()}
    miss = {k: missing_share(rgb, full.pass_values, m[hit], readback) for k, m in regions.items()}
    miss = {k: replace(v, better="zero") for k, v in miss.items()}
    n, nu = int(mask.sum()), int(unlit.sum())

    def pct(v: Measured) -> str:
        return f"{100 * v.value:.1f} % ± {100 * v.uncertainty:.2g} %"

    where = (f"; {pct(miss['unlit'])} over the {nu} px ({nu / n:.0%}) the direct light does not reach"
             if "unlit" in miss else "")
    lines = [f"global illumination: {pct(share['image'])} of the full radiance over the {n} judged px bounced more "
             f"than once (the direct-only truth lacks it)"
             + (f"; {pct(share['unlit'])} over the unlit {nu} px" if "unlit" in share else "")]
    if _passes(jd):
        lines.append(f"matches direct-only lighting: misses {pct(miss['image'])} (global illumination){where}")
    else:
        lines.append(f"misses {pct(miss['image'])} of the full radiance{where}; does not match the direct-only "
                     f"truth ({jd.fraction_accepted:.1%} of the pixels accepted)")
    return {"gi_share": share, "engine_missing": miss,
            "unlit_pixels": Measured(nu / n, unit="%", better="zero",
                                     params={"n_pixels": n, "unlit": f"direct truth <= {UNLIT_OF_PEAK:g} x its peak"}),
            "matches_direct": _passes(jd), "direct_judgement": jd.to_json(), "text": lines}


def judge_gltf_scene(scene: GltfScene, img: EngineImage, image_name: str, texels: np.ndarray | None, spp: int,
                     passes: int, seed: int = 0, transport: str = "direct", also: tuple[str, ...] = ()
                     ) -> SceneJudgement:
    """Judge ``img`` against the Mitsuba truth of the glTF ``scene`` (:mod:`validate.reference.gltf_truth`) under
    the environment ``texels``; a failed image gets the scale, the environment's turns and flips (with
    ``texels``) and the half-pixel shifts. With ``transport`` "full" and "direct" in ``also`` the image is also
    judged against the direct-only truth, as a figure (:func:`global_illumination`), never deciding."""
    h, w = img.rgb.shape[:2]
    t = render_gltf_truth(scene, w, h, texels, spp, passes, seed, transport)
    m, se, dof = t.mean, t.stderr, t.dof
    try:
        mask = interior_mask(t.hit, img.coverage)
        b, text = budget(GLTF_BUDGET_KIND, m)
        j = judge(img.rgb, m, np.sqrt(se**2 + img.readback_stderr**2), dof, mask, b, text)
    except ValidateError as exc:
        return SceneJudgement(scene.name, "gltf", "mitsuba", image_name, img.precision, {}, m, img.rgb, False,
                              note=str(exc))
    sj = SceneJudgement(scene.name, "gltf", "mitsuba", image_name, img.precision, {"mitsuba": j}, m, img.rgb,
                        _passes(j), note="; ".join(scene.notes))
    if transport == "full" and "direct" in also:
        td = render_gltf_truth(scene, w, h, texels, spp, passes, seed, "direct")
        bd, textd = budget(GLTF_BUDGET_KIND, td.mean)
        jd = judge(img.rgb, td.mean, np.sqrt(td.stderr**2 + img.readback_stderr**2), td.dof, mask, bd, textd)
        sj.figures["global_illumination"] = global_illumination(img, td, t, mask, jd)
        sj.also["direct"] = td.mean
    if sj.passed:
        return sj
    sj.diagnoses = {"scale": scale_diagnosis(img, m, se, dof, mask, b, text)}
    if texels is not None and texels.shape[1] % 4 == 0 and np.ptp(texels) > 0:
        tried = []
        for variant in VARIANTS:
            tv = render_gltf_truth(scene, w, h, turned_texels(texels, variant), spp, passes, seed, transport)
            jv = judge(img.rgb, tv.mean, np.sqrt(tv.stderr**2 + img.readback_stderr**2), dof, mask, b, text)
            tried.append({"variant": variant, "fraction_accepted": jv.fraction_accepted, "passes": _passes(jv)})
        hits = [e["variant"] for e in tried if e["passes"]]
        sj.diagnoses["environment"] = {
            "tried": tried, "passes_with": hits,
            "text": (f"the image matches the truth with the environment {hits[0]}" if hits else
                     "no turn, mirror or flip of the environment passes")}
    sj.diagnoses["raster_shift"] = shift_diagnosis(img, m, se, dof, mask, b, text)
    return sj


def authored_scenes_of(manifest: dict[str, Any], folder: Path) -> dict[str, tuple[GltfScene, np.ndarray | None]]:
    """The manifest's scenes authored as glTF files (``gltf_scenes``), each read back from the folder with its
    environment's texels; a file whose content differs from the manifest's digest is an error naming it."""
    import hashlib

    out = {}
    envs: dict[str, np.ndarray] = {}
    for e in manifest.get("gltf_scenes", []):
        path = folder / e["glb"]
        check_glb(path)
        if hashlib.sha256(path.read_bytes()).hexdigest()[:16] != e["digest"]:
            raise ValidateError(f"{path}: differs from the manifest (digest {e['digest']}): export the scenes again")
        texels = None
        if e["environment"]:
            f = e["environment"]["file"]
            if f not in envs:
                if not (folder / f).is_file():
                    raise ValidateError(f"{folder / f}: no such file (named by {folder / 'manifest.json'})")
                envs[f] = read_exr_rgb(folder / f)
            texels = envs[f]
        out[e["name"]] = (read_gltf(path), texels)
    return out


def judge_folder(images_dir: Path | str, engine: str, scenes_dir: Path | str | None = None) -> JudgeResult:
    """Judge every manifest scene's image in ``images_dir`` (module docstring); nothing is written."""
    check_engine_name(engine)
    images_dir = Path(images_dir)
    scenes_dir = Path(scenes_dir) if scenes_dir is not None else images_dir
    manifest = load_manifest(scenes_dir)
    mpath = scenes_dir / "manifest.json" if scenes_dir.is_dir() else scenes_dir
    pairs = manifest_scenes(manifest, mpath)
    for e in manifest["scenes"]:  # the scene folder is whole: every file the manifest names is there and reads
        check_glb(mpath.parent / e["glb"])
        if e["environment"] and not (mpath.parent / e["environment"]["file"]).is_file():
            raise ValidateError(f"{mpath.parent / e['environment']['file']}: no such file (named by {mpath})")
    authored = authored_scenes_of(manifest, mpath.parent)
    entries = manifest["scenes"] + manifest.get("gltf_scenes", [])
    own = {e["environment"]["file"] for e in entries if e["environment"]}
    found, missing, extra = find_images(images_dir, entries,
                                        own if images_dir.resolve() == mpath.parent.resolve() else set())
    if not found:
        raise ValidateError(f"{images_dir}: no image of any scene of {mpath} (expected e.g. "
                            f"{manifest['scenes'][0]['image']['expected']})")
    images = {e["name"]: read_engine_image(found[e["name"]], e["image"]["width"], e["image"]["height"])
              for e in entries if e["name"] in found}  # every image checked before anything is traced
    s = truth_settings(manifest)
    scenes = []
    for e, item in pairs:
        img = images.get(e["name"])
        if img is None:
            continue
        key = item.references[0]
        try:
            js, truths, mask = judge_against(item, img, s)
        except ValidateError as exc:  # no covered pixel inside the outline: nothing to judge, a failure
            scenes.append(SceneJudgement(e["name"], item.kind, key, found[e["name"]].name, img.precision, {},
                                         np.full(img.rgb.shape, np.nan), img.rgb, False, note=str(exc)))
            continue
        sj = SceneJudgement(e["name"], item.kind, key, found[e["name"]].name, img.precision, js, truths[key][0],
                            img.rgb, _passes(js[key]))
        if not sj.passed:
            sj.diagnoses = diagnose(item, img, s, truths, mask)
        scenes.append(sj)
    for e in manifest.get("gltf_scenes", []):
        img = images.get(e["name"])
        if img is not None:
            scene, texels = authored[e["name"]]
            t = e["truth"]
            scenes.append(judge_gltf_scene(scene, img, found[e["name"]].name, texels, t["spp"], t["passes"],
                                           t["seed"], t["transport"], tuple(a["transport"] for a in t.get("also", []))))
    return JudgeResult(engine, scenes, missing, extra, manifest)


def results_json(r: JudgeResult, images_dir: Path, scenes_dir: Path) -> dict[str, Any]:
    """The results file: measured values where ``validate compare`` reads judgements."""
    scenes = {}
    for sj in r.scenes:
        scenes[sj.name] = {
            "kind": sj.kind, "judged_by": sj.judged_by, "passed": sj.passed, "image": sj.image_file,
            "precision": sj.precision, **({"note": sj.note} if sj.note else {}),
            "engines": {r.engine: {"judgements": {k: j.to_json() for k, j in sj.judgements.items()},
                                   "diagnoses": sj.diagnoses, **measured_json(sj.figures)}}}
    m = r.manifest
    return {"schema": RESULTS_SCHEMA, "engine": r.engine, "registered": engine_identity(r.engine),
            "images": str(images_dir), "scenes": str(scenes_dir),
            "manifest": {"schema": m["schema"], "set": m["set"], "resolution": m["resolution"],
                         "truth_samples": m["truth_samples"]},
            "passed": r.passed, "summary": r.summary(), "missing": r.missing, "extra": r.extra,
            "experiments": {"judge": {"title": f"{r.engine} judged against Mitsuba", "claims": [],
                                      "scenes": scenes}}}


def write_outputs(r: JudgeResult, out: Path, images_dir: Path, scenes_dir: Path) -> None:
    """``results.json`` and ``index.html`` into ``out`` (each atomically; the page is built first)."""
    from .page import judge_page

    if out.exists() and not out.is_dir():
        raise ValidateError(f"{out}: exists and is not a folder")
    html = judge_page(r)
    doc = results_json(r, images_dir, scenes_dir)
    write_text(out / "results.json", json.dumps(doc, indent=1, ensure_ascii=False, allow_nan=False) + "\n")
    write_text(out / "index.html", html)
    r.out = out


def run_judge(images_dir: Path, engine: str, scenes_dir: Path | None, out: Path | None, strict: bool) -> int:
    """The command: judge, write, print one line per scene and the summary; exit 1 under ``strict`` when a scene
    failed or lacks its image."""
    r = judge_folder(images_dir, engine, scenes_dir)
    out = out if out is not None else Path("reports") / f"judge_{engine}"
    write_outputs(r, out, images_dir, scenes_dir if scenes_dir is not None else images_dir)
    print_result(r, out)
    return 1 if strict and not r.passed else 0


def print_result(r: JudgeResult, out: Path) -> None:
    """One line per scene (and its diagnoses), the missing and extra files, the summary."""
    for sj in r.scenes:
        j = sj.judgements.get(sj.judged_by)
        head = (f"{sj.name}: {'pass' if sj.passed else 'FAIL'}" +
                (f" ({j.fraction_accepted:.2%} of {j.n_pixels} px accepted vs {sj.judged_by})" if j else
                 f" ({sj.note})"))
        print(head)
        for f in sj.figures.values():
            for line in f["text"]:
                print(f"  {line}")
        for d in sj.diagnoses.values():
            print(f"  {d['text']}")
    for name in r.missing:
        print(f"{name}: no image")
    for name in r.extra:
        print(f"{name}: names no scene of the manifest")
    print(f"{r.summary()} -> {out / 'index.html'}")
