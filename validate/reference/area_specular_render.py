"""Reference radiance of a GGX ``roughconductor`` under rectangle, disc and sphere emitters: Mitsuba's own BSDF
evaluation integrated over the emitter by deterministic quadrature.

    L_o(p, v) = ∫_light L_e f_r(l, v) (n·l) dω_l

with f_r(l, v)(n·l) = Mitsuba's ``BSDF.eval`` of ``roughconductor`` (``distribution`` ggx, α, η = 0, k = 1: F = 1;
:func:`validate.reference.brdf_render.eval_bsdf_world`) and the emitter a uniform one-sided radiance L_e
(Mitsuba's ``rectangle``/``disk`` area emitters emit from the front face, along their normal; a ``sphere``
emits everywhere). The quadrature (Gauss–Legendre, n nodes per axis) runs over

* rectangle: the two edge coordinates, dω = cos θ_light dA / r²;
* disc: ρ² ∈ [0, R²] (Gauss–Legendre) × φ (2n uniform), dA = ½ dρ² dφ;
* sphere: the cone of directions it subtends, cos θ ∈ [cos σ, 1], sin σ = R/d (Gauss–Legendre) × φ (2n uniform).

Uncertainty: |L(n) − L(n/2)| per receiver (the quadrature's own convergence; Mitsuba's float32 evaluation adds
~10⁻⁶ relative). The sharp lobes of small α need n large enough to resolve the lobe's footprint on the light;
the uncertainty says when it is not.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import ValidateError
from ..scenes import brdf_scenes as bs
from . import brdf_render as br

CHUNK = 2_000_000  # BSDF evaluations per Mitsuba call


def _unit(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.float64)
    return x / np.maximum(np.linalg.norm(x, axis=-1, keepdims=True), 1e-300)


def _perp(n: np.ndarray) -> np.ndarray:
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    return _unit(np.cross(n, a))


def _gl(n: int, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    return a + (b - a) * 0.5 * (x + 1.0), (b - a) * 0.5 * w


def light_directions(light: Mapping[str, Any], point: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(unit directions (M, 3) from ``point`` to the light, solid-angle weights (M,)) — zero weight where the
    light's back face is seen."""
    shape = light.get("shape")
    c = np.asarray(light["center"], dtype=np.float64)
    if shape == "sphere":
        r = float(light["radius"])
        to_c = c - point
        d = np.linalg.norm(to_c)
        if d <= r:
            raise ValidateError("area_specular_render: receiver inside the sphere light")
        axis = to_c / d
        ct, wct = _gl(n, np.sqrt(1.0 - (r / d) ** 2), 1.0)
        phi = (np.arange(2 * n) + 0.5) * (np.pi / n)
        t = _perp(axis)
        b = np.cross(axis, t)
        st = np.sqrt(1.0 - ct * ct)
        dirs = (ct[:, None, None] * axis + st[:, None, None] * (np.cos(phi)[None, :, None] * t
                                                                  + np.sin(phi)[None, :, None] * b))
        return dirs.reshape(-1, 3), np.repeat(wct, 2 * n) * (np.pi / n)
    nrm = _unit(light["normal"])
    if shape == "rectangle":
        t = _unit(light.get("tangent", _perp(nrm)))
        t = _unit(t - nrm * np.dot(t, nrm))
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
        t = _perp(nrm)
        b = np.cross(nrm, t)
        rho = np.sqrt(rho2)
        pts = c + rho[:, None, None] * (np.cos(phi)[None, :, None] * t + np.sin(phi)[None, :, None] * b)
        da = np.outer(0.5 * w2, np.full(2 * n, np.pi / n))
    else:
        raise ValidateError(f"area_specular_render: light shape {shape!r}; expected rectangle, disc or sphere")
    vec = pts.reshape(-1, 3) - point
    dist = np.linalg.norm(vec, axis=-1)
    dirs = vec / dist[:, None]
    cos_light = np.maximum(-(dirs @ nrm), 0.0)
    return dirs, da.ravel() * cos_light / dist ** 2


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
    if light["shape"] == "sphere":
        return {"type": "sphere", "center": c.tolist(), "radius": float(light["radius"]), "emitter": emitter}
    n = _unit(light["normal"])
    t = _unit(light.get("tangent", _perp(n)))
    t = _unit(t - n * np.dot(t, n))
    b = np.cross(n, t)
    if light["shape"] == "rectangle":
        w, h = (float(x) for x in light["size"])
        m = _frame_matrix(c, t, b, n, 0.5 * w, 0.5 * h)
        return {"type": "rectangle", "to_world": mi.ScalarTransform4f(m), "emitter": emitter}
    r = float(light["radius"])
    return {"type": "disk", "to_world": mi.ScalarTransform4f(_frame_matrix(c, t, b, n, r, r)), "emitter": emitter}


def render(light: Mapping[str, Any], alpha: float, point: np.ndarray, normal: np.ndarray, view: np.ndarray,
           pixels: int = 32, spp: int = 64, seed: int = 0) -> tuple[float, float]:
    """(mean, standard error) of L_o(p, v) rendered by Mitsuba: an orthographic camera looking along −v at a patch of
    side 10⁻⁴ around p on a large ``roughconductor`` (ggx, α, F = 1) plane, ``direct`` integrator (emitter and BSDF
    sampling, MIS); pixels × pixels independent estimates of spp samples each."""
    import mitsuba as mi

    from ..backend import init

    init()
    p, n, v = (np.asarray(x, dtype=np.float64) for x in (point, normal, view))
    t = _perp(n)
    b = np.cross(n, t)
    plane = {"type": "rectangle", "to_world": mi.ScalarTransform4f(_frame_matrix(p, t, b, n, 50.0, 50.0)),
             "bsdf": bs.conductor(alpha, "ggx", coloured=False).bsdf}
    up = _perp(v)
    cam = (mi.ScalarTransform4f().look_at(origin=(p + 0.05 * v).tolist(), target=p.tolist(), up=up.tolist())
           @ mi.ScalarTransform4f().scale([1e-4, 1e-4, 1.0]))
    scene = mi.load_dict({
        "type": "scene", "integrator": {"type": "direct"}, "plane": plane, "light": emitter_dict(light),
        "sensor": {"type": "orthographic", "to_world": cam, "near_clip": 1e-3, "far_clip": 10.0,
                   "film": {"type": "hdrfilm", "width": pixels, "height": pixels, "rfilter": {"type": "box"},
                            "pixel_format": "rgb"},
                   "sampler": {"type": "independent", "sample_count": spp}}})
    img = np.asarray(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)[..., 1].ravel()
    return float(img.mean()), float(img.std(ddof=1) / np.sqrt(img.size))
__all__ = ["light_directions", "radiance", "reference", "emitter_dict", "render"]
