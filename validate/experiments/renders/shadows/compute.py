"""(e) Shadows, numbers only: the path-traced penumbra of :mod:`validate.scenes.render_shadow_scenes` and every engine's
shadow types, judged per pixel by region and measured as a penumbra width and a light leak.

Per scene: the Mitsuba reference (``shadow_spp`` × ``passes``, cached as every render reference), the unshadowed
radiance ρE/π (closed form, :func:`~validate.scenes.render_shadow_scenes.unshadowed_radiance`) and the regions lit /
penumbra / umbra from the geometric visibility of the light's disc (:func:`~validate.scenes.render_shadow_scenes.
regions`). Per engine × shadow type:

* the per-pixel judgement (:func:`validate.metrics.pixel_z.judge`, budget 0.25 % of the peak radiance, the plane's
  measured margin of the other scenes) on all judged pixels and on each region, with the engine's readback
  uncertainty σ_q (Filament's 8-bit canvas: ±½ LSB uniform, :attr:`validate.local_models.render.EngineRender.stderr`;
  0 for the float targets of three/Babylon) as a known, ∞-dof term (:func:`judged_budget`: folded into the budget,
  whose term :func:`~validate.metrics.pixel_z.welch_z` gives ∞ dof — put into the 7-dof sample standard error it
  would be read through Student's t with 7 dof and let a 2 % error through: measured (FULL, 64²), Filament's spot
  lit plane × 1.02 accepted on 99.88 % of its pixels that way, 37.0 % with σ_q as a known term, 3.6 % without σ_q);
* the shadow factor s = mean-channel radiance / ρE/π; the *penumbra width* W = #{judged px : 0.1 < s < 0.9} (the
  10–90 % transition, an area in px: the edge length is the truth's, so W_engine/W_truth is the width ratio), the
  truth's W ± its standard deviation over ``WIDTH_DRAWS`` parametric redraws s + σ_s·N(0, 1) of the reference noise;
* the *light leak* (three issue 23551): over the umbra (truth exactly 0: every sample of the light is blocked),
  the fraction of pixels brighter than the budget — lit pixels in the umbra — ± its binomial standard error
  √(p(1 − p)/n), and the mean s ± its standard error over the umbra's pixels.
"""

from __future__ import annotations

from concurrent.futures import Future
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ....local_models.render import registry
from ....metrics.pixel_z import ALPHA, PixelJudgement, interior_mask, judge, sidak_critical
from ....reference.render_reference import render_reference
from ....scenes import render_shadow_scenes as rss
from .. import images
from ..settings import Settings

SHADOW_BUDGET_OF_PEAK = 2.5e-3  # the plane's per-pixel budget of the other scenes (compute.DIRECT_BUDGET_OF_PEAK)
WIDTH_LEVELS = (0.1, 0.9)  # the 10–90 % transition of the shadow factor
WIDTH_DRAWS = 64
REGIONS = ("all", "lit", "penumbra", "umbra")


@dataclass
class ShadowEngineResult:
    engine: str
    shadow_type: str
    used: str  # the type the engine reports it used (three: PCFSoft → PCF)
    image: np.ndarray  # (R, R, 3)
    frame_ms: float
    wall_s: float
    judgements: dict[str, PixelJudgement] = field(default_factory=dict)  # region → judgement
    width_px: float = float("nan")
    leak: tuple[float, float] = (float("nan"), 0.0)  # fraction of umbra pixels lit ± binomial s.e.
    umbra_mean: tuple[float, float] = (float("nan"), 0.0)  # mean shadow factor in the umbra ± s.e.
    readback_stderr: float = 0.0  # the engine readback's standard uncertainty per value (radiance)
    info: dict[str, Any] = field(default_factory=dict)  # what the page reports besides pixels


@dataclass
class ShadowSceneResult:
    scene: rss.ShadowScene
    mean: np.ndarray
    stderr: np.ndarray
    dof: int
    unshadowed: np.ndarray  # (R, R) ρE/π
    regions: dict[str, np.ndarray]  # region → (R, R) bool, already ∩ the judged mask
    budget: float
    truth_width: tuple[float, float]  # px ± s.d. over redraws
    results: list[ShadowEngineResult] = field(default_factory=list)
    skipped: dict[str, str] = field(default_factory=dict)
    reference_s: float = 0.0


def shadow_factor(image: np.ndarray, unshadowed: np.ndarray) -> np.ndarray:
    """(R, R) s = mean over channels of the radiance / ρE/π."""
    return image.mean(axis=-1) / unshadowed


def transition_px(s: np.ndarray, mask: np.ndarray) -> float:
    lo, hi = WIDTH_LEVELS
    return float(((s > lo) & (s < hi) & mask).sum())


def truth_width(sr: ShadowSceneResult, seed: int) -> tuple[float, float]:
    """W of the reference ± its s.d. over parametric redraws of the reference noise (module docstring)."""
    s = shadow_factor(sr.mean, sr.unshadowed)
    se = np.sqrt((sr.stderr**2).sum(axis=-1)) / 3.0 / sr.unshadowed
    rng = np.random.default_rng(seed)
    draws = [transition_px(s + se * rng.standard_normal(s.shape), sr.regions["all"]) for _ in range(WIDTH_DRAWS)]
    return transition_px(s, sr.regions["all"]), float(np.std(draws, ddof=1))


def judged_budget(sr: ShadowSceneResult, mask: np.ndarray, readback_stderr: float = 0.0) -> float:
    """The budget b with the readback's σ_q folded in: b' = √(b² + (z*·σ_q)²), z* = the Šidák critical value of
    :func:`~validate.metrics.pixel_z.judge` on ``mask`` (3 channels), so that judge's σ² = s² + (b'/z*)² =
    s² + (b/z*)² + σ_q² with σ_q a known term (∞ dof; module docstring). b' = b when σ_q = 0."""
    if not readback_stderr:
        return sr.budget
    zc = sidak_critical(3 * int(mask.sum()), ALPHA)
    return float(np.hypot(sr.budget, zc * readback_stderr))


def judge_regions(image: np.ndarray, sr: ShadowSceneResult, readback_stderr: float = 0.0) -> dict[str, PixelJudgement]:
    text = f"{SHADOW_BUDGET_OF_PEAK:.2%} of the peak radiance (the plane's measured margin)"
    if readback_stderr:
        text += f" and the readback's ±½ LSB (σ_q = {readback_stderr:.2g}, known)"
    with np.errstate(divide="ignore", invalid="ignore"):  # the umbra's truth is 0: its relative errors are NaN
        return {k: judge(image, sr.mean, sr.stderr, sr.dof, m, judged_budget(sr, m, readback_stderr), text)
                for k, m in sr.regions.items() if m.any()}


def leak(image: np.ndarray, sr: ShadowSceneResult) -> tuple[tuple[float, float], tuple[float, float]]:
    """(fraction of umbra pixels brighter than the budget ± binomial s.e., mean s over the umbra ± s.e.)."""
    um = sr.regions["umbra"]
    n = int(um.sum())
    if n == 0:
        return (float("nan"), 0.0), (float("nan"), 0.0)
    lit = (image[um] > sr.budget).any(axis=-1)
    p = float(lit.mean())
    s = shadow_factor(image, sr.unshadowed)[um]
    return (p, float(np.sqrt(p * (1 - p) / n))), (float(s.mean()), float(s.std(ddof=1) / np.sqrt(n)) if n > 1 else 0.0)


def measure_engine(sr: ShadowSceneResult, engine: str, shadow_type: str) -> ShadowEngineResult:
    er = images.render(engine, sr.scene.with_shadow_type(shadow_type))
    img = er.image[..., :3].astype(np.float64)
    out = ShadowEngineResult(engine, shadow_type, str(er.info.get("shadow_type_used", shadow_type)), img,
                             er.frame_ms, er.wall_s, readback_stderr=er.stderr, info=dict(er.info))
    out.judgements = judge_regions(img, sr, er.stderr)
    out.width_px = transition_px(shadow_factor(img, sr.unshadowed), sr.regions["all"])
    out.leak, out.umbra_mean = leak(img, sr)
    return out


def measure_shadow_scene(scene: rss.ShadowScene, s: Settings, prepared: Future | None = None) -> ShadowSceneResult:
    """The scene's reference (``prepared``: its future, traced on another thread; else here) and every engine's
    shadow types against it."""
    import time

    t0 = time.perf_counter()
    ref = prepared.result() if prepared is not None else render_reference(scene, s.shadow_spp, s.passes, s.seed)
    t_ref = time.perf_counter() - t0
    mask = interior_mask(ref.hit, np.ones(ref.hit.shape))
    regions = {"all": mask, **{k: m & mask for k, m in rss.regions(scene).items()}}
    sr = ShadowSceneResult(scene, ref.mean, ref.stderr, ref.dof, rss.unshadowed_radiance(scene), regions,
                           SHADOW_BUDGET_OF_PEAK * float(np.nanmax(ref.mean)), (0.0, 0.0), reference_s=t_ref)
    sr.truth_width = truth_width(sr, s.seed)
    for engine in s.shadow_engines:
        e = registry.find(engine)
        for t in e.shadow_types if e is not None else ():
            try:
                sr.results.append(measure_engine(sr, engine, t))
            except Exception as exc:  # an engine that cannot start is skipped with its reason, never a crash
                sr.skipped[f"{engine} {t}"] = " ".join(f"{type(exc).__name__}: {exc}".split())[:300]
    return sr


def shadow_scene_list(s: Settings) -> list[rss.ShadowScene]:
    """(e) the shadow scenes at ``shadow_resolution`` (none without ``shadow_engines``)."""
    return rss.shadow_scenes(s.shadow_resolution) if s.shadow_engines else []


def compute_shadows(ctx: Any, s: Settings, prepared: list[Future] | None = None) -> list[ShadowSceneResult]:
    """(e) every shadow scene of :func:`shadow_scene_list`; ``prepared``: their references' futures, in order."""
    scenes = shadow_scene_list(s)
    futures: list[Future | None] = list(prepared) if prepared is not None else [None] * len(scenes)
    return [measure_shadow_scene(sc, s, f)
            for sc, f in ctx.progress(list(zip(scenes, futures, strict=True)), "renders: shadows")]
