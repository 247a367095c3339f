"""``check_render(render_fn, scenes=...)``: an engine team's CI judges its renderer per pixel against Mitsuba.

``render_fn(scene)`` receives a :class:`validate.scenes.render_scenes.RenderScene` (use
``scene.engine_json()`` for a plain-JSON description: camera, sphere, glTF material, KHR lights, environment
texels) and returns an (R, R, 3) or (R, R, 4) float image of linear radiance, row 0 = top, pixel centres
as :meth:`RenderScene.pixel_centres` (an orthographic camera without MSAA). Each scene is judged with
:func:`validate.metrics.pixel_z.judge` against Mitsuba's pixel-centre reference (the furnace against its
exact value 1) and returns the fraction of pixels accepted and the relative errors ± uncertainty.

Bad output raises :class:`validate.errors.ValidateError` naming the scene.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ValidateError
from ..experiments.renders.compute import budget, references, truth
from ..judge.folder import JudgeResult, judge_folder
from ..metrics.pixel_z import MIN_ACCEPTED, PixelJudgement, interior_mask, judge
from ..scenes import render_scenes as rs


@dataclass
class RenderCheck:
    scene: str
    reference: str
    judgement: PixelJudgement

    @property
    def passed(self) -> bool:
        return self.judgement.fraction_accepted >= MIN_ACCEPTED

    def summary(self) -> str:
        j = self.judgement
        return (f"{self.scene} vs {self.reference}: {j.fraction_accepted:.2%} of {j.n_pixels} px accepted, mean |rel| "
                f"{j.mean_rel:.3%} ± {j.mean_rel_unc:.1e}, max {j.max_rel:.3%} ± {j.max_rel_unc:.1e}")


def default_scenes(resolution: int = 32) -> list[tuple[rs.RenderScene, str]]:
    """The directional Lambertian sphere and the white-metal furnace at roughness 0.5."""
    return [(rs.lambert_sun_scene(resolution), "directional"),
            (rs.furnace_scenes(resolution, (0.5,))[1], "furnace")]


def _image(out: object, scene: rs.RenderScene) -> tuple[np.ndarray, np.ndarray]:
    a = np.asarray(out, dtype=np.float64)
    r = scene.resolution
    if a.ndim != 3 or a.shape[:2] != (r, r) or a.shape[2] not in (3, 4):
        raise ValidateError(f"{scene.name}: render_fn returned shape {a.shape}; expected ({r}, {r}, 3 or 4)")
    if not np.all(np.isfinite(a)):
        raise ValidateError(f"{scene.name}: render_fn returned NaN/Inf pixels")
    cov = a[..., 3] if a.shape[2] == 4 else np.ones((r, r))
    return a[..., :3], cov


def check_render(render_fn: Callable[[rs.RenderScene], object],
                 scenes: Sequence[tuple[rs.RenderScene, str]] | None = None, spp: int = 16, passes: int = 8,
                 seed: int = 0) -> list[RenderCheck]:
    """Judge ``render_fn`` on each (scene, kind) (kind "furnace", "directional", "point", "spot" or "hemisphere",
    as :func:`validate.experiments.renders.compute.scene_list` pairs them); see the module docstring."""
    out = []
    for scene, kind in scenes if scenes is not None else default_scenes():
        refs, hit = references(scene, kind, _Settings(spp, passes, seed))
        if kind == "spot":  # KHR_lights_punctual's reference falloff; three's smoothstep is the experiment's second one
            refs = {"mitsuba": refs["mitsuba"]}
        img, cov = _image(render_fn(scene), scene)
        mask = interior_mask(hit, cov)
        for name, ref in refs.items():
            m, se, dof = truth(ref, hit, passes)
            b, text = budget(kind, m)
            out.append(RenderCheck(scene.name, name, judge(img, m, se, dof, mask, b, text)))
    return out


@dataclass(frozen=True)
class _Settings:
    spp: int
    passes: int
    seed: int

    @property
    def env_spp(self) -> int:
        return self.spp


__all__ = ["check_render", "check_render_folder", "RenderCheck", "default_scenes"]


def check_render_folder(images_dir: str | Path, engine: str = "engine",
                        scenes: str | Path | None = None) -> JudgeResult:
    """An engine team's CI on images rendered anywhere: ``images_dir`` holds ``<scene>.exr`` (or ``.pfm``) for the
    scenes of ``scenes`` (a folder written by ``python -m validate scenes export``; default ``images_dir``), judged
    as ``python -m validate judge`` does (:func:`validate.judge.folder.judge_folder`) without writing anything.
    ``r.passed`` (every scene passed, none missing), ``r.failed``, ``r.missing``, ``r.summary()``; each scene's
    judgements and diagnoses in ``r.scenes``. Bad input raises :class:`~validate.errors.ValidateError`::

        def test_my_engine():
            r = check_render_folder("out/images", engine="myengine", scenes="out/scenes")
            assert r.passed, r.summary()
    """
    return judge_folder(images_dir, engine, scenes)
