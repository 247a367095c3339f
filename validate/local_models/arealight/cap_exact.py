"""``cap_exact`` (family ``arealight``): the exact horizon-clipped irradiance of the cap a sphere or disc light
subtends, E = L · E_cap(cos θ, sin²σ) (Snyder 1996 [1]; Lagarde & de Rousiers 2014 [2], §4.7.2). The closed
form, the light geometry and the references are :mod:`validate.local_models.arealight.sphere_cap` (the family's
shared cap code, also used by the disc-SH and point-light techniques and the shadow family).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..families import arealight as _arealight
from ..precision import to_np
from .sphere_cap import cap_irradiance_dr, light_geometry_dr


@_arealight.register("cap_exact", "exact horizon-clipped cap irradiance (Snyder 1996; Lagarde & de Rousiers 2014); "
                     "a disc as the cap it subtends from its axis, times its foreshortening", shapes=("sphere", "disc"))
def cap_exact(light: Any, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """E = L · E_cap(cos θ, sin²σ) [1, 2] — exact for a sphere at every receiver. A disc: [2]'s
    "illuminanceSphereOrDisk" with sin²σ = r²/(r² + d²) times max(0, cos ψ) (ψ between the disc's normal and
    the receiver), exact on the disc's axis facing it (ψ = 0), an approximation elsewhere."""
    import drjit as dr

    g = light_geometry_dr(light, points, normals)
    e = cap_irradiance_dr(g["cos_theta"], g["sin2_sigma"]) * g["radiance"] * dr.maximum(g["cos_psi"], 0.0)
    return to_np(e, (g["n"],))
