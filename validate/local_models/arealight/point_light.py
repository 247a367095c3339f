"""Point-light shortcuts for sphere and disc lights: inverse square and OpenGL's attenuation.

A receiver at distance d from the light's centre, normal at angle θ to the direction of the light:

* inverse square [1]:  E = I max(cos θ, 0) / d²;
* OpenGL fixed-function attenuation [2]:  E = I max(cos θ, 0) / (a + b d + c d²)
  (``GL_CONSTANT_ATTENUATION`` a, ``GL_LINEAR_ATTENUATION`` b, ``GL_QUADRATIC_ATTENUATION`` c;
  inverse square is (a, b, c) = (0, 0, 1)).

Intensity matched to the area light it replaces (radiance L, radius r):

* sphere: power Φ = π L · 4π r² (a Lambertian emitter's exitance is πL), isotropic, so
  I = Φ / 4π = π r² L. Then I cos θ / d² = π (r/d)² L cos θ, which is *exactly* the sphere's
  irradiance π sin²σ L cos θ (sin σ = r/d) whenever the sphere is entirely above the horizon
  (:mod:`validate.local_models.arealight.sphere_cap`): inverse square is exact for a sphere light except
  within σ of the horizon, where the point light drops to zero at θ = 90° and the sphere does not.
* disc facing the receiver: on-axis intensity I = L π r² (a Lambertian disc's I(ψ) = π r² L cos ψ).
  On the axis the exact irradiance is π L r²/(r² + d²) cos θ (above the horizon), so inverse square
  overestimates it by the factor 1 + r²/d², and OpenGL's attenuation with (a, b, c) = (r², 0, 1)
  reproduces it exactly.

References
  [1] M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering*, 4th ed., ch. 12 (point lights:
      radiant intensity I, irradiance I cos θ / r²) and ch. 4 (radiometry; Lambertian exitance πL).
  [2] The OpenGL Graphics System, version 2.1 specification, §2.14.1 (lighting equation,
      attenuation factor 1 / (k_c + k_l d + k_q d²)).
"""

from __future__ import annotations

import numpy as np

from ...errors import ValidateError
from ..precision import to_dr, to_np


def sphere_intensity(radius: float, radiance: float = 1.0) -> float:
    """I = π r² L: the isotropic intensity with the power of a sphere of radius r and radiance L."""
    if not radius > 0:
        raise ValidateError(f"sphere light: radius must be > 0, got {radius}")
    return float(np.pi * radius * radius * radiance)


def disc_intensity(radius: float, radiance: float = 1.0) -> float:
    """I = π r² L: the on-axis intensity of a Lambertian disc of radius r and radiance L."""
    if not radius > 0:
        raise ValidateError(f"disc light: radius must be > 0, got {radius}")
    return float(np.pi * radius * radius * radiance)


def attenuated_irradiance(intensity: float, distance: np.ndarray, cos_theta: np.ndarray,
                          constant: float = 0.0, linear: float = 0.0, quadratic: float = 1.0) -> np.ndarray:
    """E = I max(cos θ, 0) / (a + b d + c d²) [2] (defaults (0, 0, 1): inverse square [1]); numpy in/out,
    drjit inside; ``distance`` and ``cos_theta`` broadcast against each other."""
    d, c = np.broadcast_arrays(np.asarray(distance, dtype=np.float64), np.asarray(cos_theta, dtype=np.float64))
    if not np.all(np.isfinite(d)) or np.any(d <= 0):
        raise ValidateError("point light: distances must be finite and > 0")
    if not np.all(np.isfinite(c)) or np.any(np.abs(c) > 1.0 + 1e-6):
        raise ValidateError("point light: cos θ must be finite and within [−1, 1]")
    if min(constant, linear, quadratic) < 0 or constant + linear + quadratic <= 0:
        raise ValidateError(f"OpenGL attenuation (a, b, c) = ({constant}, {linear}, {quadratic}): need a, b, c ≥ 0, "
                            "not all zero")
    import drjit as dr

    q, x = to_dr(d), to_dr(c)
    e = float(intensity) * dr.maximum(x, 0.0) / (constant + q * (linear + q * quadratic))
    return to_np(e, d.shape)


def inverse_square(intensity: float, distance: np.ndarray, cos_theta: np.ndarray) -> np.ndarray:
    """E = I max(cos θ, 0) / d² [1]."""
    return attenuated_irradiance(intensity, distance, cos_theta)


# -- registered techniques (family ``arealight``) ----------------------------------------------------
import math  # noqa: E402
from typing import Any  # noqa: E402

from ..families import arealight as _arealight  # noqa: E402
from .sphere_cap import light_geometry_dr  # noqa: E402


def _point(light: Any, points: np.ndarray, normals: np.ndarray, constant_r2: bool) -> np.ndarray:
    import drjit as dr

    g = light_geometry_dr(light, points, normals)
    r, d = g["radius"], g["distance"]
    intensity = math.pi * r * r * g["radiance"] * dr.maximum(g["cos_psi"], 0.0)  # I = π r² L (cos ψ)
    a = r * r if constant_r2 else 0.0
    return to_np(intensity * dr.maximum(g["cos_theta"], 0.0) / (a + d * d), (g["n"],))


@_arealight.register("inverse_square", "point light at the centre, I = π r² L, E = I max(cos θ, 0)/d²",
                     shapes=("sphere", "disc"))
def inverse_square_light(light: Any, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """E = I max(cos θ, 0) / d² [1] with I = π r² L (a sphere's power / 4π; a disc's intensity π r² L cos ψ)."""
    return _point(light, points, normals, False)


@_arealight.register("opengl_r2", "OpenGL attenuation 1/(a + b d + c d²) with (a, b, c) = (r², 0, 1)",
                     shapes=("sphere", "disc"))
def opengl_r2_light(light: Any, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """E = I max(cos θ, 0) / (r² + d²) [2]: exact on a facing disc's axis above the horizon."""
    return _point(light, points, normals, True)
