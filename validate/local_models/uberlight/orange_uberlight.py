"""The Orange Book's überlight, Listings 12.6 + 12.7 [1, §12.4], run as printed (GLSL 1.10, no glue, no edit).

Family ``uberlight`` technique ``uberlight_orange_glsl`` (registered where the compatibility runtime
starts). Host state transcribed from the family's light mapping:

* WCtoLC = [axes | −axes·position] (rows x, y, z = forward of the light), WCtoLCit its rotation part (an
  orthonormal frame: the inverse transpose of the rotation is the rotation); MCtoWC = MCtoWCit = I;
  ViewPosition = the viewer (receiver + view direction, per receiver); gl_Vertex/gl_Normal = the receivers;
  ``ftransform()``'s projection is the harness's per-receiver placement;
* SeWidth = width, SeHeight = height, SeWidthEdge/SeHeightEdge = the edges, SeRoundness = roundness,
  BarnShaping = true; DsNear/DsFar/DsNearEdge/DsFarEdge = near/far and their edges;
* LightColor = I₀ (grey), LightWeights = (0, 1, 1) (no ambient), SurfaceWeights = (1, 1, 1),
  SurfaceColor = ρ/π per receiver (so the diffuse term is the radiance of a Lambertian surface of albedo ρ
  under the irradiance I₀·A·D·(n·l)), SurfaceRoughness = the material's ``ks``.

What the listing computes that the family's Python ``uberlight`` does not: the printed specular is
(n·l)·max(n·h, 0)·SurfaceRoughness — no exponent; and behind the light (z < 0) the listing still shapes
(pos.xy/pos.z with abs) and lights receivers at depth |z|, where the Python technique returns 0. Output:
the red channel (grey light and surface); the shadow (host visibility) multiplies it.

:func:`python` is the float64 transcription of the two listings; the test holds the GLSL run to it.

References
  [1] R. Rost, *OpenGL Shading Language*, 2nd ed., Addison-Wesley 2006, §12.4, Listings 12.6 and 12.7.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...gl.listing_harness import Placement, homogeneous
from ..families import uberlight
from ..listings.runner import register_gl, run, smoothstep, unit
from ..uberlight.common import check_light


def world_to_light(light: Mapping[str, Any]) -> np.ndarray:
    """WCtoLC (4 × 4, row-major)."""
    axes = np.asarray(light["axes"], dtype=np.float64).reshape(3, 3)
    m = np.eye(4)
    m[:3, :3] = axes
    m[:3, 3] = -axes @ np.asarray(light["position"], dtype=np.float64)
    return m


def uniforms(light: Mapping[str, Any], ks: float) -> dict[str, Any]:
    """The listing's uniforms from the family's light mapping (module docstring)."""
    wc = world_to_light(light)
    it = np.eye(4)
    it[:3, :3] = wc[:3, :3]
    i0 = float(light["intensity"])
    return {"WCLightPos": tuple(np.asarray(light["position"], dtype=float)), "WCtoLC": wc, "WCtoLCit": it,
            "MCtoWC": np.eye(4), "MCtoWCit": np.eye(4), "LightColor": (i0, i0, i0), "LightWeights": (0.0, 1.0, 1.0),
            "SurfaceWeights": (1.0, 1.0, 1.0), "SurfaceRoughness": float(ks), "AmbientClamping": True,
            "BarnShaping": True, "SeWidth": float(light["width"]), "SeHeight": float(light["height"]),
            "SeWidthEdge": float(light["width_edge"]), "SeHeightEdge": float(light["height_edge"]),
            "SeRoundness": float(light["roundness"]), "DsNear": float(light["near"]), "DsFar": float(light["far"]),
            "DsNearEdge": float(light["near_edge"]), "DsFarEdge": float(light["far_edge"])}


def _albedo(material: Mapping[str, Any], n: int) -> np.ndarray:
    return np.broadcast_to(np.asarray(material.get("albedo", 1.0), dtype=np.float64), (n,))


def python(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, views: np.ndarray,
           material: Mapping[str, Any]) -> np.ndarray:
    """(N,) the listings' red channel in float64 (Listing 12.6 transforms, Listing 12.7 main)."""
    u = uniforms(light, float(material.get("ks", 0.0)))
    wc = u["WCtoLC"]
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    pos = p @ wc[:3, :3].T + wc[:3, 3]
    cam = (p + np.asarray(views, dtype=np.float64)) @ wc[:3, :3].T + wc[:3, 3]
    nrm = np.asarray(normals, dtype=np.float64) @ wc[:3, :3].T
    ap = np.abs(pos[:, :2] / pos[:, 2:3])
    w, h = u["SeWidth"], u["SeHeight"]
    ww, hh = w + u["SeWidthEdge"], h + u["SeHeightEdge"]
    e1, e2 = 2.0 / u["SeRoundness"], -u["SeRoundness"] / 2.0
    inner = w * h * ((h * ap[:, 0]) ** e1 + (w * ap[:, 1]) ** e1) ** e2
    outer = ww * hh * ((hh * ap[:, 0]) ** e1 + (ww * ap[:, 1]) ** e1) ** e2
    depth = np.abs(pos[:, 2])
    dist = smoothstep(u["DsNear"] - u["DsNearEdge"], u["DsNear"], depth) * (
        1.0 - smoothstep(u["DsFar"], u["DsFar"] + u["DsFarEdge"], depth))
    att = (1.0 - smoothstep(inner, outer, 1.0)) * dist
    n, lv, v = unit(nrm), -unit(pos), unit(cam - pos)
    hv = unit(lv + v)
    ndotl, ndoth = np.sum(n * lv, axis=1), np.sum(n * hv, axis=1)
    diffuse = np.maximum(ndotl, 0.0)
    specular = diffuse * np.maximum(ndoth, 0.0) * u["SurfaceRoughness"]
    i0 = u["LightColor"][0]
    return att * (i0 * _albedo(material, len(p)) / np.pi * diffuse + i0 * specular)


def glsl(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, views: np.ndarray,
         material: Mapping[str, Any]) -> np.ndarray:
    """(N,) red channel of Listings 12.6/12.7 run as printed (module docstring)."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    alb = _albedo(material, len(p)) / np.pi
    out = run("orange_12_6_12_7", homogeneous(p), placement=Placement(None), legacy_vertex=homogeneous(p),
              legacy_normal=np.asarray(normals, dtype=np.float64), uniforms=uniforms(light, material.get("ks", 0.0)),
              per_point={"SurfaceColor": np.repeat(alb[:, None], 3, axis=1),
                         "ViewPosition": homogeneous(p + np.asarray(views, dtype=np.float64))})
    return out[:, 0].astype(np.float64)


@register_gl(uberlight, "uberlight_orange_glsl", "Orange Book Listings 12.6/12.7 run unchanged on llvmpipe (GLSL "
             "1.10): superellipse × distance shaping, diffuse + unexponentiated specular, no falloff",
             "orange_12_6_12_7",
             seed="002 OpenGL Shading Language §12.4, Listings 12.6/12.7")
def uberlight_orange_glsl(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray, views: np.ndarray,
                          material: Mapping[str, Any], shadow: np.ndarray | None = None) -> np.ndarray:
    """Listings 12.6/12.7 through the GL harness × the host's shadow visibility."""
    check_light(light)
    out = glsl(light, points, normals, views, material)
    return out if shadow is None else out * np.asarray(shadow, dtype=np.float64)


__all__ = ["glsl", "python", "uberlight_orange_glsl", "uniforms", "world_to_light"]
