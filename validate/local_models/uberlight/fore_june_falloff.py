"""Fore June's distance falloff, eqs. 20.46–20.47 as printed and as coded in the listing after them [1, §20.5.3].

As printed (seed text, §20.5.3 "Distance Falloff"):

    20.46  I(d) = K (d₀/d)^α
    20.47  I(d) = M e^{s (d₀/d)^β}  (d < d₀),   K (d₀/d)^α  (d > d₀),   s = ln(K/M),  β = −α/s,

"chosen so that the two expressions … give the same value, I(d₀) = K … and give the same slope
I'(d) = −Kα/d₀". The fragment shader that follows codes the near branch as
``maxIntensity * exp(s * pow(z/d0, beta))`` with ``s = log(1.0/maxIntensity)`` (K = 1) on the depth
``z = abs(pos.z)``, not the distance.

Which is right: with u = d/d₀ the listing's near branch M exp(s u^β) has value M e^s = K at u = 1 and
slope (K s β)/d₀ = −Kα/d₀ — the far branch's −Kα/d₀: C¹, and → M as d → 0 (β > 0 because M > K makes
s < 0). The printed (d₀/d)^β gives the same value K at d₀ but the slope +Kα/d₀ (opposite sign), and
→ 0 as d → 0 (s < 0, (d₀/d)^β → ∞): it rises from 0 to K inside d₀ instead of falling from M.

References
  [1] Fore June, *An Introduction to 3D Computer Graphics, Stereoscopic Image, and Animation in OpenGL
      and C/C++*, ch. 20 §20.5.3, eqs. 20.46–20.47 and the "Fragment Shader of uberlight-like model".
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ..families import uberlight
from ..precision import constants_dr, vec_to_dr
from ..uberlight.common import check_light, shade


def _constants(k: float, m: float, alpha: float) -> tuple[float, float]:
    if not (m > k > 0 and alpha > 0):
        raise ValidateError(f"Fore June falloff: need M > K > 0 and α > 0 (M={m:g}, K={k:g}, α={alpha:g})")
    s = math.log(k / m)
    return s, -alpha / s


def falloff_printed(d: np.ndarray, k: float, m: float, d0: float, alpha: float) -> np.ndarray:
    """Eq. 20.47 as printed: M exp(s (d₀/d)^β) for d < d₀, K (d₀/d)^α beyond."""
    s, beta = _constants(k, m, alpha)
    d = np.maximum(np.asarray(d, dtype=np.float64), 1e-300)
    return np.where(d < d0, m * np.exp(s * (d0 / d) ** beta), k * (d0 / d) ** alpha)


def falloff_listing(d: np.ndarray, k: float, m: float, d0: float, alpha: float) -> np.ndarray:
    """The listing's form: M exp(s (d/d₀)^β) for d ≤ d₀ (``pow(z/d0, beta)``), K (d₀/d)^α beyond."""
    s, beta = _constants(k, m, alpha)
    d = np.maximum(np.asarray(d, dtype=np.float64), 1e-300)
    return np.where(d <= d0, m * np.exp(s * (d / d0) ** beta), k * (d0 / d) ** alpha)


def falloff_printed_dr(d: Any, k: float, m: float, d0: float, alpha: float) -> Any:
    """:func:`falloff_printed` on a drjit array of distances, in its dtype (the technique's path; the float64 numpy
    form stays for :func:`slopes_at_d0`'s finite differences, which float32 would drown). K, M, d₀, α, s, β enter
    as opaque values (:func:`~validate.local_models.precision.constants_dr`): a new light reuses the kernel."""
    import drjit as dr

    s, beta = _constants(k, m, alpha)
    kk, mm, dd0, aa, ss, bb = constants_dr([k, m, d0, alpha, s, beta])
    ratio = dd0 / dr.maximum(d, 1e-30)
    return dr.select(d < dd0, mm * dr.exp(ss * dr.power(ratio, bb)), kk * dr.power(ratio, aa))


def slopes_at_d0(k: float, m: float, d0: float, alpha: float, form: str, h: float = 1e-6) -> tuple[float, float]:
    """(inner, outer) one-sided derivatives at d₀ by central differences of width h·d₀ (the C¹ check)."""
    f = falloff_printed if form == "printed" else falloff_listing
    lo = (f(d0 * (1 - h / 2), k, m, d0, alpha) - f(d0 * (1 - 3 * h / 2), k, m, d0, alpha)) / (h * d0)
    hi = (f(d0 * (1 + 3 * h / 2), k, m, d0, alpha) - f(d0 * (1 + h / 2), k, m, d0, alpha)) / (h * d0)
    return float(lo), float(hi)


@uberlight.register("uberlight_fore_june_printed", "the listing's shaping with Fore June's eq. 20.47 exactly as "
                    "printed: near field M exp(s (d₀/d)^β) (→ 0 as d → 0)",
                    seed="000 Fore June §20.5.3, eq. 20.46–20.47")
def uberlight_fore_june_printed(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
                                views: np.ndarray, material: Mapping[str, Any],
                                shadow: np.ndarray | None = None) -> np.ndarray:
    """Orange Book shaping (:func:`validate.local_models.uberlight.shade`) × falloff_printed(d)/I₀ with
    K = I₀/d₀^α (as ``uberlight_fore_june``, whose near branch is the listing's); d and the falloff in drjit, in
    the family's dtype (:func:`falloff_printed_dr`)."""
    import drjit as dr

    check_light(light, "d0", "alpha", "max_intensity")
    i0, d0, alpha = float(light["intensity"]), float(light["d0"]), float(light["alpha"])
    px, py, pz = vec_to_dr(points)
    cx, cy, cz, inv_i0 = constants_dr(np.r_[np.asarray(light["position"], dtype=np.float64), 1.0 / i0])
    d = dr.sqrt(dr.square(px - cx) + dr.square(py - cy) + dr.square(pz - cz))
    f = falloff_printed_dr(d, i0 / d0 ** alpha, float(light["max_intensity"]), d0, alpha) * inv_i0
    return shade(light, points, normals, views, material, shadow, f)


__all__ = ["falloff_listing", "falloff_printed", "falloff_printed_dr", "slopes_at_d0", "uberlight_fore_june_printed"]
