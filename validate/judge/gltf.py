"""A user's own glTF: ``python -m validate scenes truth MY.glb`` writes its Mitsuba truth, ``python -m validate judge
IMAGES --gltf MY.glb`` judges an engine's image of it.

The file is read by :func:`validate.scenes.gltf_import.read_gltf` (unsupported features are one line naming them);
the truth is :func:`validate.reference.gltf_truth.render_gltf_truth` (P seeded passes → mean and standard error per
pixel centre, cached by content hash), the environment (``--env``, an equirect .exr/.hdr/.pfm, 2:1) in the
orientation of :mod:`validate.scenes.env_orientation`. The judge is the exported scenes' (:mod:`.folder`): the
per-pixel z-test with Šidák's correction (:func:`validate.metrics.pixel_z.judge`) on the pixels 2 px or more
inside the meshes' outline and covered by the engine, the truth's standard error and the image's quantisation in
quadrature, and the budget of the suite's direct-lit scenes (0.25 % of the peak radiance, a measured margin:
``validate.experiments.renders.compute.DIRECT_BUDGET_OF_PEAK``). A failed image gets the diagnoses: the global
scale (named when it is π, 683, 2 …), the environment turned, mirrored or flipped (with ``--env``), a half-pixel
shift.

The image is ``IMAGES/<file stem>.exr`` (or ``.pfm``), or IMAGES is the image file itself; its size is the
truth's. ``scenes truth`` writes ``<stem>.exr`` (RGB = the truth's mean, 0 where no mesh is hit; A = the hit mask)
and ``<stem>.stderr.exr`` (the per-pixel standard error) and ``truth.json`` (settings, notes, the file's digest)
into ``--out``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from ..atomic import atomic_path, write_text
from ..errors import ValidateError
from ..reference.gltf_truth import TRANSPORTS, GltfTruth, render_gltf_truth
from ..scenes.gltf_import import GltfScene, read_gltf
from .folder import (
    JudgeResult,
    check_engine_name,
    judge_gltf_scene,
    print_result,
    write_outputs,
)
from .images import IMAGE_SUFFIXES, REFUSED_SUFFIXES, image_size, read_engine_image, write_exr

DEFAULT_SPP, DEFAULT_PASSES = 64, 8


def load_env(path: Path | str | None) -> np.ndarray | None:
    """(H, W, 3) equirect radiance of ``--env`` (2:1, the suite's loader and its checks), or None."""
    if path is None:
        return None
    from ..scenes.loaders import load_environment

    return np.asarray(load_environment(Path(path), "latlong", False).radiance, np.float64)


def find_image(images: Path, stem: str) -> Path:
    """The image of the scene ``stem``: ``images`` itself when it is a file, else ``<stem>.exr|.pfm`` in it."""
    if images.is_file():
        return images
    if not images.is_dir():
        raise ValidateError(f"{images}: no such file or folder")
    have = [images / f"{stem}{s}" for s in (*IMAGE_SUFFIXES, *REFUSED_SUFFIXES) if (images / f"{stem}{s}").is_file()]
    if not have:
        raise ValidateError(f"{images}: no image {stem}.exr or {stem}.pfm (the glTF file's name)")
    if len(have) > 1:
        raise ValidateError(f"{images}: {len(have)} images of {stem} ({', '.join(p.name for p in have)}): keep one")
    return have[0]


def judge_gltf(images: Path | str, gltf: Path | str, engine: str, env: Path | str | None = None,
               spp: int = DEFAULT_SPP, passes: int = DEFAULT_PASSES, seed: int = 0,
               transport: str = "direct") -> tuple[JudgeResult, GltfScene]:
    """Judge the engine's image of ``gltf`` (module docstring); nothing is written. Every input is read and checked
    before anything is traced."""
    check_engine_name(engine)
    scene = read_gltf(gltf)
    texels = load_env(env)
    path = find_image(Path(images), scene.name)
    w, h = image_size(path)
    img = read_engine_image(path, w, h)
    sj = judge_gltf_scene(scene, img, path.name, texels, spp, passes, seed, transport)
    manifest = {"schema": "glTF (a user's file)", "set": Path(gltf).name, "resolution": [w, h],
                "truth_samples": {"spp": spp, "passes": passes, "seed": seed, "transport": transport},
                "gltf": {"file": str(gltf), "digest": scene.digest, "notes": scene.notes,
                         "environment": None if env is None else str(env)}}
    return JudgeResult(engine, [sj], [], [], manifest), scene


def run_judge_gltf(images: Path, gltf: Path, engine: str, env: Path | None, out: Path | None, strict: bool,
                   spp: int, passes: int, transport: str) -> int:
    """The command ``judge IMAGES --gltf FILE``: judge, write results.json and index.html, print the verdict."""
    r, scene = judge_gltf(images, gltf, engine, env, spp, passes, 0, transport)
    out = out if out is not None else Path("reports") / f"judge_{engine}"
    write_outputs(r, out, images, gltf)
    for note in scene.notes:
        print(f"note: {note}")
    print_result(r, out)
    return 1 if strict and not r.passed else 0


def parse_size(text: str | None) -> tuple[int | None, int | None]:
    """``--size`` "WxH" or "H" (the width from the camera's aspect) → (height, width); None: the default."""
    if text is None:
        return None, None
    try:
        if "x" in text.lower():
            w, h = (int(v) for v in text.lower().split("x"))
            return h, w
        return int(text), None
    except ValueError:
        raise ValidateError(f"--size {text}: expected WxH or H (pixels)") from None


def write_truth(t: GltfTruth, scene: GltfScene, out: Path, settings: dict[str, Any]) -> list[Path]:
    """``<stem>.exr`` (mean, A = hit), ``<stem>.stderr.exr`` and ``truth.json`` into ``out`` (each atomically)."""
    if out.exists() and not out.is_dir():
        raise ValidateError(f"{out}: exists and is not a folder")
    files = []
    for name, rgb in ((f"{scene.name}.exr", t.mean), (f"{scene.name}.stderr.exr", t.stderr)):
        with atomic_path(out / name, suffix=".exr") as tmp:
            write_exr(tmp, np.nan_to_num(rgb, nan=0.0), t.hit.astype(np.float64))
        files.append(out / name)
    doc = {"schema": "validate-gltf-truth/1", "gltf": str(scene.path), "digest": scene.digest,
           "image": {"width": t.mean.shape[1], "height": t.mean.shape[0], "row0": "top"},
           "camera": scene.camera.key(), "settings": settings, "integrator": TRANSPORTS[settings["transport"]],
           "pixels_hit": int(t.hit.sum()), "notes": scene.notes,
           "files": {"mean": files[0].name, "stderr": files[1].name},
           "peak": float(np.nanmax(t.mean)), "max_stderr": float(np.nanmax(t.stderr))}
    write_text(out / "truth.json", json.dumps(doc, indent=1, ensure_ascii=False) + "\n")
    return [*files, out / "truth.json"]


def run_truth(gltf: Path, env: Path | None, out: Path | None, size: str | None, spp: int, passes: int,
              transport: str) -> int:
    """The command ``scenes truth FILE``: trace and write the truth (module docstring)."""
    scene = read_gltf(gltf)
    texels = load_env(env)
    height, width = parse_size(size)
    w, h = scene.image_size(height, width)
    t = render_gltf_truth(scene, w, h, texels, spp, passes, 0, transport)
    out = out if out is not None else Path("reports") / f"truth_{scene.name}"
    settings = {"spp": spp, "passes": passes, "seed": 0, "transport": transport,
                "environment": None if env is None else str(env)}
    files = write_truth(t, scene, out, settings)
    for note in scene.notes:
        print(f"note: {note}")
    print(f"{gltf}: {w}x{h} px, {int(t.hit.sum())} hit, {passes} passes x {spp} spp ({transport}); peak "
          f"{np.nanmax(t.mean):.4g}, max standard error {np.nanmax(t.stderr):.2g} -> {', '.join(map(str, files))}")
    return 0
