"""Reference shadows from Mitsuba: direct lighting, a G-buffer and the visible fraction of the disc.

Everything here is Mitsuba's own machinery (its ``direct`` and ``aov`` integrators, its sensor, its
``ray_test``); none of it shares code with :mod:`validate.local_models.shadow.shadow_map`.

Pixel centres, not pixel areas. Every ray leaves the camera through a pixel *centre*
((i + ½)/W, (j + ½)/H): the direct-lighting estimate, the G-buffer and the visibility all describe
the same surface point x per pixel, so a local model shading the G-buffer is compared with the
radiance *at that point*, with no anti-aliasing mixing shadowed and lit surface into one pixel.

* ``radiance``: Mitsuba's ``direct`` integrator (one emitter sample and one BSDF sample per path,
  combined by MIS, Veach 1997 ch. 9), evaluated by ``integrator.sample`` on pixel-centre rays.
  ``passes`` independent passes of ``spp`` samples each, each with its own seed of the scrambled
  low-discrepancy ``ldsampler`` (stratified over the spp samples of a pixel; spp must be a power of 4,
  which ldsampler would otherwise round up, breaking the pixel-major sample layout). The reference is the mean
  of the passes; its per-pixel Monte Carlo uncertainty is the standard error s/√P of the P pass
  means (s the sample standard deviation, P − 1 degrees of freedom).
* G-buffer: the ``aov`` integrator (position, geometric normal, albedo) on the same rays.
* ``visibility``: V(x) = fraction of the disc's area visible from x. The disc is split into n×n
  equal-area strata (the concentric map of Shirley & Chiu 1997 is area-preserving, so equal cells of
  the square map to equal areas of the disc); one ray per stratum centre, ``scene.ray_test`` against
  the light-free geometry. Disc points below x's tangent plane are left out (they are the horizon,
  which the shading's cosine handles, not a shadow); where the whole disc is below it, V is NaN.

References
[1] E. Veach, Robust Monte Carlo Methods for Light Transport Simulation, PhD thesis, 1997.
[2] P. Shirley, K. Chiu, A Low Distortion Map Between Disk and Square, JGT 2(3), 1997.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..backend import init, padded_count
from ..errors import ValidateError
from ..scenes.shadow_scenes import ShadowScene
from ..stats import mean_and_stderr
from .cache import cached

CODE_VERSION = "shadow_render/1"
RAY_OFFSET = 1e-4  # m: shadow-ray origins are lifted this far along the geometric normal
CHUNK_RAYS = 1 << 23  # rays per Mitsuba call (bounds peak memory)


@dataclass
class ShadowReference:
    """Per-pixel reference for one scene (arrays are (H, W, ·), row 0 at the top of the image)."""

    radiance: np.ndarray  # (H, W, 3) mean of the passes, W sr⁻¹ m⁻²
    uncertainty: np.ndarray  # (H, W, 3) standard error of the mean over passes
    position: np.ndarray  # (H, W, 3) world position of the surface point at the pixel centre
    normal: np.ndarray  # (H, W, 3) geometric normal (outward)
    albedo: np.ndarray  # (H, W, 3) diffuse reflectance
    valid: np.ndarray  # (H, W) bool: the pixel-centre ray hit geometry
    visibility: np.ndarray  # (H, W) fraction of the disc visible (NaN where it is all below the horizon)
    spp: int
    passes: int
    seed: int
    visibility_samples: int

    @property
    def total_spp(self) -> int:
        return self.spp * self.passes

    def settings(self) -> dict[str, Any]:
        return {"integrator": "direct (MIS, 1 emitter + 1 BSDF sample)", "sampler": "ldsampler",
                "spp_per_pass": self.spp, "passes": self.passes, "seed": self.seed,
                "visibility_rays_per_pixel": self.visibility_samples, "pixel_sampling": "pixel centres"}


def pixel_centre_positions(width: int, height: int, spp: int) -> Any:
    """mi.Point2f of N = W·H·spp film positions in [0,1]², pixel-major (lane i → pixel i // spp)."""
    import drjit as dr
    import mitsuba as mi

    idx = dr.arange(mi.UInt32, width * height * spp)
    pix = idx // spp
    return mi.Point2f((mi.Float(pix % width) + 0.5) / width, (mi.Float(pix // width) + 0.5) / height)


def _camera_rays(scene: Any, width: int, height: int, spp: int) -> Any:
    import mitsuba as mi

    sensor = scene.sensors()[0]
    ray, _ = sensor.sample_ray(0.0, 0.5, pixel_centre_positions(width, height, spp), mi.Point2f(0.5, 0.5))
    return ray


def render_gbuffer(scene: Any, width: int, height: int) -> dict[str, np.ndarray]:
    """Position, geometric normal, albedo and hit mask at the pixel centres (Mitsuba ``aov``)."""
    import drjit as dr
    import mitsuba as mi

    integrator = mi.load_dict({"type": "aov", "aovs": "p:position,n:geo_normal,a:albedo"})
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(0, width * height)
    rays = _camera_rays(scene, width, height, 1)
    _, _, aovs = integrator.sample(scene, sampler, rays)
    dr.eval(aovs)  # one kernel for the nine channels (converting each alone would trace the rays nine times)
    a = np.stack([np.array(c) for c in aovs], axis=-1).reshape(height, width, -1)
    valid = np.array(scene.ray_intersect(rays).is_valid()).reshape(height, width)
    return {"position": a[..., 0:3].astype(np.float64), "normal": a[..., 3:6].astype(np.float64),
            "albedo": a[..., 6:9].astype(np.float64), "valid": valid}


def render_direct(scene: Any, width: int, height: int, spp: int, passes: int, seed: int
                  ) -> tuple[np.ndarray, np.ndarray]:
    """(mean, standard error) over ``passes`` independent ldsampler passes of ``spp`` each, (H, W, 3)."""
    import mitsuba as mi

    if spp < 1 or spp & (spp - 1) or spp.bit_length() % 2 == 0 or passes < 2:
        raise ValidateError(f"reference sampling spp={spp}, passes={passes}: ldsampler needs spp a power of 4 "
                            "(1, 4, 16, 64, 256, …) and passes ≥ 2")
    integrator = mi.load_dict({"type": "direct", "emitter_samples": 1, "bsdf_samples": 1})
    rays = _camera_rays(scene, width, height, spp)
    images = []
    for p in range(passes):
        sampler = mi.load_dict({"type": "ldsampler", "sample_count": spp})
        sampler.seed(seed + 7919 * p, width * height * spp)
        spec, _, _ = integrator.sample(scene, sampler, rays)
        images.append(np.array(spec).T.reshape(height, width, spp, 3).mean(axis=2, dtype=np.float64))
    return mean_and_stderr(np.stack(images), axis=0)


def concentric_disc(u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shirley–Chiu map [2] of the unit square to the unit disc (area-preserving)."""
    a, b = 2 * u - 1, 2 * v - 1
    first = np.abs(a) > np.abs(b)
    safe_a = np.where(a == 0, 1.0, a)
    safe_b = np.where(b == 0, 1.0, b)
    r = np.where(first, a, b)
    phi = np.where(first, (np.pi / 4) * (b / safe_a), np.pi / 2 - (np.pi / 4) * (a / safe_b))
    r = np.where((a == 0) & (b == 0), 0.0, r)
    return r * np.cos(phi), r * np.sin(phi)


def disc_points(centre: np.ndarray, frame: tuple[np.ndarray, np.ndarray], radius: float, side: int) -> np.ndarray:
    """(side², 3) centres of side × side equal-area strata of the disc."""
    g = (np.arange(side) + 0.5) / side
    uu, vv = np.meshgrid(g, g, indexing="ij")
    x, y = concentric_disc(uu.ravel(), vv.ravel())
    a, b = frame
    return np.asarray(centre)[None, :] + radius * (x[:, None] * a[None, :] + y[:, None] * b[None, :])


def disc_irradiance_quadrature(light: Any, position: np.ndarray, normal: np.ndarray, side: int = 96
                               ) -> np.ndarray:
    """Unoccluded disc irradiance by quadrature, the slow exact oracle of the local models' closed form:

        E(x, n) = L_e ∫_disc max(0, n·ω) max(0, −n_L·ω) / |q − x|² dA_q,   ω = (q − x)/|q − x|,

    on side² equal-area strata of the disc (:func:`disc_points`), numpy, (N,)."""
    pts = disc_points(np.array(light.centre), light.frame(), light.radius, side)
    p = np.asarray(position, dtype=np.float64).reshape(-1, 3)
    nrm = np.asarray(normal, dtype=np.float64).reshape(-1, 3)
    out = np.empty(p.shape[0])
    da = light.area / pts.shape[0]
    for s in range(0, p.shape[0], 256):
        w = pts[None, :, :] - p[s:s + 256, None, :]
        d2 = np.einsum("pqk,pqk->pq", w, w)
        w = w / np.sqrt(d2)[..., None]
        cos_r = np.maximum(np.einsum("pqk,pk->pq", w, nrm[s:s + 256]), 0)
        cos_l = np.maximum(-(w @ light.normal), 0)
        out[s:s + 256] = light.radiance * (cos_r * cos_l / d2).sum(axis=1) * da
    return out


RAY_BLOCK = 1 << 16  # rows per numpy block of :func:`segment_rays` (its float64 temporaries stay in cache)


def segment_rays(origins: np.ndarray, normals: np.ndarray, targets: np.ndarray, count: int) -> np.ndarray:
    """(7, ``count``) float32 rows o_x, o_y, o_z, ω_x, ω_y, ω_z, maxt of the shadow segments of M ≤ ``count`` rows of
    (M, 3) float64 inputs. Per component, in float64: o = x + RAY_OFFSET·n, d = t − o, |d| = √((d_x² + d_y²) + d_z²)
    (the sum in that order, as ``np.linalg.norm(d, axis=1)`` forms it), ω = d / max(|d|, 10⁻³⁰); each rounded once
    to float32, the last ray repeated past M (zeros when M = 0). Formed on contiguous (M, 3) blocks of
    :data:`RAY_BLOCK` rows (the same operations as on the strided columns, the same bits)."""
    m = origins.shape[0]
    buf = np.empty((7, count), dtype=np.float32)
    for s in range(0, m, RAY_BLOCK):
        e = min(s + RAY_BLOCK, m)
        o = normals[s:e] * RAY_OFFSET
        o += origins[s:e]
        d = targets[s:e] - o
        sq = d * d
        dist = sq[:, 0] + sq[:, 1]
        dist += sq[:, 2]
        np.sqrt(dist, out=dist)
        d /= np.maximum(dist, 1e-30)[:, None]
        buf[0:3, s:e] = o.T
        buf[3:6, s:e] = d.T
        buf[6, s:e] = dist
    buf[:, m:] = buf[:, m - 1:m] if m else 0.0
    return buf


def segment_visible(geometry: Any, origins: np.ndarray, normals: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Whether the segment from each origin (lifted by RAY_OFFSET along its normal) to its target is free: the rays of
    :func:`segment_rays` in chunks of :data:`CHUNK_RAYS`, each padded to :func:`~validate.backend.padded_count` lanes
    (Mitsuba's query reads past a ragged end)."""
    import mitsuba as mi

    out = np.empty(origins.shape[0], dtype=bool)
    for s in range(0, origins.shape[0], CHUNK_RAYS):
        e = min(s + CHUNK_RAYS, origins.shape[0])
        buf = segment_rays(origins[s:e], normals[s:e], targets[s:e], padded_count(e - s))
        ray = mi.Ray3f(mi.Point3f(*(mi.Float(buf[k]) for k in range(3))),
                       mi.Vector3f(*(mi.Float(buf[k]) for k in range(3, 6))))
        ray.maxt = mi.Float(buf[6])
        out[s:e] = ~np.array(geometry.ray_test(ray))[:e - s]
    return out


def disc_visibility(geometry: Any, scene: ShadowScene, position: np.ndarray, normal: np.ndarray,
                    valid: np.ndarray, side: int) -> np.ndarray:
    """V(x) per pixel: visible fraction of the disc above x's tangent plane (NaN: none above; see module doc)."""
    light = scene.light
    pts = disc_points(np.array(light.centre), light.frame(), light.radius, side)  # (S, 3)
    vis = np.full(valid.shape, np.nan)
    idx = np.flatnonzero(valid.ravel())
    p, n = position.reshape(-1, 3)[idx], normal.reshape(-1, 3)[idx]
    n_pts = pts.shape[0]
    per_chunk = max(1, CHUNK_RAYS // n_pts)
    out = np.full(idx.size, np.nan)
    for s in range(0, idx.size, per_chunk):
        pc, nc = p[s:s + per_chunk], n[s:s + per_chunk]
        above = np.einsum("pk,qk->pq", nc, pts) - np.einsum("pk,pk->p", nc, pc)[:, None] > 0  # (P, S)
        m = pc.shape[0]
        free = segment_visible(geometry, np.repeat(pc, n_pts, axis=0), np.repeat(nc, n_pts, axis=0),
                               np.tile(pts, (m, 1))).reshape(m, n_pts)
        cnt = above.sum(axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            out[s:s + per_chunk] = np.where(cnt > 0, (free & above).sum(axis=1) / np.maximum(cnt, 1), np.nan)
    vis.ravel()[idx] = out
    return vis


def load_scene(scene: ShadowScene, with_light: bool = True) -> Any:
    import mitsuba as mi

    init()
    return mi.load_dict(scene.mitsuba_dict(with_light=with_light, with_sensor=True))


def reference_shadows(scene: ShadowScene, spp: int = 64, passes: int = 8, seed: int = 1234,
                      visibility_side: int = 16) -> ShadowReference:
    """The cached reference (radiance ± standard error, G-buffer, visibility) for ``scene``."""
    if visibility_side < 2:
        raise ValidateError(f"visibility_side={visibility_side}: need at least 2 (side² rays per pixel)")
    cam = scene.camera

    def compute() -> dict[str, np.ndarray]:
        lit = load_scene(scene, with_light=True)
        geometry = load_scene(scene, with_light=False)
        g = render_gbuffer(lit, cam.width, cam.height)
        mean, err = render_direct(lit, cam.width, cam.height, spp, passes, seed)
        vis = disc_visibility(geometry, scene, g["position"], g["normal"], g["valid"], visibility_side)
        return {**g, "radiance": mean, "uncertainty": err, "visibility": vis}

    parts = {"code": CODE_VERSION, "scene": scene.parts(), "spp": spp, "passes": passes, "seed": seed,
             "visibility_side": visibility_side}
    r = cached("shadow_reference", parts, compute)
    return ShadowReference(r["radiance"], r["uncertainty"], r["position"], r["normal"], r["albedo"],
                           r["valid"].astype(bool), r["visibility"], spp, passes, seed, visibility_side**2)


def point_visibility(geometry: Any, light_centre: np.ndarray, position: np.ndarray, normal: np.ndarray
                     ) -> np.ndarray:
    """Whether each point (N, 3) sees ``light_centre`` (one shadow ray each)."""
    targets = np.broadcast_to(np.asarray(light_centre, dtype=np.float64), position.shape)
    return segment_visible(geometry, position, normal, np.ascontiguousarray(targets))


def shadow_edge_band(geometry: Any, light_centre: np.ndarray, right: np.ndarray, up: np.ndarray,
                     forward: np.ndarray, step: float, position: np.ndarray, normal: np.ndarray,
                     valid: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels within one shadow-map texel of a hard-shadow edge, from Mitsuba rays alone.

    For the light's frame (forward, right, up) with the light at O, a point x has tan-plane coordinates
    (s, t) = ((x−O)·right, (x−O)·up) / ((x−O)·forward). A texel is ``step`` wide in s and t. The point is
    moved to each of its 8 neighbours (s ± step, t ± step) *on its own tangent plane* (the ray from O
    through (s', t') intersected with the plane of x and its normal), and each moved point is tested for
    visibility of O. Pixels where any neighbour's answer differs from the centre's are in the band.
    """
    o = np.asarray(light_centre, dtype=np.float64)
    idx = np.flatnonzero(valid.ravel())
    p, n = position.reshape(-1, 3)[idx], normal.reshape(-1, 3)[idx]
    rel = p - o
    z = rel @ forward
    s, t = (rel @ right) / z, (rel @ up) / z
    centre = point_visibility(geometry, o, p, n)
    differs = np.zeros(idx.size, dtype=bool)
    for ds in (-1, 0, 1):
        for dt in (-1, 0, 1):
            if ds == 0 and dt == 0:
                continue
            d = forward[None, :] + (s + ds * step)[:, None] * right[None, :] + (t + dt * step)[:, None] * up[None, :]
            denom = np.einsum("pk,pk->p", n, d)
            lam = np.einsum("pk,pk->p", n, rel) / np.where(np.abs(denom) < 1e-12, 1e-12, denom)
            moved = o[None, :] + lam[:, None] * d
            ok = (lam > 0) & (np.abs(denom) > 1e-12)
            vis = point_visibility(geometry, o, np.where(ok[:, None], moved, p), n)
            differs |= ok & (vis != centre)
    band = np.zeros(valid.size, dtype=bool)
    band[idx] = differs
    return band.reshape(valid.shape)
