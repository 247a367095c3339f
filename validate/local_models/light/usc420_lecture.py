"""USC CSCI 420 lecture 11 [1]: the printed attenuation forms, as techniques.

Printed forms (slides "Point Source", "Limitations of Point Sources", "Diffuse Light Intensity …",
"Summary of Phong Model"):

* point source: I ∝ 1/|p − p₀|²;
* attenuation: 1/(a + b q + c q²), q = |p − p₀|; "real physics would demand only quadratic attenuation"
  and "in practice, a = b = 1, c = 0 is a reasonable starting point" → ``point_usc420_a1b1c0``:
  E = I max(0, l·n)/(1 + q). The slide's I_d = k_d L_d (l·n)/(a + bq + cq²) prints no clamp; the light
  family's irradiance is ≥ 0, so the max(0, ·) of the shader is applied (identical where l·n ≥ 0);
* Phong: I = (k_d L_d (l·n) + k_s L_s (r·v)^α)/(a + bq + cq²) + k_a L_a, r = 2(l·n)n − l;
* spotlight: "cut-off by cone determined by angle θ", "attenuation function (brighter in center)" —
  no formula printed (nothing to run).

The lecture's Phong shader pair runs in the brdf family: :mod:`validate.local_models.brdf.usc420_phong`.

References
  [1] O. Stein, USC CSCI 420 Computer Graphics, Lecture 11 "Lighting and Shading" (after Angel, ch. 5).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..families import light
from ..light.common import Visible, point_irradiance, require


@light.register("point_usc420_a1b1c0", "USC CSCI 420 lecture 11's 'reasonable starting point' attenuation "
                "1/(a + bq + cq²) with a = b = 1, c = 0: E = I max(0, l·n)/(1 + q)", lights=("point",),
                attenuation=(1.0, 1.0, 0.0), seed="001 USC CSCI 420 lecture 11, 'Diffuse Light Intensity'")
def point_usc420_a1b1c0(light_map: Mapping[str, Any], points: Any, normals: Any,
                        visible: Visible | None = None) -> np.ndarray:
    """E = I max(0, n·ω)/(1 + d) · V [1]."""
    require(light_map, kinds=("point",))
    return point_irradiance(light_map, points, normals, visible, attenuation=lambda d: 1.0 / (1.0 + d))


__all__ = ["point_usc420_a1b1c0"]
