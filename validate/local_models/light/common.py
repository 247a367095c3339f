"""The light family's shared pieces: the light-mapping checks, the shadow-ray hook and the point-light
irradiance E = I max(0, n·ω) V / d² that the point, attenuated and grid techniques all evaluate (references as
in :mod:`validate.local_models.light.classic_lights`); nothing here registers a technique."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ..precision import constants_dr, packed_to_dr
from ..precision import to_dr as _to_dr

Visible = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
DIRECTIONAL_REACH = 1.0e3  # m: a directional light's shadow rays test this far towards the light


def require(light_map: Mapping[str, Any], *keys: str, kinds: tuple[str, ...] = ()) -> None:
    """One-line error when ``light_map`` lacks a key or is of a type the technique does not model."""
    kind = light_map.get("type")
    if kinds and kind not in kinds:
        raise ValidateError(f"light of type {kind!r}: this technique models {', '.join(kinds)} only")
    missing = [k for k in keys if k not in light_map]
    if missing:
        raise ValidateError(f"light of type {kind!r}: missing key(s) {', '.join(missing)}")


def as_points(points: Any, normals: Any) -> tuple[np.ndarray, np.ndarray]:
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    if p.shape != n.shape:
        raise ValidateError(f"light: {p.shape[0]} points but {n.shape[0]} normals")
    return p, n


def to_dr(a: np.ndarray) -> Any:
    """(N,) numpy → a drjit array of the active dtype (:mod:`..precision`; the light family's float32)."""
    return _to_dr(a)


def opaque(*values: float) -> list[Any]:
    """Per-call numbers (a light's intensity, direction, range) as opaque drjit values of the active dtype
    (:func:`..precision.constants_dr`): the float32 value the Python literal was rounded to, not baked into the
    kernel, so a new light reuses the compiled kernel."""
    return constants_dr(np.asarray(values, dtype=np.float64))


def shadow(visible: Visible | None, points: np.ndarray, normals: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """V ∈ {0, 1} per receiver from the scene's shadow-ray test (1 everywhere when ``visible`` is None)."""
    if visible is None:
        return np.ones(points.shape[0])
    return np.asarray(visible(points, normals, np.ascontiguousarray(targets)), dtype=np.float64).reshape(-1)


def point_geometry(position: np.ndarray, points: np.ndarray, normals: np.ndarray) -> tuple[Any, Any, Any]:
    """drjit (d, cos θ = n·ω, ω) for a point at ``position``; ω is a tuple of three arrays."""
    import drjit as dr

    # p − x formed in float64 as before, and the normals: six columns of one packed input (precision.packed_to_dr:
    # one input per column lets the kernel hash follow drjit's variable numbering, a cache miss per call)
    pos = np.asarray(position, dtype=np.float64)
    c = packed_to_dr(*(pos[k] - points[:, k] for k in range(3)), *(normals[:, k] for k in range(3)))
    v = c[:3]
    d = dr.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    w = [c / d for c in v]
    cos_t = w[0] * c[3] + w[1] * c[4] + w[2] * c[5]
    return d, cos_t, w


def point_irradiance(light_map: Mapping[str, Any], points: Any, normals: Any, visible: Visible | None,
                     attenuation: Callable[[Any], Any] | None = None,
                     profile: Callable[[Any], Any] | None = None, two_sided: bool = False) -> np.ndarray:
    """E = I(α) · c(n·ω) · a(d) · V with a(d) = 1/d² unless ``attenuation`` is given, I(α) = I
    × ``profile(cos α)`` (cos α = (−ω)·direction) if given, c = max(0, ·) or |·| (``two_sided``)."""
    import drjit as dr

    require(light_map, "position", "intensity")
    p, n = as_points(points, normals)
    pos = np.asarray(light_map["position"], dtype=np.float64)
    d, cos_t, w = point_geometry(pos, p, n)
    cos_term = dr.abs(cos_t) if two_sided else dr.maximum(cos_t, 0.0)
    att = attenuation(d) if attenuation is not None else 1.0 / (d * d)
    (intensity,) = opaque(float(light_map["intensity"]))
    e = intensity * cos_term * att
    if profile is not None:
        ax = opaque(*np.asarray(light_map["direction"], dtype=np.float64)[:3])
        cos_a = -(w[0] * ax[0] + w[1] * ax[1] + w[2] * ax[2])
        e = e * profile(cos_a)
    out = np.array(e, dtype=np.float64)
    lit = out > 0
    if visible is not None and lit.any():
        v = np.zeros_like(out)
        facing = n[lit] * np.sign(np.array(cos_t))[lit, None]  # lift along the lit side's normal
        v[lit] = shadow(visible, p[lit], facing, np.broadcast_to(pos, p[lit].shape))
        out = out * v
    return out
