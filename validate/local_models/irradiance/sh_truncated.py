"""Truncated spherical-harmonic irradiance (family ``irradiance``): ``sh9``, ``sh1``, ``sh4``.

    E(n) ≈ Σ_{l ≤ l_max} A_l Σ_m L_lm Y_lm(n),   A_0 = π, A_1 = 2π/3, A_2 = π/4   [1, eq. 7–8]

``sh9`` evaluates l_max = 2 as R&H's quadratic form [1, eq. 12]; ``sh1`` and ``sh4`` the same sum at
l_max = 1 and 4. Projection and rendering are :mod:`validate.local_models.irradiance.sh` (the family's
shared SH code), whose reference list this module's "[1]" points into.
"""

from __future__ import annotations

import numpy as np

from ..families import irradiance as _irradiance
from .sh import project_environment, render_irradiance, render_irradiance_rh2001


@_irradiance.register("sh9", "SH order 2 (9 coefficients), R&H 2001 eq. 12 quadratic form")
def sh9(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Order-2 SH irradiance, R&H 2001 eq. 12 (the c1…c5 quadratic form) [1]."""
    return render_irradiance_rh2001(project_environment(radiance, 2), normals)


@_irradiance.register("sh1", "SH order 1 (4 coefficients, 'ambient + directional')")
def sh1(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return render_irradiance(project_environment(radiance, 1), normals)


@_irradiance.register("sh4", "SH order 4 (25 coefficients)")
def sh4(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return render_irradiance(project_environment(radiance, 4), normals)
