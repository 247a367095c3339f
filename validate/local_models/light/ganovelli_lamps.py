"""Ganovelli et al.'s WebGL Lambert shaders, Listings 6.3 + 6.4 (the sun) and 6.3 + 6.9 (street lamps) [1, §6.7].

Run on llvmpipe as GLSL ES 1.00 (glue ``#version 100``) with the catalogue's edits (line numbers, the
JavaScript string wrapper, the missing ``uniform`` of uViewSpaceNormalMatrix, the loop's missing
``++i)``; see :mod:`.catalog`). Host state: uModelViewMatrix = I and uViewSpaceNormalMatrix = I (world =
view space), uProjectionMatrix = the harness's per-receiver placement, aDiffuse = (1, 1, 1, 1).

* ``directional_ganovelli_glsl`` (6.3 + 6.4): uLightDirection = (direction, 0) (the listing's
  L = normalize(−uLightDirection.xyz): the direction the light travels), uLightColor = E⊥:
  E = E⊥ max(0, N·L).
* ``point_ganovelli_6_9_glsl`` (6.3 + 6.9, one lamp): uLightsGeometry[0] = (position, 1), uLightsColor[0] =
  (I, I, I, 1): E = I max(0, N·L)/r² with the printed r = 0.03·3.14·3.14·|p − x| — the inverse square
  divided by (0.03·3.14²)² = 0.08749, i.e. ×11.43 (:data:`LAMP_FACTOR`).

:func:`python_directional` and :func:`python_lamp` are the float64 transcriptions.

References
  [1] F. Ganovelli et al., *Introduction to Computer Graphics*, CRC 2014, §6.7.2 Listings 6.3–6.4, §6.7.4
      Listing 6.9 (envymycarbook.com chapter6/0 and chapter6/1 shaders.js).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...gl.listing_harness import Placement
from ..families import light
from ..light.common import Visible, as_points, require, shadow
from ..listings.runner import register_gl, run, unit

LAMP_R_SCALE = 0.03 * 3.14 * 3.14  # the listing's r = 0.03*3.14*3.14*length(...)
LAMP_FACTOR = 1.0 / LAMP_R_SCALE ** 2  # the listing's E over I cos θ/d²


def _host(points: np.ndarray, normals: np.ndarray) -> dict[str, Any]:
    n = len(points)
    return {"placement": Placement("uProjectionMatrix"),
            "attributes": {"aPosition": points, "aNormal": normals, "aDiffuse": np.ones((n, 4))}}


def python_directional(direction: np.ndarray, e_perp: float, normals: np.ndarray) -> np.ndarray:
    """(N,) E⊥ max(0, N·L), L = normalize(−direction) (Listing 6.4)."""
    return e_perp * np.maximum(0.0, unit(np.asarray(normals)) @ unit(-np.asarray(direction, dtype=np.float64)))


def python_lamp(position: np.ndarray, intensity: float, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(N,) I max(0, N·L)/r², r = 0.03·3.14·3.14·|position − x| (Listing 6.9, one positional lamp)."""
    to = np.asarray(position, dtype=np.float64) - points
    r = LAMP_R_SCALE * np.linalg.norm(to, axis=1)
    return intensity * np.maximum(0.0, np.sum(unit(normals) * unit(to), axis=1)) / (r * r)


def glsl_directional(direction: np.ndarray, e_perp: float, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    d = np.asarray(direction, dtype=np.float64)
    u = {"uLightDirection": (*d, 0.0), "uLightColor": (e_perp,) * 3, "uModelViewMatrix": np.eye(4),
         "uViewSpaceNormalMatrix": np.eye(3)}
    out = run("ganovelli_6_3_6_4", points, uniforms=u, **_host(points, normals))
    return out[:, 0].astype(np.float64)


def glsl_lamp(position: np.ndarray, intensity: float, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    p = np.asarray(position, dtype=np.float64)
    out = run("ganovelli_6_9", points, uniforms={"uLightsGeometry[0]": (*p, 1.0), "uLightsColor[0]": (intensity,) * 3
                                                  + (1.0,), "uModelViewMatrix": np.eye(4),
                                                  "uViewSpaceNormalMatrix": np.eye(3)}, **_host(points, normals))
    return out[:, 0].astype(np.float64)


@register_gl(light, "directional_ganovelli_glsl", "Ganovelli Listings 6.3 + 6.4 (WebGL Lambert, directional) on "
             "llvmpipe: E = E⊥ max(0, N·L)", "ganovelli_6_3_6_4", lights=("directional",),
             seed="003 Ganovelli §6.7.2, Listings 6.3/6.4")
def directional_ganovelli_glsl(light_map: Mapping[str, Any], points: Any, normals: Any,
                               visible: Visible | None = None) -> np.ndarray:
    require(light_map, "direction", "irradiance", kinds=("directional",))
    p, n = as_points(points, normals)
    e = glsl_directional(light_map["direction"], float(light_map["irradiance"]), p, n)
    reach = p - 1.0e3 * unit(np.asarray(light_map["direction"], dtype=np.float64))
    return e * shadow(visible, p, n, reach) if visible is not None else e


@register_gl(light, "point_ganovelli_6_9_glsl", "Ganovelli Listing 6.9 (street lamps) on llvmpipe: "
             "I max(0, N·L)/r², r = 0.03·3.14²·d as printed (×11.4 the inverse square)", "ganovelli_6_9",
             lights=("point",),
             seed="003 Ganovelli §6.7.4, Listing 6.9")
def point_ganovelli_6_9_glsl(light_map: Mapping[str, Any], points: Any, normals: Any,
                             visible: Visible | None = None) -> np.ndarray:
    require(light_map, "position", "intensity", kinds=("point",))
    p, n = as_points(points, normals)
    pos = np.asarray(light_map["position"], dtype=np.float64)
    e = glsl_lamp(pos, float(light_map["intensity"]), p, n)
    return e * shadow(visible, p, n, np.broadcast_to(pos, p.shape)) if visible is not None else e


__all__ = ["LAMP_FACTOR", "glsl_directional", "glsl_lamp", "python_directional", "python_lamp"]
