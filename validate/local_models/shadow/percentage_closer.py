"""Percentage-closer shadow-map techniques of the shadow family: the hard depth test, PCF and PCSS.

Each registers one visibility V′ ∈ [0, 1] read from a :class:`~validate.local_models.shadow.shadow_map.ShadowMap`
(the depth map, its polygon offset and the lookups, shared with the filterable maps); the formulas and the
numbered references [3]–[6] are those of :mod:`validate.local_models.shadow.shadow_map`."""

from __future__ import annotations

import numpy as np

from ...scenes.shadow_scenes import DiscLight
from ..families import shadow
from .shadow_map import ShadowMap, visibility_hard, visibility_pcf, visibility_pcss

PCF_KERNEL = 3  # 3×3 taps as shipped [6]; each tap bilinear (sampler2DShadow, GL_LINEAR [3])
PCSS_SEARCH_TAPS = 32  # blocker-search taps [4]
PCSS_FILTER_TAPS = 64  # filter taps [4]


@shadow.register("hard", "hard shadow map: nearest-texel depth test, glPolygonOffset(2, 4)",
                 source="Red Book ch. 7 [3]: nearest-texel depth comparison with glPolygonOffset(2, 4)",
                 memory_bytes_per_texel=4)
def shadow_hard(shadow_map: ShadowMap, light: DiscLight, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """V′ ∈ {0, 1}: lit iff z_r ≤ D + o at the nearest texel (:func:`visibility_hard`)."""
    return visibility_hard(shadow_map, points, normals)


@shadow.register("pcf", f"PCF {PCF_KERNEL}×{PCF_KERNEL} bilinear taps one texel apart (footprint 4×4 texels)",
                 source="3×3 neighbourhood of LearnOpenGL's PCF [6]; each tap a GL_LINEAR sampler2DShadow [3]",
                 memory_bytes_per_texel=4)
def shadow_pcf(shadow_map: ShadowMap, light: DiscLight, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """V′ = mean of the k×k bilinear comparisons, k = PCF_KERNEL (:func:`visibility_pcf`)."""
    return visibility_pcf(shadow_map, points, normals, PCF_KERNEL)


@shadow.register("pcss", "PCSS: blocker search, penumbra w_p = r (z_r − z_b)/(z_b z_r), variable PCF",
                 source="Fernando 2005 [4]; receiver-plane depth per tap, Isidoro 2006 [5]", memory_bytes_per_texel=4)
def shadow_pcss(shadow_map: ShadowMap, light: DiscLight, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """V′ of PCSS with the light's own radius (:func:`visibility_pcss`, receiver-plane depth on)."""
    return visibility_pcss(shadow_map, points, normals, light.radius, search_taps=PCSS_SEARCH_TAPS,
                           filter_taps=PCSS_FILTER_TAPS).visibility
