"""Reference radiance of a GGX ``roughconductor`` under rectangle, disc, sphere and tube (capsule) emitters: Mitsuba's
own BSDF evaluation integrated over the emitter by deterministic quadrature.

    L_o(p, v) = ∫_light L_e f_r(l, v) (n·l) dω_l

with f_r(l, v)(n·l) = Mitsuba's ``BSDF.eval`` of ``roughconductor`` (``distribution`` ggx, α, η = 0, k = 1: F = 1;
:func:`validate.reference.brdf_render.eval_bsdf_world`) and the emitter a uniform one-sided radiance L_e
(Mitsuba's ``rectangle``/``disk`` area emitters emit from the front face, along their normal; a ``sphere``
emits everywhere). The quadrature (Gauss–Legendre, n nodes per axis) runs over

* rectangle: the two edge coordinates, dω = cos θ_light dA / r²;
* disc: ρ² ∈ [0, R²] (Gauss–Legendre) × φ (2n uniform), dA = ½ dρ² dφ;
* sphere: the cone of directions it subtends, cos θ ∈ [cos σ, 1], sin σ = R/d (Gauss–Legendre) × φ (2n uniform);
* tube: a capsule (the segment c ± (ℓ/2)a swept by a sphere of radius R: a cylinder closed by two hemispheres),
  integrated over the part of its surface the receiver sees, dω = cos θ_light dA / r² (a convex emitter: every
  direction towards it meets exactly one front-facing surface point). Cylinder side: s ∈ [−ℓ/2, ℓ/2] × the visible
  arc φ ∈ [−β, β] about the receiver's side, cos β = R/h (h the receiver's distance to the axis), dA = R ds dφ.
  Each cap (outer hemisphere about its end e, outward axis a_e): the visible cap of its sphere in polar angle t
  about the direction u from e to the receiver, t ∈ [0, γ], cos γ = R/‖p − e‖, split where the hemisphere's rim
  enters (tan t = |u·a_e| / √(1 − (u·a_e)²)), and for each t the azimuth range on the outer half,
  cos φ ≥ −(u·a_e) cos t / (√(1 − (u·a_e)²) sin t), dA = R² sin t dt dφ. Every factor is Gauss–Legendre with n
  nodes; the integration limits follow the visibility and rim boundaries, so each integrand is smooth (no
  indicator functions) apart from the receiver's horizon, as for the other shapes.

Uncertainty: |L(n) − L(n/2)| per receiver (the quadrature's own convergence; Mitsuba's float32 evaluation adds
~10⁻⁶ relative). The sharp lobes of small α need n large enough to resolve the lobe's footprint on the light;
the uncertainty says when it is not.
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping
from functools import lru_cache
from typing import Any

import numpy as np

from ..backend import init, load_scene
from ..errors import ValidateError
from ..geometry import frame, perp, unit
from ..scenes import area_lights
from ..scenes import brdf_scenes as bs
from . import brdf_render as br

CHUNK = 2_000_000  # BSDF evaluations per Mitsuba call


@lru_cache(maxsize=32)
def _leggauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [−1, 1] (cached: the tube's caps ask for them per polar node)."""
    x, w = np.polynomial.legendre.leggauss(n)
    x.flags.writeable = False
    w.flags.writeable = False
    return x, w


def _gl(n: int, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    x, w = _leggauss(n)
    return a + (b - a) * 0.5 * (x + 1.0), (b - a) * 0.5 * w


def light_directions(light: Mapping[str, Any], point: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(unit directions (M, 3) from ``point`` to the light, solid-angle weights (M,)) — zero weight where the
    light's back face is seen."""
    shape = light.get("shape")
    c = np.asarray(light["center"], dtype=np.float64)
    if shape == "tube":
        pts, nrm, da = _tube_surface(light, np.asarray(point, dtype=np.float64), n)
        vec = pts - point
        dist = np.linalg.norm(vec, axis=-1)
        dirs = vec / dist[:, None]
        return dirs, da * np.maximum(-np.sum(dirs * nrm, -1), 0.0) / dist ** 2
    if shape == "sphere":
        r = float(light["radius"])
        to_c = c - point
        d = np.linalg.norm(to_c)
        if d <= r:
            raise ValidateError("area_specular_render: receiver inside the sphere light")
        axis = to_c / d
        ct, wct = _gl(n, np.sqrt(1.0 - (r / d) ** 2), 1.0)
        phi = (np.arange(2 * n) + 0.5) * (np.pi / n)
        t, b = frame(axis)
        st = np.sqrt(1.0 - ct * ct)
        dirs = (ct[:, None, None] * axis + st[:, None, None] * (np.cos(phi)[None, :, None] * t
                                                                  + np.sin(phi)[None, :, None] * b))
        return dirs.reshape(-1, 3), np.repeat(wct, 2 * n) * (np.pi / n)
    nrm = unit(light["normal"])
    if shape == "rectangle":
        t = unit(light.get("tangent", perp(nrm)))
        t = unit(t - nrm * np.dot(t, nrm))
        b = np.cross(nrm, t)
        w, h = (float(x) for x in light["size"])
        xu, wu = _gl(n, -0.5 * w, 0.5 * w)
        xv, wv = _gl(n, -0.5 * h, 0.5 * h)
        pts = c + xu[:, None, None] * t + xv[None, :, None] * b
        da = np.outer(wu, wv)
    elif shape == "disc":
        r = float(light["radius"])
        rho2, w2 = _gl(n, 0.0, r * r)
        phi = (np.arange(2 * n) + 0.5) * (np.pi / n)
        t, b = frame(nrm)
        rho = np.sqrt(rho2)
        pts = c + rho[:, None, None] * (np.cos(phi)[None, :, None] * t + np.sin(phi)[None, :, None] * b)
        da = np.outer(0.5 * w2, np.full(2 * n, np.pi / n))
    else:
        raise ValidateError(f"area_specular_render: light shape {shape!r}; expected rectangle, disc, sphere or tube")
    vec = pts.reshape(-1, 3) - point
    dist = np.linalg.norm(vec, axis=-1)
    dirs = vec / dist[:, None]
    cos_light = np.maximum(-(dirs @ nrm), 0.0)
    return dirs, da.ravel() * cos_light / dist ** 2


def tube_geometry(light: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray, float, float]:
    """(centre, unit axis, length ℓ ≥ 0, radius R > 0) of a tube light mapping
    (:func:`validate.scenes.area_lights.tube_geometry`)."""
    return area_lights.tube_geometry(light, "area_specular_render")


def _tube_surface(light: Mapping[str, Any], p: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(points (M, 3), outward normals (M, 3), area weights (M,)) on the part of the capsule visible from p."""
    c, a, length, r = tube_geometry(light)
    q = p - c
    s_p = float(q @ a)
    qp = q - s_p * a
    h = float(np.linalg.norm(qp))
    pts, nrm, da = [], [], []
    if h > r and length > 0.0:  # cylinder side
        u = qp / h
        b = np.cross(a, u)
        beta = np.arccos(r / h)
        s, ws = _gl(n, -0.5 * length, 0.5 * length)
        phi, wp = _gl(n, -beta, beta)
        nn = np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * b
        pts.append((c + s[:, None, None] * a + r * nn[None, :, :]).reshape(-1, 3))
        nrm.append(np.broadcast_to(nn, (n, n, 3)).reshape(-1, 3))
        da.append((r * np.outer(ws, wp)).ravel())
    for sign in (-1.0, 1.0):
        e = c + sign * 0.5 * length * a
        cap = _cap_surface(e, sign * a, r, p, n)
        if cap is not None:
            pts.append(cap[0])
            nrm.append(cap[1])
            da.append(cap[2])
    if not pts:
        raise ValidateError("area_specular_render: receiver inside the tube light")
    return np.concatenate(pts), np.concatenate(nrm), np.concatenate(da)


def _cap_surface(e: np.ndarray, ax: np.ndarray, r: float, p: np.ndarray, n: int
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The visible part of the hemisphere {e + R m : m·ax ≥ 0}: polar angle t about u = (p − e)/‖p − e‖ up to the
    visibility limit cos γ = R/‖p − e‖, azimuth (from the projection of ax) limited to the outer half."""
    dvec = p - e
    d = float(np.linalg.norm(dvec))
    if d <= r:
        return None
    u = dvec / d
    ua = float(u @ ax)
    t1 = ax - ua * u
    sa = float(np.linalg.norm(t1))
    t1 = t1 / sa if sa > 1e-12 else perp(u)
    t2 = np.cross(u, t1)
    gamma = float(np.arccos(r / d))
    t_star = float(np.arctan2(abs(ua), sa))  # where the rim circle m·ax = 0 becomes tangent to the t-circle
    edges = [0.0, *([t_star] if 0.0 < t_star < gamma else []), gamma]
    pts, nrm, da = [], [], []
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        t, wt = _gl(n, lo, hi)
        st = np.maximum(np.sin(t), 1e-300)
        phi_max = np.arccos(np.clip(-ua * np.cos(t) / (max(sa, 1e-300) * st), -1.0, 1.0))
        x, wx = _leggauss(n)
        phi = np.outer(phi_max, x)  # (n_t, n_φ) on [−φ_max, φ_max]
        w = np.outer(wt * st * phi_max, wx) * r * r
        m = (np.cos(t)[:, None, None] * u + st[:, None, None] * (np.cos(phi)[..., None] * t1
                                                                 + np.sin(phi)[..., None] * t2))
        pts.append((e + r * m).reshape(-1, 3))
        nrm.append(m.reshape(-1, 3))
        da.append(w.ravel())
    return np.concatenate(pts), np.concatenate(nrm), np.concatenate(da)


def radiance(light: Mapping[str, Any], alpha: float, points: np.ndarray, normals: np.ndarray, views: np.ndarray,
             n: int) -> np.ndarray:
    """L_o per receiver (N,) for a GGX roughconductor with F = 1 (unit L_e scaled by light['radiance'])."""
    bsdf = bs.conductor(alpha, "ggx", coloured=False).bsdf
    out = np.empty(len(points))
    batch: list[tuple[int, np.ndarray, np.ndarray]] = []
    size = 0

    def flush() -> None:
        nonlocal batch, size
        if not batch:
            return
        d = np.concatenate([x[1] for x in batch])
        nn = np.concatenate([np.broadcast_to(normals[i], x[1].shape) for i, x in ((b[0], b) for b in batch)])
        vv = np.concatenate([np.broadcast_to(views[i], x[1].shape) for i, x in ((b[0], b) for b in batch)])
        q = br.eval_bsdf_world(bsdf, nn, d, vv)[:, 1]
        k = 0
        for i, dirs, w in batch:
            out[i] = float(np.sum(w * q[k:k + len(dirs)]))
            k += len(dirs)
        batch, size = [], 0

    for i, p in enumerate(np.asarray(points, dtype=np.float64)):
        dirs, w = light_directions(light, p, n)
        batch.append((i, dirs, w))
        size += len(dirs)
        if size >= CHUNK:
            flush()
    flush()
    return float(light.get("radiance", 1.0)) * out


def reference(light: Mapping[str, Any], alpha: float, points: np.ndarray, normals: np.ndarray, views: np.ndarray,
              n: int) -> tuple[np.ndarray, np.ndarray]:
    """(L_o at n nodes, |L(n) − L(n/2)|) per receiver."""
    full = radiance(light, alpha, points, normals, views, n)
    half = radiance(light, alpha, points, normals, views, max(n // 2, 1))
    return full, np.abs(full - half)


Job = tuple[Mapping[str, Any], np.ndarray, np.ndarray, np.ndarray]  # (light, point (3,), normal (3,), view (3,))


def _local_frame(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(t, b, n) as (1, 3) rows: :func:`validate.reference.brdf_render.eval_bsdf_world`'s tangent frame of one normal
    (the same operations on one row as there on every row, so the same bits)."""
    n = np.asarray(normal, dtype=np.float64).reshape(1, 3)
    a = np.where(np.abs(n[:, 1:2]) > 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
    t = np.cross(n, a)
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    return t, np.cross(n, t), n


def _to_local(d: np.ndarray, frame: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    t, b, n = frame
    return np.stack([np.sum(d * t, -1), np.sum(d * b, -1), np.sum(d * n, -1)], -1)


def reference_alphas(jobs: list[Job], alphas: tuple[float, ...], n: int) -> tuple[np.ndarray, np.ndarray]:
    """(L_o at n nodes, |L(n) − L(n/2)|), each (len(alphas), len(jobs)): :func:`reference` of every job's single
    receiver at every α — the same numbers, bit for bit (the same directions, frames, float32 BSDF evaluations and
    per-receiver sums) — with each job's light directions and local frame computed once for all α and one
    ``BSDF.eval`` call per α over every job (chunks of :data:`CHUNK`)."""
    levels = []
    for nodes in (n, max(n // 2, 1)):
        for light, p, nrm, v in jobs:
            dirs, w = light_directions(light, np.asarray(p, dtype=np.float64), nodes)
            frame = _local_frame(nrm)
            lv = _to_local(np.asarray(v, dtype=np.float64).reshape(1, 3), frame).astype(np.float32)
            levels.append((_to_local(dirs, frame).astype(np.float32), lv, w, float(light.get("radiance", 1.0))))
    out = np.empty((len(alphas), len(levels)))
    for ia, alpha in enumerate(alphas):
        bsdf = bs.conductor(alpha, "ggx", coloured=False).bsdf
        start = 0
        while start < len(levels):
            stop, size = start, 0
            while stop < len(levels) and (size < CHUNK or stop == start):
                size += len(levels[stop][0])
                stop += 1
            block = levels[start:stop]
            q = br.eval_bsdf(bsdf, np.concatenate([x[0] for x in block]),
                             np.concatenate([np.broadcast_to(x[1], x[0].shape) for x in block]))[:, 1]
            k = 0
            for j, (ld, _, w, le) in enumerate(block, start):
                out[ia, j] = le * float(np.sum(w * q[k:k + len(ld)]))
                k += len(ld)
            start = stop
    full, half = out[:, :len(jobs)], out[:, len(jobs):]
    return full, np.abs(full - half)


# ---------------------------------------------------------------------------------------------
# Mitsuba render of the same configuration (validates the quadrature reference)

def _frame_matrix(center: np.ndarray, t: np.ndarray, b: np.ndarray, n: np.ndarray, sx: float, sy: float) -> list:
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = t * sx, b * sy, n, center
    return m.tolist()


def emitter_dict(light: Mapping[str, Any]) -> dict[str, Any]:
    """Mitsuba shape + ``area`` emitter (uniform radiance, front face along the light's normal) for a light mapping."""
    import mitsuba as mi

    emitter = {"type": "area", "radiance": {"type": "rgb", "value": float(light.get("radiance", 1.0))}}
    c = np.asarray(light["center"], dtype=np.float64)
    if light["shape"] == "tube":
        raise ValidateError("area_specular_render: a tube is three Mitsuba shapes; use emitter_shapes")
    if light["shape"] == "sphere":
        return {"type": "sphere", "center": c.tolist(), "radius": float(light["radius"]), "emitter": emitter}
    n = unit(light["normal"])
    t = unit(light.get("tangent", perp(n)))
    t = unit(t - n * np.dot(t, n))
    b = np.cross(n, t)
    if light["shape"] == "rectangle":
        w, h = (float(x) for x in light["size"])
        m = _frame_matrix(c, t, b, n, 0.5 * w, 0.5 * h)
        return {"type": "rectangle", "to_world": mi.ScalarTransform4f(m), "emitter": emitter}
    r = float(light["radius"])
    return {"type": "disk", "to_world": mi.ScalarTransform4f(_frame_matrix(c, t, b, n, r, r)), "emitter": emitter}


CAP_RINGS, CAP_SEGMENTS = 48, 192  # tessellation of a tube's hemispherical caps (polar rings × azimuth segments)


def emitter_shapes(light: Mapping[str, Any], workdir: str | None = None) -> dict[str, dict[str, Any]]:
    """Scene entries for a light mapping: one shape, or for a tube Mitsuba's open ``cylinder`` (p0, p1, radius;
    normals outward) closed by two hemispherical caps, each with its own ``area`` emitter.

    The caps are triangle meshes (``obj`` files written to ``workdir``: CAP_RINGS × CAP_SEGMENTS, vertices on the
    sphere, so the area is short by ≈ (π/CAP_SEGMENTS)²/3 ≈ 10⁻⁴ of the caps'), not ``sphere`` shapes: full spheres
    would put their inner halves just behind the cylinder's wall, and Mitsuba's shadow rays stop short of their target
    by a relative ShadowEpsilon (~10⁻³), so emitter samples on the inner half within ~√(2R·10⁻³ d) of the rim pass the
    visibility test — measured: +35 % on the caps' radiance with emitter sampling, exact with BSDF sampling only."""
    if light["shape"] != "tube":
        return {"light": emitter_dict(light)}
    c, a, length, r = tube_geometry(light)
    le = float(light.get("radiance", 1.0))

    def emitter() -> dict[str, Any]:
        return {"type": "area", "radiance": {"type": "rgb", "value": le}}

    if length == 0.0:
        return {"light": {"type": "sphere", "center": c.tolist(), "radius": r, "emitter": emitter()}}
    if workdir is None:
        raise ValidateError("area_specular_render: a tube's caps need a workdir for their mesh files")
    p0, p1 = c - 0.5 * length * a, c + 0.5 * length * a
    out = {"light": {"type": "cylinder", "p0": p0.tolist(), "p1": p1.tolist(), "radius": r, "emitter": emitter()}}
    for i, (e, ax) in enumerate(((p0, -a), (p1, a))):
        path = f"{workdir}/cap{i}.obj"
        write_hemisphere_obj(path, e, ax, r)
        out[f"light_cap{i}"] = {"type": "obj", "filename": path, "face_normals": True, "emitter": emitter()}
    return out


def write_hemisphere_obj(path: str, center: np.ndarray, axis: np.ndarray, radius: float,
                         rings: int = CAP_RINGS, segments: int = CAP_SEGMENTS) -> None:
    """A hemisphere {center + R m : m·axis ≥ 0} as an OBJ triangle mesh, faces wound counter-clockwise seen from
    outside (outward face normals): the pole, then ``rings`` rings at polar angles kπ/(2·rings). The text is built
    once per distinct (center, axis, R, rings, segments) (:func:`_hemisphere_obj_text`): the render check asks for
    the same tube, hence the same caps, at every α."""
    text = _hemisphere_obj_text(tuple(float(x) for x in np.asarray(center, dtype=np.float64)),
                                tuple(float(x) for x in np.asarray(axis, dtype=np.float64)), float(radius),
                                int(rings), int(segments))
    with open(path, "w") as f:
        f.write(text)


@lru_cache(maxsize=64)
def _hemisphere_obj_text(center: tuple[float, ...], axis: tuple[float, ...], radius: float, rings: int,
                         segments: int) -> str:
    """The OBJ text of :func:`write_hemisphere_obj` (vertices ``v x y z`` to 9 significant digits, then the faces of
    :func:`_hemisphere_obj_faces`)."""
    c, ax = np.array(center), np.array(axis)
    t, b = frame(ax)
    th = np.arange(1, rings + 1) * (0.5 * np.pi / rings)
    ph = np.arange(segments) * (2.0 * np.pi / segments)
    ring = (np.cos(th)[:, None, None] * ax + np.sin(th)[:, None, None]
            * (np.cos(ph)[None, :, None] * t + np.sin(ph)[None, :, None] * b))
    verts = np.concatenate([[c + radius * ax], (c + radius * ring).reshape(-1, 3)])
    return "\n".join([f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in verts]) + "\n" + _hemisphere_obj_faces(rings,
                                                                                                         segments)


@lru_cache(maxsize=8)
def _hemisphere_obj_faces(rings: int, segments: int) -> str:
    """The face lines ``f i j k`` (1-based; vertex 1 is the pole, then ring after ring of ``segments`` vertices) of
    :func:`write_hemisphere_obj`, newline-terminated: they depend on the tessellation alone."""
    faces = []
    for j in range(segments):
        k = (j + 1) % segments
        faces.append((1, 2 + j, 2 + k))
        for i in range(rings - 1):
            a0, a1 = 2 + i * segments + j, 2 + i * segments + k
            b0, b1 = a0 + segments, a1 + segments
            faces += [(a0, b0, b1), (a0, b1, a1)]
    return "\n".join(f"f {i} {j} {k}" for i, j, k in faces) + "\n"


def render(light: Mapping[str, Any], alpha: float, point: np.ndarray, normal: np.ndarray, view: np.ndarray,
           pixels: int = 32, spp: int = 64, seed: int = 0) -> tuple[float, float]:
    """(mean, standard error) of L_o(p, v) rendered by Mitsuba: an orthographic camera looking along −v at a patch of
    side 10⁻⁴ around p on a large ``roughconductor`` (ggx, α, F = 1) plane, ``direct`` integrator (emitter and BSDF
    sampling, MIS); pixels × pixels independent estimates of spp samples each. The scene is loaded by
    :func:`validate.backend.load_scene` (emitters in the dict's order: a tube's three emitters otherwise came out in
    another order in ≈ 1 load in 12, and the same seed gave another estimate)."""
    import mitsuba as mi

    init()
    p, n, v = (np.asarray(x, dtype=np.float64) for x in (point, normal, view))
    t, b = frame(n)
    plane = {"type": "rectangle", "to_world": mi.ScalarTransform4f(_frame_matrix(p, t, b, n, 50.0, 50.0)),
             "bsdf": bs.conductor(alpha, "ggx", coloured=False).bsdf}
    up = perp(v)
    cam = (mi.ScalarTransform4f().look_at(origin=(p + 0.05 * v).tolist(), target=p.tolist(), up=up.tolist())
           @ mi.ScalarTransform4f().scale([1e-4, 1e-4, 1.0]))
    with tempfile.TemporaryDirectory(prefix="validate_tube_") as work:
        scene = load_scene({
            "type": "scene", "integrator": {"type": "direct"}, "plane": plane, **emitter_shapes(light, work),
            "sensor": {"type": "orthographic", "to_world": cam, "near_clip": 1e-3, "far_clip": 10.0,
                       "film": {"type": "hdrfilm", "width": pixels, "height": pixels, "rfilter": {"type": "box"},
                                "pixel_format": "rgb"},
                       "sampler": {"type": "independent", "sample_count": spp}}})
    img = np.asarray(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)[..., 1].ravel()
    return float(img.mean()), float(img.std(ddof=1) / np.sqrt(img.size))


__all__ = ["light_directions", "radiance", "reference", "reference_alphas", "emitter_dict", "emitter_shapes", "render",
           "tube_geometry", "write_hemisphere_obj"]
