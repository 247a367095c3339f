"""(b) Babylon's CDF irradiance (Babylon PR 16247), numbers only: the Lambertian sphere under a sunny 1k probe
(:mod:`validate.scenes.render_cdf_scenes`) rendered by Babylon with its CDF irradiance at cube sizes ``cdf_sizes``,
supersampled as shipped and as before PR 16247, against Mitsuba.

Per size × variant: the per-pixel judgement (:func:`validate.metrics.pixel_z.judge`, the probe budget
``budgets.PROBE_BUDGET_REL`` × the reference) and the *energy ratio* r = Σ e / Σ m over the judged pixels and the three
channels (engine e, Mitsuba mean m). Its uncertainty is the reference's: σ_r = r·√(Σ s²)/Σ m (s the per-pixel
standard error over the passes; the passes are independent, the pixels too). Babylon's own estimate is deterministic
(4096 Hammersley points per irradiance texel, no random seed), so it adds no variance; its sampling error is part of
what is measured (and negligible here: 16384 points give the same r to 4 digits, 64 points move it by 0.009 —
scripts/diagnose_renders/cdf_patch.py). Babylon only (full runs): its first call (page, shaders, first CDF cube)
took 42–45 s on the shared 2 cores (measured); the whole group (reference + 6 renders) 172 s wall from a cold page.
"""

from __future__ import annotations

from concurrent.futures import Future
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ....metrics.pixel_z import PixelJudgement, interior_mask, judge
from ....reference.render_reference import RenderReference, render_reference
from ....scenes import render_cdf_scenes as rcs
from ....scenes import render_scenes as rs
from .. import images
from ..budgets import PROBE_BUDGET_REL
from ..settings import Settings


@dataclass
class CdfResult:
    size: int
    variant: str  # "shipped" | "pre16247"
    image: np.ndarray
    judgement: PixelJudgement
    ratio: float  # Σ e / Σ m over the judged pixels
    ratio_unc: float  # the reference's standard error of it
    info: dict[str, Any]
    frame_ms: float
    wall_s: float


@dataclass
class CdfScene:
    scene: rs.RenderScene
    mean: np.ndarray
    stderr: np.ndarray
    dof: int
    mask: np.ndarray
    note: str
    results: list[CdfResult] = field(default_factory=list)
    skipped: dict[str, str] = field(default_factory=dict)

    def result(self, size: int, variant: str) -> CdfResult | None:
        return next((r for r in self.results if (r.size, r.variant) == (size, variant)), None)


def energy_ratio(image: np.ndarray, mean: np.ndarray, stderr: np.ndarray, mask: np.ndarray) -> tuple[float, float]:
    """r = Σ e / Σ m over ``mask`` × channels, ± r·√(Σ s²)/Σ m (module docstring)."""
    se, sm = float(image[mask].sum()), float(mean[mask].sum())
    r = se / sm
    return r, r * float(np.sqrt((stderr[mask] ** 2).sum())) / sm


def load_cdf_probe(ctx: Any) -> tuple[np.ndarray | None, str]:
    from ....scenes.loaders import load_environment

    if ctx.probes_dir is None:
        return None, "no --probes directory: the CDF irradiance scene is not rendered"
    path = ctx.probes_dir / rcs.CDF_PROBE_FILE
    if not path.is_file():
        return None, f"{path}: not found: the CDF irradiance scene is not rendered"
    t = load_environment(path, "latlong", False).radiance
    note = f"{rcs.CDF_PROBE_FILE} ({t.shape[1]}×{t.shape[0]}, sun at azimuth {rcs.SUN_AZIMUTH_DEG:g}°)"
    return np.asarray(t, np.float64), note


def measure(scene: rs.RenderScene, s: Settings, note: str, prepared: Future | None = None) -> CdfScene:
    """Babylon's CDF renders against the reference (``prepared``: its future, traced meanwhile on the reference
    thread of :func:`validate.experiments.renders.compute.compute`; else traced here)."""
    ref = prepared.result() if prepared is not None else cdf_reference(scene, s)
    out = CdfScene(scene, ref.mean, ref.stderr, ref.dof, ref.hit, note)
    for n in s.cdf_sizes:
        for v in rcs.CDF_VARIANTS:
            name = rcs.engine_name(n, v)
            try:
                er = images.render(name, scene)
            except Exception as exc:  # an engine that cannot start is skipped with its reason, never a crash
                out.skipped[name] = " ".join(f"{type(exc).__name__}: {exc}".split())[:300]
                continue
            img = er.image[..., :3].astype(np.float64)
            mask = interior_mask(ref.hit, er.image[..., 3])
            out.mask = mask
            b = PROBE_BUDGET_REL * ref.mean
            j = judge(img, ref.mean, ref.stderr, ref.dof, mask, b, f"{PROBE_BUDGET_REL:.2e} × the reference")
            r, u = energy_ratio(img, ref.mean, ref.stderr, mask)
            out.results.append(CdfResult(n, v, img, j, r, u, er.info, er.frame_ms, er.wall_s))
    return out


def cdf_reference(scene: rs.RenderScene, s: Settings) -> RenderReference:
    """The CDF scene's Mitsuba reference (``env_spp`` × ``passes``; Mitsuba only, safe on the reference thread)."""
    return render_reference(scene, s.env_spp, s.passes, s.seed)


def cdf_scene_list(ctx: Any, s: Settings) -> list[tuple[rs.RenderScene, str]]:
    """The CDF scene and its probe note when Babylon is among the engines and ``cdf_sizes`` is not empty (else
    none)."""
    if "babylon" not in s.engines or not s.cdf_sizes:
        return []
    texels, note = load_cdf_probe(ctx)
    if texels is None:
        return []
    return [(rcs.cdf_lambert_scene(texels, s.cdf_resolution), note)]


def compute_cdf(ctx: Any, s: Settings, scenes: list[tuple[rs.RenderScene, str]] | None = None,
                prepared: list[Future] | None = None) -> list[CdfScene]:
    """Every scene of :func:`cdf_scene_list` (``scenes``: that list, already built); ``prepared``: their references'
    futures, in order (else traced here)."""
    scenes = cdf_scene_list(ctx, s) if scenes is None else scenes
    futures: list[Future | None] = list(prepared) if prepared is not None else [None] * len(scenes)
    return [measure(sc, s, note, f) for (sc, note), f in zip(scenes, futures, strict=True)]
