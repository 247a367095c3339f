"""The specular area-light family's shared pieces: reading a technique's GGX parameters (α, F0) from the
family's brdf mapping, with the one-line error every technique raises. Registers nothing."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError


def brdf_params(brdf: Mapping[str, Any], who: str) -> tuple[float, np.ndarray]:
    alpha = np.asarray(brdf.get("alpha", 0.3), dtype=np.float64)
    f0 = np.asarray(brdf.get("f0", 1.0), dtype=np.float64)
    if alpha.ndim != 0 or not 0.0 < float(alpha) <= 1.0:
        raise ValidateError(f"technique '{who}' (specular_arealight): alpha={alpha.tolist()!r} must be in (0, 1]")
    if f0.ndim > 1 or (f0.ndim == 1 and f0.shape[0] != 3) or np.any((f0 < 0) | (f0 > 1)):
        raise ValidateError(f"technique '{who}' (specular_arealight): f0={f0.tolist()!r} must be in [0, 1], scalar "
                            "or RGB")
    return float(alpha), np.broadcast_to(f0, (3,))


# -- drjit vector helpers and the GGX point-light term (the family's float32 dtype, :mod:`..precision`) -----------
TINY = 1e-30  # a norm floor that is a normal float32 (a zero vector stays zero)
Vec = tuple[Any, Any, Any]


def dot(a: Vec, b: Vec) -> Any:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def axpy(s: Any, a: Vec, b: Vec) -> Vec:
    """s·a + b, componentwise."""
    return (s * a[0] + b[0], s * a[1] + b[1], s * a[2] + b[2])


def unit_dr(a: Vec) -> Vec:
    import drjit as dr

    inv = 1.0 / dr.maximum(dr.sqrt(dot(a, a)), TINY)
    return (a[0] * inv, a[1] * inv, a[2] * inv)


def ggx_point_dr(alpha: float, f0: np.ndarray, n: Vec, l: Vec, v: Vec, e_scaled: Any) -> list[Any]:
    """F(v·h) f_r(l, v) (n·l) · e_scaled per channel (3 drjit arrays), zero where l or v is below the horizon:
    GGX D = α²/(π ((n·h)²(α² − 1) + 1)²) (Walter et al. 2007 eq. 33), separable Smith G₁ = 2/(1 + √(1 + α² tan²θ))
    (eq. 34), Schlick F = F₀ + (1 − F₀)(1 − v·h)⁵ — :mod:`validate.local_models.brdf.common`'s terms on drjit arrays."""
    import drjit as dr

    from ..precision import constants_dr  # noqa: PLC0415

    cl, cv = dot(n, l), dot(n, v)
    h = unit_dr((l[0] + v[0], l[1] + v[1], l[2] + v[2]))
    ch, vh = dr.clip(dot(n, h), 0.0, 1.0), dr.clip(dot(v, h), 0.0, 1.0)
    # α², α² − 1, F₀, 1 − F₀ opaque (formed in float64 as the literals were): a new α or F₀ reuses the kernel
    a2, a2m1, *fk = constants_dr([alpha * alpha, alpha * alpha - 1.0, *f0[:3], *(1.0 - f0[:3])])
    q = ch * ch * a2m1 + 1.0
    d = dr.select(ch > 0.0, a2 / (np.pi * q * q), 0.0)

    def g1(c: Any) -> Any:
        c = dr.clip(c, 1e-12, 1.0)
        tan2 = dr.maximum(1.0 - c * c, 0.0) / (c * c)
        return 2.0 / (1.0 + dr.sqrt(1.0 + a2 * tan2))

    spec = d * g1(cl) * g1(cv) / (4.0 * dr.maximum(cv, 1e-12)) * e_scaled
    front = (cl > 0.0) & (cv > 0.0)
    m = (1.0 - vh) ** 5
    out = [dr.select(front, dr.maximum((fk[k] + fk[3 + k] * m) * spec, 0.0), 0.0) for k in range(3)]
    dr.eval(*out)  # one kernel for the three channels
    return out
