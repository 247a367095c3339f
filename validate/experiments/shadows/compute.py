"""Measurements of the ``shadows`` experiment (numbers only): the frame, every registered shadow
technique's errors, and the internal sweeps (resolution, bias, PCF kernel, edge band, convergence rate).

Every shadow technique is taken from the registry (``for tech in shadow``) and called through
``shadow.call(tech, shadow_map, light, points, normals)``, which checks the family's output contract;
built-ins (:mod:`validate.local_models.shadow.shadow_map`) and plug-ins are measured alike. The sweeps of
bias and PCF kernel stay internal: they vary parameters of the built-in functions directly.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...backend import init
from ...errors import ValidateError
from ...local_models import shadow
from ...local_models.registry import Technique
from ...local_models.shadow import shadow_map as smod
from ...metrics import shadow_error as se
from ...reference import shadow_render as sr
from ...scenes import shadow_scenes as ss
from ..base import Context
from .settings import Settings

BAND_TEST_ALPHA = 1e-3  # per-pixel two-sided t test level (expected exceed fraction 0.1 %)
BLEEDING_REDUCTION = 0.2  # Lauritzen 2007 (GPU Gems 3, ch. 8) light-bleeding reduction linstep(0.2, 1, p)


class Frame:
    """The G-buffer of the fixed camera (identical for every radius) and the per-radius references."""

    def __init__(self, refs: dict[float, sr.ShadowReference], scenes: dict[float, ss.ShadowScene],
                 flip_radii: tuple[float, ...] = ()):
        first = refs[min(refs)]
        for r, ref in refs.items():  # one camera, one geometry: the G-buffers must agree
            if not (np.array_equal(ref.valid, first.valid) and np.allclose(ref.position, first.position)):
                raise ValidateError(f"shadows: the G-buffer of the r = {r:g} m reference differs from the others")
        self.valid = first.valid
        self.h, self.w = first.valid.shape
        self.position = first.position[self.valid]
        self.normal = first.normal[self.valid]
        self.albedo = first.albedo[self.valid]
        self.refs, self.scenes = refs, scenes
        self.irradiance = {r: smod.disc_irradiance(scenes[r].light, self.position, self.normal) for r in refs}
        self.norm = {r: se.lit_normaliser(refs[r].radiance[self.valid], refs[r].visibility[self.valid])
                     for r in refs}
        self.flip_noise = {r: se.flip_noise_floor(refs[r].radiance, refs[r].uncertainty) if r in flip_radii
                           else float("nan") for r in refs}

    def image(self, values: np.ndarray, fill: float = 0.0) -> np.ndarray:
        """Valid-pixel values (N, …) → a full (H, W, …) image."""
        out = np.full((self.h, self.w) + values.shape[1:], fill, dtype=np.float64)
        out[self.valid] = values
        return out

    def ref(self, r: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(radiance (N, 3), its standard error (N, 3), visible fraction V (N,)) at the valid pixels."""
        ref = self.refs[r]
        return ref.radiance[self.valid], ref.uncertainty[self.valid], ref.visibility[self.valid]


def build_frame(s: Settings, radii: tuple[float, ...], seed: int, progress: Any = iter,
                flip_radii: tuple[float, ...] | None = None) -> Frame:
    """References (cached) for every radius and the frame they share (FLIP for ``s.flip_radii`` unless given)."""
    scenes = {r: ss.shadow_scene(r, s.width, s.height) for r in radii}
    refs = {r: sr.reference_shadows(scenes[r], s.spp, s.passes, seed, s.visibility_side) for r in progress(radii)}
    return Frame(refs, scenes, s.flip_radii if flip_radii is None else flip_radii)


def technique_visibility(tech: Technique | str, sm: smod.ShadowMap, frame: Frame, radius: float) -> np.ndarray:
    """V′ of a registered technique at the valid pixels, through the family's contract check."""
    return shadow.call(tech, sm, frame.scenes[radius].light, frame.position, frame.normal)


def evaluate(frame: Frame, radius: float, vis: np.ndarray, flip: bool = False) -> tuple[se.ShadowErrors, np.ndarray]:
    """Metrics of V′ for the light of ``radius``; returns (errors, shaded radiance (N, 3))."""
    rad, unc, v_ref = frame.ref(radius)
    approx = smod.shade(frame.albedo, frame.irradiance[radius], vis)
    images = (frame.image(rad), frame.image(approx)) if flip else None
    return se.shadow_errors(rad, unc, approx, vis, v_ref, images, frame.norm[radius]), approx


@dataclass
class Measurements:
    """Everything :func:`~validate.experiments.shadows.claims`, ``findings`` and ``sections`` read."""

    settings: Settings
    frame: Frame
    techniques: list[Technique]
    sweep: dict[int, dict[float, dict[str, se.ShadowErrors]]] = field(default_factory=dict)  # res → r → tech
    images: dict[tuple[int, float, str], np.ndarray] = field(default_factory=dict)  # shaded radiance (N, 3)
    bias: dict[str, Any] = field(default_factory=dict)
    kernels: dict[str, Any] = field(default_factory=dict)
    band: dict[str, Any] = field(default_factory=dict)
    rate: dict[str, Any] = field(default_factory=dict)
    pcss_flat: se.ShadowErrors | None = None
    bounds: dict[str, dict[str, Any]] = field(default_factory=dict)  # upper-bound techniques (VSM, ESM, MSM)
    bleeding: dict[str, Any] = field(default_factory=dict)  # synthetic two-occluder leak case
    build_seconds: dict[int, float] = field(default_factory=dict)

    @property
    def radii(self) -> list[float]:
        return sorted(self.frame.refs)

    @property
    def r_pt(self) -> float:
        return min(self.frame.refs)

    @property
    def r_max(self) -> float:
        return max(self.frame.refs)

    def at_default(self, r: float) -> dict[str, se.ShadowErrors]:
        return self.sweep[self.settings.default_resolution][r]


def measure_resolution(m: Measurements, sm: smod.ShadowMap) -> None:
    """Every technique at every radius with this map; images and FLIP at the default resolution."""
    s, res = m.settings, sm.resolution
    ress = sorted(s.resolutions)
    m.sweep[res] = {}
    for r in m.radii:
        m.sweep[res][r] = {}
        for tech in m.techniques:
            vis = technique_visibility(tech, sm, m.frame, r)
            err, approx = evaluate(m.frame, r, vis, flip=res == s.default_resolution and r in s.flip_radii)
            m.sweep[res][r][tech.name] = err
            if res == s.default_resolution or (r == m.r_pt and res in (ress[0], ress[-1])):
                m.images[(res, r, tech.name)] = approx


def bias_sweep(sm: smod.ShadowMap, frame: Frame, r: float, scales: tuple[float, ...]) -> dict[str, Any]:
    """Hard shadows of the near-point light at one resolution, glPolygonOffset(2k, 4k) for each k."""
    out: dict[str, Any] = {k: [] for k in ("scale", "factor", "units", "total", "total_uncertainty",
                                            "false_shadow", "false_light")}
    for k in scales:
        off = smod.PolygonOffset().scaled(k)
        err, _ = evaluate(frame, r, smod.visibility_hard(sm, frame.position, frame.normal, off))
        for key, val in (("scale", k), ("factor", off.factor), ("units", off.units), ("total", err.total.mean),
                         ("total_uncertainty", err.total.uncertainty), ("false_shadow", err.false_shadow),
                         ("false_light", err.false_light)):
            out[key].append(float(val))
    out["resolution"], out["radius"] = sm.resolution, r
    return out


def kernel_sweep(sm: smod.ShadowMap, frame: Frame, radii: tuple[float, ...], kernels: tuple[int, ...]
                 ) -> dict[str, Any]:
    """PCF penumbra and total error vs kernel size k (classic and receiver-plane depth), and PCSS on the
    same map against the best fixed kernel: the paired per-pixel difference over the penumbra."""
    out: dict[str, Any] = {"kernels": list(kernels), "resolution": sm.resolution}
    for r in radii:
        rad, _, v_ref = frame.ref(r)
        pen = se.region_masks(v_ref)["penumbra"]
        d: dict[str, Any] = {}
        best: tuple[float, int, bool, np.ndarray] | None = None
        for rp in (False, True):
            tag = "receiver_plane" if rp else "classic"
            for k in kernels:
                vis = smod.visibility_pcf(sm, frame.position, frame.normal, k, receiver_plane=rp)
                err, approx = evaluate(frame, r, vis)
                d.setdefault(f"{tag}_penumbra", []).append(err.regions["penumbra"].mean)
                d.setdefault(f"{tag}_total", []).append(err.total.mean)
                d.setdefault(f"{tag}_false_shadow", []).append(err.false_shadow)
                e_pix = se.pixel_error(rad, approx, frame.norm[r])[pen]
                if best is None or e_pix.mean() < best[0]:
                    best = (float(e_pix.mean()), k, rp, e_pix)
        if "pcss" in shadow and best is not None:
            err, approx = evaluate(frame, r, technique_visibility("pcss", sm, frame, r))
            e_pcss = se.pixel_error(rad, approx, frame.norm[r])[pen]
            diff = best[3] - e_pcss
            d.update({"pcss_penumbra": err.regions["penumbra"].mean, "pcss_total": err.total.mean,
                      "penumbra_uncertainty": err.regions["penumbra"].uncertainty,
                      "best_kernel": best[1], "best_receiver_plane": best[2], "best_penumbra": best[0],
                      "difference": float(diff.mean()),
                      "difference_stderr": float(diff.std(ddof=1) / np.sqrt(diff.size)),
                      "pixels": int(diff.size)})
        out[f"{r:g}"] = d
    return out


def band_test(sm: smod.ShadowMap, frame: Frame, geometry: Any, r: float) -> dict[str, Any]:
    """The registered ``hard`` technique vs the reference outside a one-texel band of the shadow edge and
    the reference's penumbra: fraction of pixels failing a per-pixel Student-t test at BAND_TEST_ALPHA;
    with the approximation × 1.01 (a 1 % radiance bias) for the power check."""
    v = sm.view
    ref = frame.refs[r]
    band_img = sr.shadow_edge_band(geometry, v.origin, v.right, v.up, v.forward, sm.texel_tan, ref.position,
                                   ref.normal, ref.valid)
    rad, unc, v_ref = frame.ref(r)
    approx = smod.shade(frame.albedo, frame.irradiance[r], technique_visibility("hard", sm, frame, r))
    masks = se.region_masks(v_ref)
    band = band_img[frame.valid]
    include = (masks["lit"] | masks["umbra"]) & ~band

    def test(a: np.ndarray, where: np.ndarray) -> dict[str, Any]:
        return se.outside_band_test(rad, unc, a, ref.passes, where, frame.norm[r], BAND_TEST_ALPHA).to_json()

    return {"resolution": sm.resolution, "radius": r, "texel_tan": sm.texel_tan, "passes": ref.passes,
            "band_pixels": int(band.sum()), "penumbra_pixels": int(masks["penumbra"].sum()),
            "outside": test(approx, include), "inside_band": test(approx, band | masks["penumbra"]),
            "outside_biased_1pct": test(1.01 * approx, include), "_band_image": band_img, "_include": include}


def upper_bounds(sm: smod.ShadowMap, frame: Frame, techniques: list[Technique], r: float) -> dict[str, Any]:
    """For each technique registered with meta ``upper_bound=True`` (the filterable maps): the largest amount
    by which its V′ falls below the filtered depth test P(D ≥ t) over the same 6×6 weights
    (:func:`~validate.local_models.shadow.shadow_map.filter_footprint`), and the same after the light-bleeding
    reduction V′ → clamp((V′ − a)/(1 − a)), a = BLEEDING_REDUCTION (the power check)."""
    p = smod.filter_footprint(sm, frame.position).depth_test()
    out = {}
    for tech in techniques:
        if tech.meta.get("upper_bound"):
            v = technique_visibility(tech, sm, frame, r)
            reduced = np.clip((v - BLEEDING_REDUCTION) / (1 - BLEEDING_REDUCTION), 0.0, 1.0)
            out[tech.name] = {"max_violation": float(np.max(p - v)),
                              "reduced_max_violation": float(np.max(p - reduced)),
                              "partial_pixels": int(((p > 0) & (p < 1)).sum()), "resolution": sm.resolution}
    return out


def ground_grid(frame: Frame, side: int) -> tuple[np.ndarray, np.ndarray]:
    """side² receivers on the ground plane (y = 0, normal +y) over the bounding box of the ground pixels."""
    g = (np.abs(frame.position[:, 1]) < 1e-4) & (frame.normal[:, 1] > 0.99)
    if not g.any():
        raise ValidateError("shadows: no ground pixel in the frame")
    lo, hi = frame.position[g].min(axis=0), frame.position[g].max(axis=0)
    u = (np.arange(side) + 0.5) / side
    gx, gz = np.meshgrid(lo[0] + u * (hi[0] - lo[0]), lo[2] + u * (hi[2] - lo[2]), indexing="ij")
    p = np.c_[gx.ravel(), np.zeros(side * side), gz.ravel()]
    return p, np.tile([0.0, 1.0, 0.0], (side * side, 1))


def rate_counts(sm: smod.ShadowMap, light: ss.DiscLight, points: np.ndarray, normals: np.ndarray,
                exact: np.ndarray) -> int:
    """Receivers inside the map's window where the ``hard`` technique disagrees with the point light's own
    shadow ray (``exact``, Mitsuba): the misclassified area, in grid cells."""
    x, y, _, _ = sm.window_coords(points)
    inside = (x >= 0) & (x < sm.resolution) & (y >= 0) & (y < sm.resolution)
    vis = shadow.call("hard", sm, light, points, normals) > 0.5
    return int((vis != exact)[inside].sum())


def fit_rate(resolutions: list[int], counts: list[int]) -> tuple[float, float]:
    """Weighted least-squares slope b of ln k against ln R (weights k: Poisson counts, var ln k ≈ 1/k) and its
    standard error 1/√(Σ k (ln R − x̄)²)."""
    x = np.log(np.asarray(resolutions, dtype=np.float64))
    k = np.maximum(np.asarray(counts, dtype=np.float64), 1.0)
    y = np.log(k)
    xb = float((k * x).sum() / k.sum())
    sxx = float((k * (x - xb) ** 2).sum())
    return float((k * (x - xb) * y).sum() / sxx), float(1.0 / np.sqrt(sxx))


BLEED_RES = 64  # texels per side of the synthetic two-occluder map
BLEED_NEAR, BLEED_FAR, BLEED_RECEIVER = 1.0, 4.0, 3.0  # view depths (m): near/far planes, receiver plane
BLEED_OCCLUDERS = {"far apart": (1.5, 2.0), "contact": (1.5, 2.9)}  # (left, right) occluder depths


def bleeding_case(techniques: list[Technique]) -> dict[str, Any]:
    """Light bleeding where every filter sees two occluders at different depths: a synthetic map looking
    down +z (window [0, 1]², near 1, far 4) holds occluder A over the left half and B over the right half;
    receivers on the plane z = 3 behind both are fully shadowed (V = 0), so any V′ > 0 is a leak. Per
    technique and case: mean V′ (``leak``) and the fraction of receivers with V′ > 0.1 (``leak_area``)."""
    import mitsuba as mi

    init()
    view = smod.LightView(np.zeros(3), np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]),
                          np.array([0.0, 1.0, 0.0]), 0.0, 0.0, 1.0, BLEED_NEAR, BLEED_FAR)
    i = np.tile(np.arange(BLEED_RES), BLEED_RES)
    x = np.linspace(0.25, 0.75, 201)  # receivers across the A/B boundary, away from the window's border
    p = np.c_[x * BLEED_RECEIVER, np.full_like(x, 0.5 * BLEED_RECEIVER), np.full_like(x, BLEED_RECEIVER)]
    n = np.tile([0.0, 0.0, -1.0], (x.size, 1))
    light = ss.DiscLight((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.02, 1.0)
    out: dict[str, Any] = {"receivers": int(x.size), "resolution": BLEED_RES, "receiver_depth": BLEED_RECEIVER}
    for case, (za, zb) in BLEED_OCCLUDERS.items():
        z = np.where(i < BLEED_RES // 2, za, zb)
        depth = smod.quantise_depth(mi.Float((view.depth_scale * (1 - BLEED_NEAR / z)).astype(np.float32)))
        sm = smod.ShadowMap(view, BLEED_RES, depth, mi.Float(np.zeros(BLEED_RES**2, np.float32)))
        out[case] = {"depths": [za, zb]}
        for tech in techniques:
            v = shadow.call(tech, sm, light, p, n)
            out[case][tech.name] = {"leak": float(v.mean()), "leak_area": float((v > 0.1).mean())}
    return out


__all__ = ["BAND_TEST_ALPHA", "Frame", "Measurements", "Settings", "band_test", "bias_sweep",
           "bleeding_case", "build_frame", "evaluate", "fit_rate", "ground_grid", "kernel_sweep",
           "measure_resolution", "rate_counts", "technique_visibility", "upper_bounds"]


def compute(ctx: Context, s: Settings) -> Measurements:
    """References, every technique at every resolution and radius, the sweeps and the convergence counts."""
    for what in (s.default_resolution, s.bias_resolution, s.kernel_resolution):
        if what not in s.resolutions:
            raise ValidateError(f"shadows settings: resolution {what} is not in the sweep {s.resolutions}")
    frame = build_frame(s, s.radii, ctx.seed, lambda it: ctx.progress(it, "shadows: references"))
    m = Measurements(s, frame, list(shadow))
    light = frame.scenes[m.r_pt].light
    geometry = sr.load_scene(frame.scenes[m.r_pt], with_light=False)
    grid_p, grid_n = ground_grid(frame, s.rate_grid)
    exact = sr.point_visibility(geometry, np.array(light.centre), grid_p, grid_n)
    counts: dict[int, int] = {}
    for res in ctx.progress(sorted(s.resolutions), "shadows: shadow-map resolutions"):
        sm = smod.build_shadow_map(geometry, light, frame.position, res)
        m.build_seconds[res] = round(sm.build_seconds, 3)
        measure_resolution(m, sm)
        if "hard" in shadow:
            counts[res] = rate_counts(sm, light, grid_p, grid_n, exact)
        if res == s.bias_resolution:
            m.bias = bias_sweep(sm, frame, m.r_pt, s.bias_scales)
        if res == s.kernel_resolution:
            m.kernels = kernel_sweep(sm, frame, tuple(r for r in s.kernel_radii if r in frame.refs), s.kernels)
        if res == s.default_resolution:
            flat = smod.visibility_pcss(sm, frame.position, frame.normal, m.r_max, receiver_plane=False)
            m.pcss_flat = evaluate(frame, m.r_max, flat.visibility)[0]
            m.bounds = upper_bounds(sm, frame, m.techniques, m.r_max)
        if res == max(s.resolutions) and "hard" in shadow:
            m.band = band_test(sm, frame, geometry, m.r_pt)
        del sm
    if counts:
        m.rate = _rate(counts, s.rate_grid, int(grid_p.shape[0]))
    m.bleeding = bleeding_case(m.techniques)
    return m


def _rate(counts: dict[int, int], side: int, cells: int) -> dict[str, Any]:
    """The fitted slope of the misclassified area against resolution, and the same fit with the top
    resolution capped at the one below it (a texture-size limit or a mip level off by one: the power check)."""
    ress = sorted(counts)
    k = [counts[q] for q in ress]
    b, b_se = fit_rate(ress, k)
    capped = k[:-1] + [k[-2]] if len(k) > 1 else k
    cb, cb_se = fit_rate(ress, capped)
    return {"resolutions": ress, "counts": k, "grid_side": side, "cells": cells, "slope": b, "stderr": b_se,
            "capped_counts": capped, "capped_slope": cb, "capped_stderr": cb_se}
