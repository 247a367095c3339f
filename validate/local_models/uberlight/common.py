"""Shared code of the überlight family: the Orange Book listing's shaping (superellipse, distance
window, smoothstep), its light coordinates and the shading skeleton every überlight technique uses
(formulas and references: :mod:`.orange_book`). Registers nothing."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ..precision import constants_dr, packed_to_dr
from ..precision import to_dr as _to_dr

SHAPE_KEYS = ("width", "height", "width_edge", "height_edge", "roundness")
DISTANCE_KEYS = ("near", "far", "near_edge", "far_edge")
NO_DISTANCE_SHAPING = {"near": 0.0, "far": 1.0e9, "near_edge": 0.0, "far_edge": 0.0}


def check_light(light: Mapping[str, Any], *extra: str) -> None:
    """One-line error naming the missing or invalid überlight parameters."""
    keys = ("position", "axes", "intensity") + SHAPE_KEYS + DISTANCE_KEYS + extra
    missing = [k for k in keys if k not in light]
    if missing:
        raise ValidateError(f"überlight light mapping: missing {', '.join(missing)}")
    bad = [k for k in ("width", "height", "roundness") if not float(light[k]) > 0]
    bad += [k for k in ("width_edge", "height_edge", "near_edge", "far_edge") if not float(light[k]) >= 0]
    if bad:
        raise ValidateError(f"überlight light mapping: {', '.join(bad)} must be > 0 (widths, roundness) or ≥ 0 "
                            "(edges)")


def _f(a: Any) -> Any:
    return _to_dr(a)


def smoothstep(e0: Any, e1: Any, x: Any) -> Any:
    """GLSL smoothstep; e₀ = e₁ is the step x ≥ e₁ (module docstring)."""
    import drjit as dr

    width = e1 - e0
    t = dr.clip((x - e0) / dr.select(width > 0, width, 1.0), 0.0, 1.0)
    return dr.select(width > 0, t * t * (3.0 - 2.0 * t), dr.select(x >= e1, 1.0, 0.0))


def light_coordinates(light: Mapping[str, Any], points: np.ndarray) -> np.ndarray:
    """(N, 3) receiver positions in the light's frame (x, y, z = forward), float64."""
    axes = np.asarray(light["axes"], dtype=np.float64).reshape(3, 3)
    rel = np.asarray(points, dtype=np.float64).reshape(-1, 3) - np.asarray(light["position"], dtype=np.float64)
    return rel @ axes.T


def superellipse_shape(light: Mapping[str, Any], lc: Any) -> Any:
    """A = 1 − smoothstep(inner, outer, 1) of Listing 12.6 (drjit; ``lc`` = (x, y, z) drjit arrays)."""
    import drjit as dr

    x, y, z = lc
    front = z > 0
    zs = dr.select(front, z, 1.0)
    px, py = dr.abs(x / zs), dr.abs(y / zs)
    w0, h0 = float(light["width"]), float(light["height"])
    ww0, hh0 = w0 + float(light["width_edge"]), h0 + float(light["height_edge"])
    # widths opaque (precision.constants_dr: a new light reuses the kernel), the products w h formed in float64 as
    # the literals were; the exponents stay literals: drjit's power takes exact fast paths on literal integer
    # exponents (e₁ = 2 at roundness 1), an opaque exponent would change the float32 numbers
    w, h, ww, hh, wh, wwhh = constants_dr([w0, h0, ww0, hh0, w0 * h0, ww0 * hh0])
    e1, e2 = 2.0 / float(light["roundness"]), -float(light["roundness"]) / 2.0
    at_axis = (px == 0) & (py == 0)
    inner = wh * dr.power(dr.select(at_axis, 1.0, dr.power(h * px, e1) + dr.power(w * py, e1)), e2)
    outer = wwhh * dr.power(dr.select(at_axis, 1.0, dr.power(hh * px, e1) + dr.power(ww * py, e1)), e2)
    shape = 1.0 - smoothstep(inner, outer, dr.full(type(inner), 1.0, dr.width(inner)))
    return dr.select(front, dr.select(at_axis, 1.0, shape), 0.0)


def distance_shape(light: Mapping[str, Any], z: Any) -> Any:
    """D = smoothstep(near − nearEdge, near, z) · (1 − smoothstep(far, far + farEdge, z)) (Listing 12.6)."""
    near, far = float(light["near"]), float(light["far"])
    ne, fe = float(light["near_edge"]), float(light["far_edge"])
    one = z * 0.0
    a, b, c, d = constants_dr([near - ne, near, far, far + fe])  # opaque: a new light reuses the kernel
    return smoothstep(one + a, one + b, z) * (1.0 - smoothstep(one + c, one + d, z))


def superellipse_shape_np(light: Mapping[str, Any], x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The same A in float64 numpy (the slow, obvious version the drjit one is tested against; the fits use it)."""
    def sstep(e0: np.ndarray, e1: np.ndarray, v: float) -> np.ndarray:
        wdt = e1 - e0
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.clip((v - e0) / np.where(wdt > 0, wdt, 1.0), 0.0, 1.0)
        return np.where(wdt > 0, t * t * (3 - 2 * t), (v >= e1).astype(float))

    front = z > 0
    zs = np.where(front, z, 1.0)
    px, py = np.abs(x / zs), np.abs(y / zs)
    w, h = float(light["width"]), float(light["height"])
    ww, hh = w + float(light["width_edge"]), h + float(light["height_edge"])
    e1, e2 = 2.0 / float(light["roundness"]), -float(light["roundness"]) / 2.0
    axis = (px == 0) & (py == 0)
    with np.errstate(divide="ignore", over="ignore"):
        inner = w * h * np.where(axis, 1.0, (h * px) ** e1 + (w * py) ** e1) ** e2
        outer = ww * hh * np.where(axis, 1.0, (hh * px) ** e1 + (ww * py) ** e1) ** e2
    return np.where(front & ~axis, 1.0 - sstep(inner, outer, 1.0), np.where(front, 1.0, 0.0))


def superellipse_shape_ad(width: Any, height: Any, width_edge: Any, height_edge: Any, roundness: Any,
                          x: Any, y: Any, z: Any) -> Any:
    """The same A with every shape value a drjit array (width 1 or N: the AD fits differentiate through them,
    :mod:`validate.numerics.adfit`); x, y, z drjit arrays of the light coordinates. |h p_x|, |w p_y| are floored at
    10⁻³⁰ (a zero base has no derivative in its exponent; 10⁻³⁰ raised to e₁ ≥ 0.5 is below 10⁻¹⁵ of the other term)."""
    import drjit as dr

    front = z > 0
    zs = dr.select(front, z, 1.0)
    px, py = dr.abs(x / zs), dr.abs(y / zs)
    ww, hh = width + width_edge, height + height_edge
    e1, e2 = 2.0 / roundness, -roundness / 2.0
    axis = (px == 0) & (py == 0)

    def term(a: Any, b: Any) -> Any:
        base = dr.power(dr.maximum(b * px, 1e-30), e1) + dr.power(dr.maximum(a * py, 1e-30), e1)
        return a * b * dr.power(dr.select(axis, 1.0, base), e2)

    inner, outer = term(width, height), term(ww, hh)
    span = outer - inner
    t = dr.clip((1.0 - inner) / dr.select(span > 0, span, 1.0), 0.0, 1.0)
    step = dr.select(span > 0, t * t * (3.0 - 2.0 * t), dr.select(outer <= 1.0, 1.0, 0.0))
    return dr.select(front & ~axis, 1.0 - step, dr.select(front, 1.0, 0.0))


def distance_shape_np(light: Mapping[str, Any], z: np.ndarray) -> np.ndarray:
    """The same D in float64 numpy (twin of :func:`distance_shape`)."""
    def sstep(e0: float, e1: float, v: np.ndarray) -> np.ndarray:
        if e1 > e0:
            t = np.clip((v - e0) / (e1 - e0), 0.0, 1.0)
            return t * t * (3 - 2 * t)
        return (v >= e1).astype(float)

    z = np.asarray(z, dtype=np.float64)
    near, far = float(light["near"]), float(light["far"])
    return sstep(near - float(light["near_edge"]), near, z) * (1.0 - sstep(far, far + float(light["far_edge"]), z))


def fore_june_falloff(d: np.ndarray, intensity: float, d0: float, alpha: float, max_intensity: float
                      ) -> np.ndarray:
    """Barzel's falloff (module docstring): K (d₀/d)^α for d ≥ d₀, M exp(s (d/d₀)^β) below, K = I₀/d₀^α."""
    d = np.asarray(d, dtype=np.float64)
    k = intensity / d0 ** alpha
    if not (max_intensity > k > 0 and d0 > 0 and alpha > 0):
        raise ValidateError(f"Fore June falloff: need M > K = I₀/d₀^α > 0 and d₀, α > 0 (M={max_intensity:g}, "
                            f"K={k:g}, d₀={d0:g}, α={alpha:g})")
    s = math.log(k / max_intensity)
    beta = -alpha / s
    with np.errstate(divide="ignore"):
        far = k * (d0 / np.maximum(d, 1e-30)) ** alpha
    return np.where(d >= d0, far, max_intensity * np.exp(s * (d / d0) ** beta))


def shade(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, views: np.ndarray,
          material: Mapping[str, Any], shadow: np.ndarray | None, falloff: np.ndarray | float) -> np.ndarray:
    """L_o of the module docstring with the per-point falloff F (array or scalar)."""
    import drjit as dr

    check_light(light)
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    lc64 = light_coordinates(light, p)
    to_light = np.asarray(light["position"], dtype=np.float64) - p
    dist = np.linalg.norm(to_light, axis=1)
    ldir = to_light / np.maximum(dist, 1e-30)[:, None]
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    v = np.asarray(views, dtype=np.float64).reshape(-1, 3)
    half = ldir + v
    half /= np.maximum(np.linalg.norm(half, axis=1), 1e-30)[:, None]
    albedo = np.broadcast_to(np.asarray(material.get("albedo", 1.0), dtype=np.float64), (len(p),))
    vis = np.ones(len(p)) if shadow is None else shadow
    fall = np.broadcast_to(np.asarray(falloff, dtype=np.float64), (len(p),))
    # one packed input (precision.packed_to_dr): with eight separate ones the kernel's hash followed drjit's
    # variable numbering and every call recompiled (≈ 0.2 s each, measured with drjit's kernel history)
    x, y, z, cl, ch, rho, vis_d, fall_d = packed_to_dr(*lc64.T, np.einsum("nk,nk->n", n, ldir),
                                                       np.einsum("nk,nk->n", n, half), albedo / math.pi, vis, fall)
    a = superellipse_shape(light, [x, y, z]) * distance_shape(light, z)
    ks, s = float(material.get("ks", 0.0)), float(material.get("specular_exponent", 20.0))
    refl = rho * dr.maximum(cl, 0.0) + ks * dr.power(dr.maximum(ch, 0.0), s)
    c = constants_dr([float(light["intensity"])])[0] * a * fall_d
    return np.array(c * vis_d * refl, dtype=np.float64)


def _distance(light: Mapping[str, Any], points: np.ndarray) -> np.ndarray:
    return np.linalg.norm(np.asarray(points, dtype=np.float64).reshape(-1, 3) - np.asarray(light["position"]), axis=1)
