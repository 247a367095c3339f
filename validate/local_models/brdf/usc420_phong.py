"""USC CSCI 420 lecture 11 [1]: the Phong shader pair, run as printed (the lecture's printed
attenuation is :mod:`validate.local_models.light.usc420_lecture`).

``phong_usc420_glsl`` runs the lecture's "Phong Shader" vertex + fragment programs (#version 150; the
fragment program prints no #version, the vertex program's is glued on) in the brdf family: per sample
the host rotates the sample's frame so that l is +z (:func:`to_light_frame`: the shader uses dot products
only, so a rotation of (n, l, v) leaves c unchanged) and sets the one uniform viewLightDirection = +z,
places the receiver at viewPosition = −v so that eyedir = normalize(0 − viewPosition) = v, with
modelViewMatrix = normalMatrix = I, projectionMatrix = the placement; k_d = albedo, k_s = ks,
α = phong_exponent, L_a = 0, L_d = L_s = 1/π (π folded into the light,
:mod:`validate.local_models.brdf.classic_brdfs`). Output c.rgb; zero below either horizon as the family
requires. The transcription is ``classic_brdfs.phong`` (same formula).

References
  [1] O. Stein, USC CSCI 420 Computer Graphics, Lecture 11 "Lighting and Shading" (after Angel, ch. 5).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...gl.listing_harness import Placement, homogeneous
from ..brdf.common import finish_front, front_mask, param
from ..families import brdf
from ..listings.runner import register_gl, run


def to_light_frame(lights: np.ndarray, *vectors: np.ndarray) -> list[np.ndarray]:
    """Rotate each sample's vectors by the R_i that takes l_i to +z (Rodrigues: R = I + [w]× + [w]×²/(1 + c),
    w = l × z, c = l·z; l = −z is turned by π about x). By components: the products and differences of
    ``np.cross`` (w = (l_y·1 − l_z·0, l_z·0 − l_x·1, l_x·0 − l_y·0), w × x likewise), the same float64 numbers
    without its (N, 3) temporaries."""
    lt = np.asarray(lights, dtype=np.float64)
    z = np.array([0.0, 0.0, 1.0])
    lc = (lt[:, 0], lt[:, 1], lt[:, 2])
    w = _cross3(lc, (z[0], z[1], z[2]))
    c = lt @ z
    anti = c < -1.0 + 1e-12
    k = np.where(anti, 0.0, 1.0 / np.maximum(1.0 + c, 1e-300))
    out = []
    for vec in vectors:
        x = np.asarray(vec, dtype=np.float64)
        xc = (x[:, 0], x[:, 1], x[:, 2])
        wx = _cross3(w, xc)
        wwx = _cross3(w, wx)
        r = np.empty((len(x), 3))
        for i, sign in enumerate((1.0, -1.0, -1.0)):
            r[:, i] = np.where(anti, xc[i] * sign, xc[i] + wx[i] + k * wwx[i])
        out.append(r)
    return out


def _cross3(a: tuple[Any, Any, Any], b: tuple[Any, Any, Any]) -> tuple[Any, Any, Any]:
    """a × b by components, as ``np.cross`` forms it: (a₁b₂ − a₂b₁, a₂b₀ − a₀b₂, a₀b₁ − a₁b₀)."""
    return a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]


def glsl_phong(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    """(N, 3) c.rgb of the lecture's Phong shader pair, host state of the module docstring."""
    who = "phong_usc420_glsl"
    kd = np.broadcast_to(param(params, "albedo", who), (3,))
    ks = np.broadcast_to(param(params, "ks", who), (3,))
    nrm, vw = to_light_frame(lights, normals, views)
    pos = -vw
    lp = (1.0 / np.pi,) * 4
    u = {"modelViewMatrix": np.eye(4), "normalMatrix": np.eye(4), "La": (0.0,) * 4, "Ld": lp, "Ls": lp,
         "ka": (0.0,) * 4, "kd": (*kd, 1.0), "ks": (*ks, 1.0), "viewLightDirection": (0.0, 0.0, 1.0),
         "alpha": float(param(params, "phong_exponent", who))}
    out = run("usc420_l11", homogeneous(pos), placement=Placement("projectionMatrix"), uniforms=u,
              attributes={"position": pos, "normal": nrm})
    return out[:, :3].astype(np.float64)


@register_gl(brdf, "phong_usc420_glsl", "USC CSCI 420 lecture 11 Phong shader pair (#version 150) on llvmpipe: "
             "[k_d max(l·n, 0) + k_s max(r·v, 0)^α]/π", "usc420_l11",
             seed="001 USC CSCI 420 lecture 11, 'Phong Shader'")
def phong_usc420_glsl(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                      views: np.ndarray) -> np.ndarray:
    return finish_front(front_mask(normals, lights, views), glsl_phong(params, normals, lights, views))


__all__ = ["glsl_phong", "phong_usc420_glsl", "to_light_frame"]
