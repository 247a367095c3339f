"""Reference renders for image-based lighting: Mitsuba path tracing of a sphere and a dented sphere
under an environment, with per-pixel Monte Carlo uncertainty and a G-buffer for the local models.

Scene
  * the environment's ``envmap`` (:meth:`validate.scenes.environment.Environment.mitsuba_emitter`);
  * one shape: the unit ``sphere`` (convex: nothing is occluded, no light inter-reflects) or the
    *dented sphere* (:func:`dented_sphere_mesh`), whose crater is concave, so part of the environment
    is hidden from it and light bounces inside it — what local IBL ignores;
  * one BSDF: Mitsuba's ``diffuse``, ``roughconductor`` / ``roughplastic`` (GGX), a ``blendbsdf``, or
    the normalised modified-Phong BSDF below.

Camera and pixels
  An orthographic camera at direction c from the origin, looking along −c, ``up`` roughly +y; its
  image spans [−h, h]² (h = :data:`HALF_WIDTH`) in the plane ⟂ c with right = normalize((−c) × up),
  up' = right × (−c). Pixel (i, j) of an S × S image is the *single ray through its centre*,
  x = (j + ½)/S·2 − 1, y = 1 − (i + ½)/S·2, origin 5c + h(x·right + y·up'), direction −c. No pixel
  filter: each pixel is the radiance leaving one surface point towards the camera, the quantity a
  local model computes from that point's G-buffer entry.

G-buffer
  ``scene.ray_intersect`` of the same rays: shading normal n (Mitsuba's interpolated vertex normal on
  meshes), position p, view v = −ray.d = c, and the hit mask — the same data an ``aov`` integrator
  writes, without its pixel filter.

Estimator and uncertainty
  Mitsuba's ``path`` integrator (MIS of envmap and BSDF sampling) called directly
  (``integrator.sample(scene, sampler, ray)``), ``max_depth`` 2 (direct lighting only; on the sphere
  that is everything) or more (inter-reflections). P independent passes, each with spp/P samples per
  pixel from a randomised quasi-Monte Carlo sampler (default ``ldsampler``: scrambled (0, 2)-sequence,
  its scramble seeded ``seed·1000 + p``, so passes are independent randomisations [4]); the pixel value
  is the mean of the pass means and its standard error s/√P (s the sample standard deviation of the P
  pass means) [1, §2]. Under a small bright source (a 4° disc 400× its sky) the stratification cuts
  the per-pixel standard error about 5× against ``independent`` at 512 spp (measured: diffuse sphere,
  0.56 % vs 3.2 % median). spp/P must be a power of 4 (16, 64, 256, …) for ``ldsampler``.
  Results are cached (:func:`validate.reference.cache.cached`) keyed by the environment digest, the
  shape, BSDF, camera, spp, passes, seed, depth and :data:`RENDER_VERSION`.

Modified Phong (``modphong``, registered with ``mi.register_bsdf``)
  f_r(ω_i, ω_o) = k_s (s + 2)/(2π) max(0, r·ω_o)^s, r = (−ω_i.x, −ω_i.y, ω_i.z) the mirror direction of
  the view in the local frame [2, 3]. ``eval`` returns f_r cos θ_o; ``sample`` draws ω_o from the
  normalised lobe (s + 1)/(2π) cos^s α around r (cos α = u^{1/(s+1)}, φ = 2πu'), pdf = that lobe,
  weight = f_r cos θ_o / pdf = k_s (s + 2)/(s + 1) cos θ_o (0 below the horizon). White furnace: at
  normal incidence r = n, cos θ_o = cos α and the albedo is k_s ∫ (s + 2)/(2π) cos^{s+1} α dω = k_s
  exactly; elsewhere the lobe is cut by the horizon and the albedo is below k_s.

References
  [1] M. Pharr, W. Jakob, G. Humphreys, "Physically Based Rendering", 4th ed., §2.1 (Monte Carlo
      estimators and their variance).
  [2] E. Lafortune, Y. Willems, "Using the modified Phong reflectance model for physically based
      rendering", KU Leuven CW197, 1994.
  [3] R. R. Lewis, "Making shaders more physically plausible", CGF 13(2), 1994.
  [4] A. B. Owen, "Randomly permuted (t, m, s)-nets and (t, s)-sequences", 1995 (randomised QMC: the
      variance of independent randomisations estimates the error).

Checks of the reference BSDFs (:func:`furnace`, :func:`chi2_bsdf`)
  [1] PBRT 4th ed. §4.3.2 / §5.6.1: under a uniform unit environment the outgoing radiance equals the
      directional albedo ρ_hd(ω_o) = ∫ f cos θ dω ("white furnace").
  [2] Mitsuba 3, ``src/python/python/chi2.py``: ``ChiSquareTest`` (Pearson χ², pooling of cells with
      expected count < 5, Šidák correction) and ``BSDFAdapter``.
"""

from __future__ import annotations

import functools
import json
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..backend import init
from ..errors import ValidateError
from ..geometry import face_direction
from ..scenes.environment import Environment
from ..scenes.ibl_scenes import PHONG_PLUGIN
from ..scenes.latlong import luminance
from ..stats import mean_and_stderr
from .cache import cached

RENDER_VERSION = 1  # bump when this module's rendering changes (part of the cache key)
HALF_WIDTH = 1.05  # the image spans [−1.05, 1.05]² around the unit-sized object
CAMERA_DISTANCE = 5.0
MAX_PASSES = 1000
MAX_SPP_PER_LAUNCH = 1 << 24  # rays per integrator call (memory)


# ---------------------------------------------------------------------------------------------
# The modified-Phong BSDF
# ---------------------------------------------------------------------------------------------

_REGISTERED = False


def register_phong_bsdf() -> str:
    """Register the normalised modified-Phong BSDF as Mitsuba plugin ``modphong`` (once); its name.

    Properties: ``exponent`` (s > 0, default 10), ``reflectance`` (k_s in [0, 1], default 1), and
    ``eval_scale`` (default 1): multiplies ``eval`` only, leaving ``sample``/``pdf`` alone — a deliberate
    inconsistency used by the ``ibl`` power checks (e.g. (s + 1)/(s + 2): the Phong lobe's normalisation
    written in ``eval`` instead of the BRDF's), never in a reference."""
    global _REGISTERED
    init()
    if _REGISTERED:
        return PHONG_PLUGIN
    import drjit as dr
    import mitsuba as mi

    class ModifiedPhong(mi.BSDF):
        def __init__(self, props: Any) -> None:
            super().__init__(props)
            self.s = float(props.get("exponent", 10.0))
            self.ks = float(props.get("reflectance", 1.0))
            self.eval_scale = float(props.get("eval_scale", 1.0))  # power checks only (register_phong_bsdf)
            if not (self.s > 0 and 0.0 <= self.ks <= 1.0):
                raise ValidateError(f"modphong: exponent={self.s}, reflectance={self.ks}: expected exponent > 0 "
                                    "and reflectance in [0, 1]")
            self.m_flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            self.m_components = [self.m_flags]

        def _lobe(self, si: Any, wo: Any) -> Any:
            r = mi.Vector3f(-si.wi.x, -si.wi.y, si.wi.z)
            return dr.power(dr.maximum(dr.dot(r, wo), 0.0), self.s)

        def sample(self, ctx: Any, si: Any, sample1: Any, sample2: Any, active: Any = True) -> Any:
            cos_i = mi.Frame3f.cos_theta(si.wi)
            r = mi.Vector3f(-si.wi.x, -si.wi.y, si.wi.z)
            ca = dr.power(sample2.x, 1.0 / (self.s + 1.0))
            sa = dr.safe_sqrt(1.0 - ca * ca)
            phi = 2.0 * dr.pi * sample2.y
            local = mi.Vector3f(sa * dr.cos(phi), sa * dr.sin(phi), ca)
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = mi.Frame3f(r).to_world(local)
            bs.pdf = (self.s + 1.0) / (2.0 * dr.pi) * dr.power(ca, self.s)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            cos_o = mi.Frame3f.cos_theta(bs.wo)
            ok = active & (cos_i > 0) & (cos_o > 0) & ctx.is_enabled(mi.BSDFFlags.GlossyReflection)
            weight = self.ks * (self.s + 2.0) / (self.s + 1.0) * cos_o
            return bs, dr.select(ok, mi.Spectrum(weight), mi.Spectrum(0.0))

        def eval(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            cos_i, cos_o = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(wo)
            v = self.eval_scale * self.ks * (self.s + 2.0) / (2.0 * dr.pi) * self._lobe(si, wo) * cos_o
            ok = active & (cos_i > 0) & (cos_o > 0) & ctx.is_enabled(mi.BSDFFlags.GlossyReflection)
            return dr.select(ok, mi.Spectrum(v), mi.Spectrum(0.0))

        def pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            cos_i, cos_o = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(wo)
            p = (self.s + 1.0) / (2.0 * dr.pi) * self._lobe(si, wo)
            ok = active & (cos_i > 0) & (cos_o > 0) & ctx.is_enabled(mi.BSDFFlags.GlossyReflection)
            return dr.select(ok, p, 0.0)

        def eval_pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def traverse(self, callback: Any) -> None:
            return None

        def to_string(self) -> str:
            return f"ModifiedPhong[exponent={self.s}, reflectance={self.ks}, eval_scale={self.eval_scale}]"

    mi.register_bsdf(PHONG_PLUGIN, lambda props: ModifiedPhong(props))
    _REGISTERED = True
    return PHONG_PLUGIN


@functools.lru_cache(maxsize=8)
def gauss_legendre(nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [−1, 1] (memoised: the eigenvalue solve costs O(n³))."""
    return np.polynomial.legendre.leggauss(nodes)


def phong_albedo(s: float, cos_theta_v: float, nodes: int = 256) -> float:
    """Directional albedo of the modified-Phong BRDF (k_s = 1) by independent quadrature:
    a(θ_v) = ∫_{H(n)} (s + 2)/(2π) max(0, r·ω)^s cos θ_ω dω, over a lobe-centred (α, φ) Gauss–Legendre
    grid (α ∈ [0, π/2], where cos^s α lives), with the horizon as an indicator. 1 at normal incidence."""
    mu = float(np.clip(cos_theta_v, -1.0, 1.0))
    sv = np.sqrt(1.0 - mu * mu)
    r = np.array([-sv, 0.0, mu])  # the view is (sv, 0, μ)
    e1 = np.array([mu, 0.0, sv])  # ⟂ r, in the plane of incidence
    e2 = np.array([0.0, 1.0, 0.0])
    # α-nodes concentrated where cos^s α lives: substitute α = β·min(π/2, 8/√s), then the tail to π/2
    xa, wa = gauss_legendre(nodes)
    amax = min(np.pi / 2, 8.0 / np.sqrt(s))
    alpha = 0.5 * (xa + 1.0) * amax
    walpha = 0.5 * amax * wa
    xp, wp = gauss_legendre(2 * nodes)
    phi = (xp + 1.0) * np.pi
    wphi = np.pi * wp
    a, p = np.meshgrid(alpha, phi, indexing="ij")
    w = np.sin(a) * walpha[:, None] * wphi[None, :]
    d = (np.cos(a)[..., None] * r + (np.sin(a) * np.cos(p))[..., None] * e1
         + (np.sin(a) * np.sin(p))[..., None] * e2)
    cos_o = d[..., 2]
    f = (s + 2.0) / (2.0 * np.pi) * np.power(np.cos(a), s) * np.maximum(cos_o, 0.0)
    return float(np.sum(f * w))


# ---------------------------------------------------------------------------------------------
# Geometry and camera
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class DentSpec:
    """A unit sphere with a smooth crater: radius 1 − depth·cos²(πψ/2γ) within angle γ of ``axis``."""

    depth: float = 0.45
    width_deg: float = 55.0
    axis: tuple[float, float, float] = (0.5, 0.2, 0.84)
    resolution: int = 48  # vertices per cube-face edge (6·48² ≈ 14k vertices)


def dented_sphere_vertices(spec: DentSpec) -> tuple[np.ndarray, np.ndarray]:
    """(positions (V, 3), faces (F, 3)): a welded cube-sphere grid displaced by the crater."""
    if not (0.0 <= spec.depth < 1.0 and 0.0 < spec.width_deg <= 180.0 and spec.resolution >= 2):
        raise ValidateError(f"dented sphere {spec}: expected 0 ≤ depth < 1, 0 < width ≤ 180°, resolution ≥ 2")

    k = spec.resolution
    g = np.linspace(-1.0, 1.0, k + 1)
    tc, sc = np.meshgrid(g, g, indexing="ij")
    verts, faces = [], []
    for f in range(6):
        d = face_direction(f, sc, tc).reshape(-1, 3)
        base = f * (k + 1) ** 2
        verts.append(d / np.linalg.norm(d, axis=-1, keepdims=True))
        i, j = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")
        v00 = base + i * (k + 1) + j
        v01, v10, v11 = v00 + 1, v00 + k + 1, v00 + k + 2
        quad = np.stack([v00, v10, v11, v01], -1).reshape(-1, 4)
        faces += [quad[:, [0, 1, 2]], quad[:, [0, 2, 3]]]
    dirs = np.concatenate(verts)
    tri = np.concatenate(faces)
    # weld the duplicated edge vertices so normals are smooth across cube-face seams
    key = np.round(dirs * 1e6).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    dirs = dirs[first]
    tri = inverse.ravel()[tri]
    # orient counter-clockwise seen from outside
    a, b, c = dirs[tri[:, 0]], dirs[tri[:, 1]], dirs[tri[:, 2]]
    flip = np.sum(np.cross(b - a, c - a) * (a + b + c), axis=-1) < 0
    tri[flip] = tri[flip][:, [0, 2, 1]]
    axis = np.asarray(spec.axis, dtype=np.float64)
    axis /= np.linalg.norm(axis)
    psi = np.arccos(np.clip(dirs @ axis, -1.0, 1.0))
    gamma = np.radians(spec.width_deg)
    bump = np.where(psi < gamma, np.cos(0.5 * np.pi * psi / gamma) ** 2, 0.0)
    return dirs * (1.0 - spec.depth * bump)[:, None], tri.astype(np.uint32)


def dented_sphere_mesh(spec: DentSpec, bsdf: dict) -> Any:
    """The dented sphere as a Mitsuba ``Mesh`` with smooth (area-weighted) vertex normals."""
    import drjit as dr
    import mitsuba as mi

    init()
    pos, tri = dented_sphere_vertices(spec)
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    mesh = mi.Mesh("dented_sphere", pos.shape[0], tri.shape[0], props=props, has_vertex_normals=True)
    params = mi.traverse(mesh)
    params["vertex_positions"] = dr.ravel(mi.Point3f(pos.T.astype(np.float32)))
    params["faces"] = dr.ravel(mi.Vector3u(tri.T))
    params.update()
    mesh.recompute_vertex_normals()
    return mesh


@dataclass(frozen=True)
class Camera:
    """Orthographic camera at unit direction ``direction`` from the origin (module docstring)."""

    direction: tuple[float, float, float]
    size: int = 64
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        c = np.asarray(self.direction, dtype=np.float64)
        c /= np.linalg.norm(c)
        fwd = -c
        right = np.cross(fwd, np.asarray(self.up, dtype=np.float64))
        if np.linalg.norm(right) < 1e-6:
            right = np.cross(fwd, np.array([0.0, 0.0, 1.0]))
        right /= np.linalg.norm(right)
        return c, right, np.cross(right, fwd)

    def rays(self) -> tuple[np.ndarray, np.ndarray]:
        """(origins (S·S, 3), directions (S·S, 3)) of the pixel-centre rays, row-major from the top left."""
        if not 1 <= self.size <= 4096:
            raise ValidateError(f"camera size {self.size}: expected 1…4096 pixels")
        c, right, up = self.basis()
        t = (np.arange(self.size) + 0.5) / self.size * 2.0 - 1.0
        yy, xx = np.meshgrid(-t, t, indexing="ij")
        o = CAMERA_DISTANCE * c + HALF_WIDTH * (xx[..., None] * right + yy[..., None] * up)
        return o.reshape(-1, 3), np.broadcast_to(-c, o.shape).reshape(-1, 3).copy()


def camera_towards(direction: np.ndarray, azimuth_offset_deg: float, size: int) -> Camera:
    """A camera at ``direction`` rotated about +y by ``azimuth_offset_deg`` (e.g. just off a key light)."""
    a = np.radians(azimuth_offset_deg)
    rot = np.array([[np.cos(a), 0.0, np.sin(a)], [0.0, 1.0, 0.0], [-np.sin(a), 0.0, np.cos(a)]])
    d = rot @ (np.asarray(direction, dtype=np.float64) / np.linalg.norm(direction))
    return Camera(tuple(float(x) for x in d), size)


# ---------------------------------------------------------------------------------------------
# Rendering
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class RenderSpec:
    """What to render: shape ("sphere" | "dented"), BSDF dict, camera, samples, passes, seed, depth."""

    shape: str
    bsdf: dict
    camera: Camera
    spp: int = 64
    passes: int = 8
    seed: int = 0
    max_depth: int = 2
    dent: DentSpec = DentSpec()
    sampler: str = "ldsampler"
    crop_deg: float | None = None  # render only pixels whose view angle θ_v = ∠(n, v) ≤ crop_deg

    def key(self, env: Environment) -> dict:
        return {"env": env.digest, "shape": self.shape, "bsdf": json.dumps(self.bsdf, sort_keys=True),
                "camera": asdict(self.camera), "spp": self.spp, "passes": self.passes, "seed": self.seed,
                "max_depth": self.max_depth, "dent": asdict(self.dent) if self.shape == "dented" else None,
                "sampler": self.sampler, "crop_deg": self.crop_deg, "version": RENDER_VERSION}


@dataclass
class Render:
    """A reference render: radiance mean and standard error (S, S, 3), the standard error of its
    luminance (S, S) (from the pass luminances: the channels' errors are correlated), G-buffer, mask
    (object pixels actually rendered); NaN elsewhere."""

    mean: np.ndarray
    stderr: np.ndarray
    stderr_y: np.ndarray
    normal: np.ndarray
    position: np.ndarray
    view: np.ndarray
    mask: np.ndarray
    spec: RenderSpec

    @property
    def cos_view(self) -> np.ndarray:
        """n·v per pixel (S, S); NaN off the object."""
        return np.sum(self.normal * self.view, axis=-1)


def build_scene(env: Environment, spec: RenderSpec) -> Any:
    import mitsuba as mi

    init()
    if spec.bsdf.get("type") == PHONG_PLUGIN or PHONG_PLUGIN in json.dumps(spec.bsdf):
        register_phong_bsdf()
    if spec.shape == "sphere":
        shape: Any = {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0, "bsdf": spec.bsdf}
    elif spec.shape == "dented":
        shape = dented_sphere_mesh(spec.dent, spec.bsdf)
    else:
        raise ValidateError(f"shape {spec.shape!r}: expected 'sphere' or 'dented'")
    return mi.load_dict({"type": "scene", "emitter": env.mitsuba_emitter(), "shape": shape})


def _ray(origins: np.ndarray, directions: np.ndarray) -> Any:
    import mitsuba as mi

    return mi.Ray3f(mi.Point3f(origins.T.astype(np.float32)), mi.Vector3f(directions.T.astype(np.float32)))


def gbuffer(scene: Any, camera: Camera) -> dict[str, np.ndarray]:
    """Normals, positions, views and hit mask (S·S,) of the pixel-centre rays."""
    o, d = camera.rays()
    si = scene.ray_intersect(_ray(o, d))
    mask = np.array(si.is_valid(), dtype=bool)
    n = np.array(si.sh_frame.n, dtype=np.float64).reshape(3, -1).T
    p = np.array(si.p, dtype=np.float64).reshape(3, -1).T
    n[~mask] = np.nan
    p[~mask] = np.nan
    v = -d.astype(np.float64)
    v[~mask] = np.nan
    return {"normal": n, "position": p, "view": v, "mask": mask}


def _trace(scene: Any, integrator: Any, origins: np.ndarray, directions: np.ndarray, spp: int,
           seed: int, sampler_type: str) -> np.ndarray:
    """Mean radiance (K, 3) of ``spp`` paths along each of K rays (one sampler launch per ray batch;
    the lanes of a ray are consecutive, so a stratified sampler stratifies each ray's own samples)."""
    import drjit as dr
    import mitsuba as mi

    k = origins.shape[0]
    out = np.zeros((k, 3))
    per = max(1, MAX_SPP_PER_LAUNCH // spp)
    for s in range(0, k, per):
        o, d = origins[s:s + per], directions[s:s + per]
        m = o.shape[0]
        idx = dr.arange(mi.UInt32, m * spp) // spp
        ray = _ray(o, d)
        ray = mi.Ray3f(dr.gather(mi.Point3f, ray.o, idx), dr.gather(mi.Vector3f, ray.d, idx))
        sampler = mi.load_dict({"type": sampler_type, "sample_count": spp})
        sampler.set_samples_per_wavefront(spp)
        sampler.seed(seed + s, m * spp)
        value, valid, _ = integrator.sample(scene, sampler, mi.RayDifferential3f(ray))
        value = dr.select(valid, value, 0.0)
        dr.eval(value)  # one kernel for the three channels (block_sum would trace each channel's paths anew)
        out[s:s + m] = np.array(dr.block_sum(value, spp) / spp, dtype=np.float64).reshape(3, -1).T
    return out


def render(env: Environment, spec: RenderSpec) -> Render:
    """Render (or load from the cache) the reference image and G-buffer of ``spec`` under ``env``."""
    import mitsuba as mi

    if spec.passes < 2 or spec.passes > MAX_PASSES or spec.spp < spec.passes or spec.spp % spec.passes:
        raise ValidateError(f"render: spp={spec.spp}, passes={spec.passes}: need 2 ≤ passes ≤ {MAX_PASSES} "
                            "and spp a multiple of passes")
    per = spec.spp // max(spec.passes, 1)
    if spec.sampler == "ldsampler" and (per & (per - 1) or per.bit_length() % 2 == 0):
        raise ValidateError(f"render: {per} samples per pass with ldsampler: expected a power of 4 (16, 64, 256, …)")
    if spec.max_depth < 2:
        raise ValidateError(f"render: max_depth={spec.max_depth}: expected ≥ 2 (camera ray + one bounce)")

    def compute() -> dict[str, np.ndarray]:
        scene = build_scene(env, spec)
        integrator = mi.load_dict({"type": "path", "max_depth": spec.max_depth})
        g = gbuffer(scene, spec.camera)
        o, d = spec.camera.rays()
        hit = g["mask"].copy()
        if spec.crop_deg is not None:
            cos_v = np.sum(np.nan_to_num(g["normal"]) * np.nan_to_num(g["view"]), axis=-1)
            hit &= cos_v >= np.cos(np.radians(spec.crop_deg))
        per_pass = spec.spp // spec.passes
        passes = np.stack([_trace(scene, integrator, o[hit], d[hit], per_pass, spec.seed * MAX_PASSES + p,
                                  spec.sampler) for p in range(spec.passes)])
        mean = np.full((o.shape[0], 3), np.nan)
        err = np.full((o.shape[0], 3), np.nan)
        mean[hit], err[hit] = mean_and_stderr(passes)
        err_y = np.full(o.shape[0], np.nan)
        err_y[hit] = mean_and_stderr(luminance(passes))[1]
        g["mask"] = hit
        return {"mean": mean, "stderr": err, "stderr_y": err_y, **g}

    r = cached("ibl_render", spec.key(env), compute)
    s = spec.camera.size
    return Render(r["mean"].reshape(s, s, 3), r["stderr"].reshape(s, s, 3), r["stderr_y"].reshape(s, s),
                  r["normal"].reshape(s, s, 3), r["position"].reshape(s, s, 3), r["view"].reshape(s, s, 3),
                  r["mask"].reshape(s, s), spec)


def ambient_occlusion(env: Environment, spec: RenderSpec, samples: int = 256, seed: int = 7
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Cosine-weighted visibility A(x) = (1/π) ∫ V(x, ω) max(0, n·ω) dω of the G-buffer points, by
    ``samples`` cosine-distributed shadow rays (``scene.ray_test``) per pixel: (mean, standard error),
    (S, S) each; NaN off the object."""
    import drjit as dr
    import mitsuba as mi

    def compute() -> dict[str, np.ndarray]:
        scene = build_scene(env, spec)
        g = gbuffer(scene, spec.camera)
        hit = g["mask"]
        n, p = g["normal"][hit], g["position"][hit]
        m = n.shape[0]
        idx = dr.arange(mi.UInt32, m * samples) // samples
        frame = mi.Frame3f(dr.gather(mi.Vector3f, mi.Vector3f(n.T.astype(np.float32)), idx))
        origin = dr.gather(mi.Point3f, mi.Point3f(p.T.astype(np.float32)), idx)
        sampler = mi.load_dict({"type": "independent"})
        sampler.seed(seed, m * samples)
        d = frame.to_world(mi.warp.square_to_cosine_hemisphere(sampler.next_2d()))
        ray = mi.Ray3f(origin + d * 1e-4 + frame.n * 1e-4, d)
        vis = dr.select(scene.ray_test(ray), 0.0, 1.0)
        mean = np.array(dr.block_sum(vis, samples) / samples, dtype=np.float64)
        a = np.full(hit.shape, np.nan)
        e = np.full(hit.shape, np.nan)
        a[hit] = mean
        e[hit] = np.sqrt(mean * (1.0 - mean) / max(samples - 1, 1))
        return {"ao": a, "stderr": e}

    key = dict(spec.key(env), ao_samples=samples, ao_seed=seed, bsdf="")
    r = cached("ibl_ao", key, compute)
    s = spec.camera.size
    return r["ao"].reshape(s, s), r["stderr"].reshape(s, s)


def bsdf_albedo(bsdf: dict, cos_theta_v: float, samples: int = 1 << 18, seed: int = 3) -> tuple[float, float]:
    """Directional albedo ∫ f cos θ_o dω_o of a Mitsuba BSDF (any plugin) at incidence cos θ_v, by its own
    importance sampling: mean and standard error of ``sample``'s weights (red channel; the BSDFs used
    here are grey)."""
    import drjit as dr
    import mitsuba as mi

    init()
    if PHONG_PLUGIN in json.dumps(bsdf):
        register_phong_bsdf()
    b = mi.load_dict(bsdf)
    mu = float(np.clip(cos_theta_v, 0.0, 1.0))
    si = dr.zeros(mi.SurfaceInteraction3f, samples)
    si.wi = mi.Vector3f(float(np.sqrt(1.0 - mu * mu)), 0.0, mu)
    si.sh_frame = mi.Frame3f(mi.Vector3f(0.0, 0.0, 1.0))
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(seed, samples)
    _, w = b.sample(mi.BSDFContext(), si, sampler.next_1d(), sampler.next_2d())
    w = np.array(w, dtype=np.float64).reshape(3, -1)[0]
    m, se = mean_and_stderr(w)
    return float(m), float(se)


# ---------------------------------------------------------------------------------------------
# BSDF checks: white furnace through the path integrator, χ² of the sampling routine
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class FurnaceResult:
    """Outgoing radiance of a unit sphere under a uniform white environment (L = 1) at views with
    n·v = ``cos_views``: pass mean and standard error per view (red channel), P = ``passes``."""

    cos_views: np.ndarray
    mean: np.ndarray
    stderr: np.ndarray
    passes: int
    spp: int


def furnace(bsdf: dict, cos_views: np.ndarray, spp: int = 1 << 16, passes: int = 8, seed: int = 11,
            rays: int = 64) -> FurnaceResult:
    """White furnace through Mitsuba's ``path`` integrator (``max_depth`` 2, MIS of emitter and BSDF
    sampling, so ``eval``, ``pdf`` and ``sample`` all enter): a unit sphere with ``bsdf`` under a
    ``constant`` emitter of radiance 1, hit by ``rays`` orthographic rays along −z whose hit point has
    n·v = μ. Then L_o(μ) = ∫ f cos θ_o dω_o, the BSDF's directional albedo [1, §5.6.1] — what a
    quadrature of the BRDF (e.g. :func:`phong_albedo`) must equal. Each view gets ``passes`` independent
    passes (``independent`` sampler, seeds ``seed·1000 + p``) of rays·spp/passes paths."""
    import mitsuba as mi

    init()
    if PHONG_PLUGIN in json.dumps(bsdf):
        register_phong_bsdf()
    mus = np.asarray(cos_views, dtype=np.float64).ravel()
    if not (np.all(mus > 0) and np.all(mus <= 1)) or passes < 2 or spp % passes:
        raise ValidateError(f"furnace: cos_views in (0, 1], passes ≥ 2, spp a multiple of passes; got "
                            f"{mus.tolist()}, spp={spp}, passes={passes}")
    scene = mi.load_dict({"type": "scene", "emitter": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
                          "shape": {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0, "bsdf": bsdf}})
    integrator = mi.load_dict({"type": "path", "max_depth": 2})
    x = np.sqrt(np.clip(1.0 - mus * mus, 0.0, 1.0)) * (1.0 - 1e-6)
    o = np.repeat(np.stack([x, np.zeros_like(x), np.full_like(x, CAMERA_DISTANCE)], -1), rays, axis=0)
    d = np.broadcast_to(np.array([0.0, 0.0, -1.0]), o.shape).copy()
    per = spp // passes
    vals = np.stack([_trace(scene, integrator, o, d, per, seed * MAX_PASSES + p, "independent")[:, 0]
                     .reshape(len(mus), rays).mean(axis=1) for p in range(passes)])
    mean, se = mean_and_stderr(vals)
    return FurnaceResult(mus, mean, se, passes, spp * rays)


@dataclass(frozen=True)
class Chi2Result:
    """Pearson χ² of a BSDF's ``sample`` against its ``pdf`` (Mitsuba's ``ChiSquareTest``)."""

    p_value: float
    statistic_ok: bool  # False when Mitsuba's sanity checks failed (samples outside the domain, …)
    messages: str


def chi2_bsdf(bsdf: dict, cos_view: float, pdf_bsdf: dict | None = None, samples: int = 2_000_000,
              res: int = 101, ires: int = 16, seed: int = 5) -> Chi2Result:
    """``mitsuba.chi2.ChiSquareTest`` with its ``BSDFAdapter`` [2]: histogram of ``samples`` directions from
    ``bsdf``'s ``sample`` on the sphere (``SphericalDomain``, res × 2res cells; odd res so no cell edge lies
    on the horizon) against ``pdf`` integrated per cell (trapezoid rule, ires² points per cell: 16 resolves
    a lobe of 1/√100 rad in 1.8° cells), cells with expected count < 5 pooled. ``pdf_bsdf`` (default
    ``bsdf``) supplies the pdf: a different one is the power check (does the test see a wrong pdf?).
    The view is (√(1 − μ²), 0, μ) in the local frame; returns the p-value (0 if a sanity check failed)."""
    from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain

    init()
    for b in (bsdf, pdf_bsdf or bsdf):
        if b.get("type") == PHONG_PLUGIN:
            register_phong_bsdf()
    mu = float(np.clip(cos_view, 0.0, 1.0))
    wi = [float(np.sqrt(1.0 - mu * mu)), 0.0, mu]
    sample_fn, _ = BSDFAdapter(bsdf["type"], bsdf, wi=wi)
    _, pdf_fn = BSDFAdapter((pdf_bsdf or bsdf)["type"], pdf_bsdf or bsdf, wi=wi)
    test = ChiSquareTest(SphericalDomain(), sample_fn, pdf_fn, sample_dim=3, sample_count=samples, res=res,
                         ires=ires, seed=seed)
    test.run(significance_level=0.01, test_count=1, quiet=True)
    ok = not test.fail
    p = float(test.p_value) if ok and test.p_value is not None and np.isfinite(test.p_value) else 0.0
    return Chi2Result(p, ok, test.messages)
