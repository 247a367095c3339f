"""Ground truth for the ``brdfs`` experiment: Mitsuba BSDF evaluations and a path-traced V-groove microsurface.

BSDF evaluation
  :func:`eval_bsdf` calls Mitsuba's ``BSDF.eval(ctx, si, wo)`` directly (no rendering, no noise):
  ``si.wi`` = v (towards the viewer), ``wo`` = l (towards the light), both in the local frame (normal +z),
  ``si.sh_frame`` the identity frame. It returns f_r(l, v)·cos θ_l — the ``brdf`` family's quantity —
  in single precision (float32: relative rounding ≈ 1e-6 per operation).

V-groove microsurface (Oren & Nayar's V-cavity surface [1], path traced)
  For facet slope θ_a: the mesh of :func:`validate.scenes.brdf_scenes.vgroove_mesh` (Lambertian facets of
  albedo ρ, many grooves in the measured footprint), a directional light of unit perpendicular irradiance
  from l and an orthographic viewer along v (all slopes of a σ in one scene, the meshes side by side, so that
  every bounce is one wavefront). The groove orientation φ_a is applied by rotating l and v by
  −φ_a about z. A path starts at a uniform point p of the central footprint square of the mean plane (an
  orthographic pixel averages radiance over the projected area, i.e. uniformly over the mean plane), is
  traced along −v from above, and at each facet hit x (normal n_f) adds next-event estimation
  throughput·ρ/π·max(0, n_f·l)·V(x, l) (V: shadow ray) and continues in a cosine-distributed direction
  about n_f with throughput ×ρ (f cos/pdf = ρ), up to ``depth`` facet hits (inter-reflections; missing
  the mesh ends the path: there is no other light). The mean over paths estimates the macroscopic
  f_r·cos θ_l; its standard error is sd/√N (independent paths, fixed seed). The macroscopic value of the
  isotropic surface is Σ_a w_a · value(θ_a, φ_a) with the Gaussian slope weights of
  :func:`validate.scenes.brdf_scenes.vgroove_quadrature`; its uncertainty √(Σ w_a² se_a²).

  Path depth: the energy left after D bounces is at most ρ^D of the first bounce's, so the truncation
  bias is below ρ^D/(1 − ρ) of the single-scattering value (ρ = 0.8, D = 12: 0.34 %; measured smaller,
  because most bounced light escapes a V-groove).

References
  [1] M. Oren, S. K. Nayar, "Generalization of Lambert's reflectance model", SIGGRAPH 1994 (V-cavity
      model §3, Gaussian slope distribution).
  [2] M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering*, 4th ed., §13 (path tracing, next-
      event estimation) and §2.1 (Monte Carlo error).
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from ..backend import init, pad_rows, padded_count
from ..errors import ValidateError
from ..scenes import brdf_scenes as bs
from .cache import cached
from .ibl_render import PHONG_PLUGIN, register_phong_bsdf

VGROOVE_VERSION = 2
RAY_EPS = 1e-6


def load_bsdf(bsdf: dict[str, Any]) -> Any:
    """Mitsuba BSDF object of a dict (registers the suite's modified-Phong plugin when named)."""
    import mitsuba as mi

    init()
    if PHONG_PLUGIN in json.dumps(bsdf):
        register_phong_bsdf()
    return mi.load_dict(bsdf)


def eval_bsdf(bsdf: dict[str, Any], lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    """f_r(l, v)·cos θ_l from Mitsuba's ``BSDF.eval`` (local frame, normal +z), (N, 3) float64."""
    import drjit as dr
    import mitsuba as mi

    b = load_bsdf(bsdf)
    if not init().is_vectorized:
        raise ValidateError("eval_bsdf: needs a vectorised Mitsuba variant (llvm_ad_rgb or cuda_ad_rgb)")
    lights = np.ascontiguousarray(lights, dtype=np.float32)
    views = np.ascontiguousarray(views, dtype=np.float32)
    if lights.shape != views.shape or lights.ndim != 2 or lights.shape[1] != 3:
        raise ValidateError(f"eval_bsdf: lights {lights.shape} and views {views.shape} must both be (N, 3)")
    si = dr.zeros(mi.SurfaceInteraction3f, len(views))
    si.wi = mi.Vector3f(views[:, 0], views[:, 1], views[:, 2])
    si.sh_frame = mi.Frame3f(mi.Vector3f(0.0, 0.0, 1.0))
    wo = mi.Vector3f(lights[:, 0], lights[:, 1], lights[:, 2])
    out = b.eval(mi.BSDFContext(), si, wo)
    return np.array(out, dtype=np.float64).reshape(3, -1).T.copy()


# ---------------------------------------------------------------------------------------------
# V-grooves

SLOPE_SPACING = 3.0  # x offset between the groove meshes of different slopes in one scene (mesh side 1)


def _mesh_scene(slopes: np.ndarray) -> Any:
    """One scene holding a V-groove mesh per slope, the k-th shifted by k·SLOPE_SPACING along x (no ray leaves one
    mesh for another: all geometry lies below z = 0 and the meshes are 2 units apart)."""
    import mitsuba as mi

    shapes: dict[str, Any] = {"type": "scene"}
    for k, slope in enumerate(slopes):
        verts, faces = bs.vgroove_mesh(float(slope))
        verts = verts + np.array([k * SLOPE_SPACING, 0.0, 0.0])
        mesh = mi.Mesh(f"vgrooves{k}", len(verts), len(faces), has_vertex_normals=False)
        params = mi.traverse(mesh)
        params["vertex_positions"] = mi.Float(verts.astype(np.float32).ravel())
        params["faces"] = mi.UInt32(faces.astype(np.uint32).ravel())
        params.update()
        shapes[f"grooves{k}"] = mesh
    return mi.load_dict(shapes)


def _rays(origins: np.ndarray, dirs: np.ndarray) -> tuple[Any, int]:
    """Mitsuba rays of (M, 3) origins and directions, padded to :func:`validate.backend.padded_count` rows (the
    last row repeated; see there), each component imported from its own contiguous float32 row; (rays, M)."""
    import mitsuba as mi

    m = origins.shape[0]
    o, d = (np.ascontiguousarray(pad_rows(a, padded_count(m)).T) for a in (origins, dirs))
    return mi.Ray3f(mi.Point3f(o[0], o[1], o[2]), mi.Vector3f(d[0], d[1], d[2])), m


def _intersect(scene: Any, origins: np.ndarray, dirs: np.ndarray,
               hits_only: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(hit mask, hit points, geometric normals oriented to +z) of rays (points and normals of the hits only, in
    ray order, with ``hits_only``). The three outputs are evaluated in one kernel (``dr.eval``): read one by one,
    each would launch its own kernel and trace the rays again."""
    import drjit as dr

    ray, m = _rays(origins, dirs)
    si = scene.ray_intersect(ray)
    valid, pos, nrm = si.is_valid(), si.p, si.n
    dr.eval(valid, pos, nrm)
    hit = np.array(valid, dtype=bool)[:m]
    if hits_only:  # select in float32, then widen (exact): only the hits are converted
        p = np.array(pos).reshape(3, -1)[:, :m][:, hit].T.astype(np.float64)
        n = np.array(nrm).reshape(3, -1)[:, :m][:, hit].T.astype(np.float64)
    else:
        p = np.array(pos, dtype=np.float64).reshape(3, -1).T[:m]
        n = np.array(nrm, dtype=np.float64).reshape(3, -1).T[:m]
    n = np.where(n[:, 2:3] < 0.0, -n, n)
    return hit, p, n


def _occluded(scene: Any, origins: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    ray, m = _rays(origins, dirs)
    return np.array(scene.ray_test(ray), dtype=bool)[:m]


def _cross(a: tuple[np.ndarray, ...], b: tuple[np.ndarray, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """a × b by components: (a₁b₂ − a₂b₁, a₂b₀ − a₀b₂, a₀b₁ − a₁b₀), the products and differences ``np.cross``
    forms (same float64 results), without its (N, 3) temporaries."""
    return a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]


def _cosine_about(n: np.ndarray, u1: np.ndarray, u2: np.ndarray) -> np.ndarray:
    """Cosine-distributed directions about unit normals n (pdf cos θ/π): local (√u₁ cos 2πu₂, √u₁ sin 2πu₂,
    √(1 − u₁)) in the frame t = n × a/|n × a|, b = n × t (a = y where |n_x| > 0.9, else x)."""
    r, phi = np.sqrt(u1), 2.0 * np.pi * u2
    lx, ly, lz = r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(1.0 - u1, 0.0))
    nc = (n[:, 0], n[:, 1], n[:, 2])
    ya = np.abs(nc[0]) > 0.9
    t = _cross(nc, (np.where(ya, 0.0, 1.0), np.where(ya, 1.0, 0.0), np.zeros(len(n))))
    norm = np.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
    t = (t[0] / norm, t[1] / norm, t[2] / norm)
    b = _cross(nc, t)
    return np.stack([lx * t[k] + ly * b[k] + lz * nc[k] for k in range(3)], -1)


Vec = tuple[np.ndarray, np.ndarray, np.ndarray]


def _padded_block(comps: Vec, count: int) -> np.ndarray:
    """Three ray components (M,) as one C-contiguous (3, count) float32 block, count ≥ M, each row's last entry
    repeated (0 when M = 0): the rows :func:`_rays` imports (the transposed :func:`validate.backend.pad_rows` of the
    (M, 3) rows, the same buffer layout), without the (count, 3) temporaries."""
    out = np.empty((3, count), dtype=np.float32)
    m = len(comps[0])
    for row, c in zip(out, comps, strict=True):
        row[:m] = c
        row[m:] = c[m - 1] if m else 0.0
    return out


def _rays_soa(origins: Vec, dirs: Vec) -> tuple[Any, int]:
    """:func:`_rays` of origins and directions given by components (three (M,) arrays each): the same float32 rays,
    padded the same way to :func:`validate.backend.padded_count` rows; (rays, M)."""
    import mitsuba as mi

    m = len(origins[0])
    count = padded_count(m)
    o, d = _padded_block(origins, count), _padded_block(dirs, count)
    return mi.Ray3f(mi.Point3f(o[0], o[1], o[2]), mi.Vector3f(d[0], d[1], d[2])), m


def _intersect_hits(scene: Any, origins: Vec, dirs: Vec) -> tuple[np.ndarray, Vec, Vec]:
    """:func:`_intersect` with ``hits_only`` by components: (hit mask (M,), hit points, geometric normals oriented to
    +z), the points and normals of the hits only (ray order) as three float64 (H,) arrays each. The float32 results
    are selected and the normals flipped (exact) before widening (exact), the same numbers as :func:`_intersect`."""
    import drjit as dr

    ray, m = _rays_soa(origins, dirs)
    si = scene.ray_intersect(ray)
    valid, pos, nrm = si.is_valid(), si.p, si.n
    dr.eval(valid, pos, nrm)
    hit = np.array(valid, dtype=bool)[:m]
    # component by component: numpy's import of a whole Point3f takes a slow generic path (≈ 20× the three Floats)
    p = tuple(np.array(c)[:m][hit].astype(np.float64) for c in (pos.x, pos.y, pos.z))
    nh = [np.array(c)[:m][hit] for c in (nrm.x, nrm.y, nrm.z)]
    flip = nh[2] < 0.0
    n = tuple(np.where(flip, -c, c).astype(np.float64) for c in nh)
    return hit, p, n  # type: ignore[return-value]


def _occluded_soa(scene: Any, origins: Vec, dirs: Vec) -> np.ndarray:
    ray, m = _rays_soa(origins, dirs)
    return np.array(scene.ray_test(ray), dtype=bool)[:m]


def _cosine_about_soa(n: Vec, u1: np.ndarray, u2: np.ndarray) -> Vec:
    """:func:`_cosine_about` by components (the same float64 operations), three (N,) arrays."""
    r, phi = np.sqrt(u1), 2.0 * np.pi * u2
    lx, ly, lz = r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(1.0 - u1, 0.0))
    ya = np.abs(n[0]) > 0.9
    t = _cross(n, (np.where(ya, 0.0, 1.0), np.where(ya, 1.0, 0.0), np.zeros(len(n[0]))))
    norm = np.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
    t = (t[0] / norm, t[1] / norm, t[2] / norm)
    b = _cross(n, t)
    return tuple(lx * t[k] + ly * b[k] + lz * n[k] for k in range(3))  # type: ignore[return-value]


VGROOVE_BLOCK = 1 << 18  # paths per block of the tracer's work (a multiple of RAY_PACKET)


def trace_vgrooves(scene: Any, mesh_index: np.ndarray, lights: np.ndarray, views: np.ndarray, albedo: float,
                   paths: int, depth: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Macroscopic f_r·cos θ_l of V-groove sets (grooves along y; pair m on mesh ``mesh_index[m]`` of
    :func:`_mesh_scene`) for each (l, v) pair: (mean (M,), standard error (M,)) over ``paths`` paths per pair
    (see the module docstring).

    The paths' vectors are kept by components in buffers allocated once ((3, N) float64, the live paths compacted
    to the front after each bounce), and each bounce is worked through in blocks of :data:`VGROOVE_BLOCK` paths
    (small temporaries that the allocator reuses, instead of fresh (N,)-sized ones per operation). Every bounce is
    still one wavefront: its uniform numbers are drawn for all live paths at once, in the same order, so the same
    float64 operations, random numbers and rays as the (N, 3) form (every ray's hit is its own: full ray packets)."""
    rng = np.random.default_rng(seed)
    m = len(views)
    total = m * paths
    k = np.repeat(np.arange(m), paths)
    half = 0.5 * bs.VGROOVE_FOOTPRINT
    px = rng.uniform(-half, half, total) + SLOPE_SPACING * mesh_index[k]
    py = rng.uniform(-half, half, total)
    vz = np.maximum(views[:, 2], 1e-3)[k]
    lgt = tuple(np.ascontiguousarray(lights[:, c])[k] for c in range(3))
    vk = tuple(np.ascontiguousarray(views[:, c])[k] for c in range(3))
    org, dirn, nrm = np.empty((3, total)), np.empty((3, total)), np.empty((3, total))
    org[0], org[1], org[2] = px + 2.0 * vk[0] / vz, py + 2.0 * vk[1] / vz, np.zeros(total) + 2.0 * vk[2] / vz
    for c in range(3):
        dirn[c] = -vk[c]
    del vk, px, py, vz, k
    u1, u2 = np.empty(total), np.empty(total)
    # The live paths are kept compact (entry j = path alive[j]); every live path has had the same number of facet
    # hits, so its throughput ρ^b is one number (the same float64 products as per path).
    throughput = 1.0
    value = np.zeros(total)
    alive = np.arange(total)
    count = total
    for _ in range(depth):
        kept = 0
        for s in range(0, count, VGROOVE_BLOCK):
            e = min(s + VGROOVE_BLOCK, count)
            hit, p, n = _intersect_hits(scene, (org[0, s:e], org[1, s:e], org[2, s:e]),
                                        (dirn[0, s:e], dirn[1, s:e], dirn[2, s:e]))
            idx = alive[s:e][hit]
            nh = len(idx)
            if nh == 0:
                continue
            la = tuple(c[idx] for c in lgt)
            cos_l = n[0] * la[0] + n[1] * la[1] + n[2] * la[2]
            lit = cos_l > 0.0
            origin = (p[0] + RAY_EPS * n[0], p[1] + RAY_EPS * n[1], p[2] + RAY_EPS * n[2])
            occ = np.zeros(nh, dtype=bool)
            if lit.any():
                occ[lit] = _occluded_soa(scene, tuple(c[lit] for c in origin), tuple(c[lit] for c in la))
            value[idx] += np.where(lit & ~occ, throughput * albedo / np.pi * cos_l, 0.0)
            # compaction in place: kept + nh ≤ e, and this block's entries were read above
            alive[kept:kept + nh] = idx
            for c in range(3):
                org[c, kept:kept + nh] = origin[c]
                nrm[c, kept:kept + nh] = n[c]
            kept += nh
        count = kept
        if count == 0:
            break
        throughput *= albedo
        rng.random(out=u1[:count])
        rng.random(out=u2[:count])
        for s in range(0, count, VGROOVE_BLOCK):
            e = min(s + VGROOVE_BLOCK, count)
            d = _cosine_about_soa((nrm[0, s:e], nrm[1, s:e], nrm[2, s:e]), u1[s:e], u2[s:e])
            for c in range(3):
                dirn[c, s:e] = d[c]
    per = value.reshape(m, paths)
    return per.mean(axis=1), per.std(axis=1, ddof=1) / np.sqrt(paths)


def _rotate_z(d: np.ndarray, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1], d[:, 2]], -1)


def vgroove_brdf(sigma: float, lights: np.ndarray, views: np.ndarray, albedo: float, n_slope: int, n_orient: int,
                 paths: int, depth: int, seed: int) -> dict[str, Any]:
    """The isotropic V-groove surface of slope deviation σ (radians): {'value': (M,), 'stderr': (M,), settings},
    cached by its inputs."""
    key = {"sigma": float(sigma), "lights": np.round(lights, 9).tolist(), "views": np.round(views, 9).tolist(),
           "albedo": float(albedo), "n_slope": n_slope, "n_orient": n_orient, "paths": paths, "depth": depth,
           "seed": seed, "count": bs.VGROOVE_COUNT, "footprint": bs.VGROOVE_FOOTPRINT, "version": VGROOVE_VERSION}

    def compute() -> dict[str, Any]:
        init()
        slopes, orients, w = bs.vgroove_quadrature(sigma, n_slope, n_orient)
        ls = np.concatenate([_rotate_z(lights, -a) for a in orients])
        vs = np.concatenate([_rotate_z(views, -a) for a in orients])
        idx = np.repeat(np.arange(len(slopes)), len(ls))
        mean, se = trace_vgrooves(_mesh_scene(slopes), idx, np.tile(ls, (len(slopes), 1)),
                                  np.tile(vs, (len(slopes), 1)), albedo, paths, depth, seed)
        mean = mean.reshape(len(slopes), len(orients), -1)
        se = se.reshape(len(slopes), len(orients), -1)
        total = np.sum(w[..., None] * mean, axis=(0, 1))
        var = np.sum((w[..., None] * se) ** 2, axis=(0, 1))
        return {"value": total, "stderr": np.sqrt(var), "slopes": slopes, "orientations": orients}

    r = cached("brdf_vgroove", key, compute)
    return {k: np.asarray(v) for k, v in r.items()}


# ---------------------------------------------------------------------------------------------
# Shading frames and meshes seen by an orthographic camera

def eval_bsdf_world(bsdf: dict[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    """:func:`eval_bsdf` with world-space unit normals, lights and views (an isotropic BSDF: any tangent frame)."""
    n = np.asarray(normals, dtype=np.float64)
    a = np.where(np.abs(n[:, 1:2]) > 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
    t = np.cross(n, a)
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    b = np.cross(n, t)

    def local(d: np.ndarray) -> np.ndarray:
        return np.stack([np.sum(d * t, -1), np.sum(d * b, -1), np.sum(d * n, -1)], -1)

    return eval_bsdf(bsdf, local(np.asarray(lights, dtype=np.float64)), local(np.asarray(views, dtype=np.float64)))


def mesh_gbuffer(verts: np.ndarray, faces: np.ndarray, x: np.ndarray, y: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Orthographic rays along −z through the points (x, y) against a triangle mesh: (hit (P,), triangle index
    (P,), barycentric coordinates (P, 3) of the hit in its triangle's vertices)."""
    import drjit as dr
    import mitsuba as mi

    init()
    mesh = mi.Mesh("tess", len(verts), len(faces), has_vertex_normals=False)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(verts.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(faces.astype(np.uint32).ravel())
    params.update()
    scene = mi.load_dict({"type": "scene", "mesh": mesh})
    o = np.stack([x.ravel(), y.ravel(), np.full(x.size, 3.0)], -1).astype(np.float32)
    m = o.shape[0]
    o = pad_rows(o, padded_count(m))  # padded: Mitsuba's query reads past a ragged end (backend.padded_count)
    ray = mi.Ray3f(mi.Point3f(o[:, 0], o[:, 1], o[:, 2]), mi.Vector3f(0.0, 0.0, -1.0))
    si = scene.ray_intersect(ray)
    valid, prim_index, pos = si.is_valid(), si.prim_index, si.p
    dr.eval(valid, prim_index, pos)  # one kernel, one trace (see :func:`_intersect`)
    hit = np.array(valid, dtype=bool)[:m]
    prim = np.array(prim_index, dtype=np.int64)[:m]
    p = np.array(pos, dtype=np.float64).reshape(3, -1).T[:m]
    prim = np.where(hit, prim, 0)
    a, b, c = (verts[faces[prim, k]] for k in range(3))
    n = np.cross(b - a, c - a)
    area = np.maximum(np.sum(n * n, -1), 1e-300)
    wa = np.sum(np.cross(b - p, c - p) * n, -1) / area
    wb = np.sum(np.cross(c - p, a - p) * n, -1) / area
    bary = np.clip(np.stack([wa, wb, 1.0 - wa - wb], -1), 0.0, 1.0)
    return hit, prim, bary / bary.sum(-1, keepdims=True)
