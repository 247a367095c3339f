"""The glTF Sample Viewer's pixels, numbers only: ``scenes export`` → the viewer's ``render_folder`` → the per-pixel
judgement against the parent's references (the same Mitsuba images, masks' outlines and budgets the other engines
are judged with, :func:`validate.experiments.renders.compute.budget`), the viewer's 8-bit readback carried per pixel
as an uncertainty in quadrature (:func:`validate.local_models.render.khronos_viewer.readback_stderr`).

Which scenes: ``Settings.khronos_scenes`` (names shared by the export and the parent's scenes). Without the npm
package or Chromium the part records why and renders nothing.
"""

from __future__ import annotations

import dataclasses
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ....local_models.render import khronos_viewer as kv
from ....local_models.render.blender import read_exr_rgba
from ....metrics.pixel_z import PixelJudgement, interior_mask, judge
from ....scenes.manifest import export_scenes
from ..settings import Settings


@dataclass
class KhronosScene:
    name: str
    kind: str
    image: np.ndarray  # (R, R, 3) decoded radiance, row 0 = top
    coverage: np.ndarray
    readback_stderr: np.ndarray  # (R, R, 3) σ of the 8-bit gamma readback
    mask: np.ndarray
    judgements: dict[str, PixelJudgement]
    energy: float  # mean radiance over the mask
    info: dict[str, Any]
    frame_ms: float


@dataclass
class KhronosPart:
    version: str | None
    skipped: str = ""  # why nothing was rendered, or ""
    scenes: dict[str, KhronosScene] = field(default_factory=dict)
    not_rendered: dict[str, str] = field(default_factory=dict)
    ibl: dict[str, Any] = field(default_factory=dict)  # the IBL sampler's fields used
    export_s: float = 0.0
    startup_s: float = 0.0
    wall_s: float = 0.0
    total_s: float = 0.0  # the whole part: availability check, export, renders, judgements
    parent_scenes: dict[str, Any] = field(default_factory=dict)  # name → the parent's SceneResult (references)
    budget: Callable | None = None  # the parent's per-pixel budget (kind, mean) → (b, text)


def judged_stderr(sr: Any, key: str, ks: KhronosScene) -> np.ndarray:
    """The reference's standard error and the viewer's readback σ in quadrature."""
    return np.sqrt(sr.stderrs[key] ** 2 + ks.readback_stderr**2)


def compute_khronos(ctx: Any, s: Settings, parent_scenes: list[Any], budget: Callable) -> KhronosPart:
    """Export, render with the viewer, judge against ``parent_scenes``' references with the parent's ``budget``
    (kind, mean) → (b, text) (module docstring)."""
    t_part = time.perf_counter()
    eng = dataclasses.replace(kv.ENGINE, ibl=dict(kv.IBL_QUICK if s.khronos_ibl == "quick" else kv.IBL_SUITE))
    part = KhronosPart(eng.version(), ibl=dict(eng.ibl), budget=budget)
    by_name = {sr.scene.name: sr for sr in parent_scenes}
    part.parent_scenes = {n: by_name[n] for n in s.khronos_scenes if n in by_name}
    names = [n for n in s.khronos_scenes if n in by_name]
    part.not_rendered = {n: "not among the renders scenes of this run" for n in s.khronos_scenes if n not in by_name}
    if not names:
        part.skipped = "no scene to render (Settings.khronos_scenes)"
        return part
    why = eng.unavailable()
    if why is not None:
        part.skipped = f"{why.piece}: {why.why} (fix: {why.fix})"
        return part
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="validate-khronos-") as d:
        scenes_dir, out_dir = Path(d) / "scenes", Path(d) / "images"
        export_scenes(scenes_dir, "quick", s.resolution)
        part.export_s = time.perf_counter() - t0
        try:
            fr = eng.render_folder(scenes_dir, names, out_dir)
        except Exception as exc:  # a viewer that cannot start is recorded with its reason, never a crash
            part.skipped = " ".join(f"{type(exc).__name__}: {exc}".split())[:300]
            return part
        part.not_rendered.update(fr.skipped)
        part.startup_s, part.wall_s = fr.startup_s, fr.wall_s
        for n, path in fr.images.items():
            sr = by_name[n]
            rgba = read_exr_rgba(path).astype(np.float64)
            img, cov = rgba[..., :3], rgba[..., 3]
            info = fr.info[n]
            hit = np.isfinite(next(iter(sr.references.values()))[..., 0])
            mask = interior_mask(hit, cov)
            ks = KhronosScene(n, str(sr.kind), img, cov, kv.readback_stderr(img, info["exposure"]), mask, {},
                              float("nan"), info, fr.frame_ms[n])
            for k, m in sr.references.items():
                b, text = budget(sr.kind, m)
                ks.judgements[k] = judge(img, m, judged_stderr(sr, k, ks), sr.dof, mask, b, text)
            ks.energy = float(img[mask].mean()) if mask.any() else float("nan")
            part.scenes[n] = ks
    part.total_s = time.perf_counter() - t_part
    return part
