"""Karis 2013's representative-point sphere light, a technique of the ``specular_arealight`` family.

Karis [1] §"Area lights", eq. 10–14: the sphere light (centre c, radius R, radiance L_e) seen from p is replaced
by a point light at the point of the sphere closest to the mirror ray r = reflect(−v, n):

    L = c − p,   C = (L·r) r − L,   P = L + C · saturate(R/‖C‖),   l = P/‖P‖          (eq. 11)

lit with the sphere's illuminance at normal incidence, E_⊥ = L_e π R²/‖L‖² (the point light of the same power),
times (n·l), through the GGX BRDF f_r(l, v) (Walter et al. 2007 eq. 20, separable Smith G, Schlick F(v·h) with
``f0``), with the energy normalisation of the widened lobe

    α′ = saturate(α + R/(2‖L‖)),   L_o = (α/α′)² f_r(l, v) (n·l) E_⊥                         (eq. 10, 14)

Without the normalisation (``representative_point_unnormalized``) the highlight of a rough-enough surface gathers
the whole sphere's power into the sharp lobe: the paper's reason for eq. 14.

References
  [1] B. Karis, "Real shading in Unreal Engine 4", SIGGRAPH 2013 course (Physically Based Shading in Theory and
      Practice), pp. 14–16.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import ValidateError
from .classic_brdfs import Geometry, fresnel_schlick, ggx_d, smith_g1
from .ltc import brdf_params, specular_arealight


def _unit(x: np.ndarray) -> np.ndarray:
    return x / np.maximum(np.linalg.norm(x, axis=-1, keepdims=True), 1e-300)


def representative_point(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
                         views: np.ndarray, who: str, normalise: bool = True) -> np.ndarray:
    """L_o of Karis's representative point (eq. 10–14), (N, 3)."""
    if light.get("shape") != "sphere":
        raise ValidateError(f"technique '{who}' (specular_arealight): handles sphere lights only, got "
                            f"{light.get('shape')!r}")
    alpha, f0 = brdf_params(brdf, who)
    n, v = _unit(np.asarray(normals, dtype=np.float64)), _unit(np.asarray(views, dtype=np.float64))
    radius = float(light["radius"])
    to_c = np.asarray(light["center"], dtype=np.float64) - np.asarray(points, dtype=np.float64)
    dist = np.linalg.norm(to_c, axis=-1)
    r = 2.0 * np.sum(n * v, -1, keepdims=True) * n - v
    c2r = np.sum(to_c * r, -1, keepdims=True) * r - to_c
    t = np.clip(radius / np.maximum(np.linalg.norm(c2r, axis=-1, keepdims=True), 1e-300), 0.0, 1.0)
    l = _unit(to_c + c2r * t)
    g = Geometry(n, l, v)
    spec = (ggx_d(g.ch, alpha) * smith_g1(g.cl, alpha, "ggx") * smith_g1(g.cv, alpha, "ggx")
            / (4.0 * np.maximum(g.cv, 1e-12)))  # f_r (n·l) with F = 1
    e_perp = float(light.get("radiance", 1.0)) * np.pi * radius ** 2 / dist ** 2
    scale = (alpha / np.clip(alpha + radius / (2.0 * dist), 0.0, 1.0)) ** 2 if normalise else np.ones_like(dist)
    return g.finish(fresnel_schlick(g.vh, f0) * (spec * e_perp * scale)[:, None])


@specular_arealight.register("representative_point", "Karis 2013 representative point on the sphere closest to the "
                             "mirror ray, with the (α/α′)² energy normalisation", shapes=("sphere",))
def karis_sphere(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
                 views: np.ndarray) -> np.ndarray:
    return representative_point(light, brdf, points, normals, views, "representative_point")


@specular_arealight.register("representative_point_unnormalized", "Karis 2013 representative point without the "
                             "(α/α′)² normalisation (eq. 14 left out)", shapes=("sphere",))
def karis_sphere_unnormalized(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray,
                              normals: np.ndarray, views: np.ndarray) -> np.ndarray:
    return representative_point(light, brdf, points, normals, views, "representative_point_unnormalized",
                                normalise=False)


__all__ = ["representative_point"]
