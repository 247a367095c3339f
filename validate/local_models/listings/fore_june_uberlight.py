"""Fore June's "uberlight-like" vertex + fragment shader [1, §20.5], run as printed and transcribed to numpy.

The listing (``shaders/forejune_20_5_uberlight.*``), in its own words and numbers:

* vertex: L = normalize(lightPos.xyz); d = √(L_y² + L_z²); R = R_y R_x with R_x, R_y of eqs. 20.44–20.45
  (columns as printed), which turns L onto +z; vPosLC = R (p − lightPos), eyeLC = R (eye − lightPos),
  normLC = R p — the normal of a sphere centred on the origin, so the listing shades that sphere only;
* fragment: superEllipseShape (eqs. 20.41–20.42, 1 − smoothstep(q, r, 1)) ×
  distanceAttenuation(vPosLC, maxIntensity 2.0, d0 1.0, alpha 1.0): cuton/cutoff smoothsteps on
  z = |pos.z|, times pow(d0/z, alpha) beyond d0, else maxIntensity·exp(s·pow(z/d0, beta)),
  s = log(1/maxIntensity), β = −α/s; colour = att·max(N·L, 0) + att·max(N·H, 0)⁴ + (0.5, 0.2, 0.2).

Figure 20-17's parameters (:data:`BOOK`): lightPos {1, 1, 2, 1}, eyePos 0, 0, 6.3, 1; a, b, A, B, d =
0.2, 0.3, 0.3, 0.4, 0.8; zNear, zFar = 1.0, 2.0; nearEdge 0.4, farEdge 0.8 — the application's uniforms.
maxIntensity, d0 and alpha are literals of the shader's main (2.0, 1.0, 1.0).

Not registered in the ``uberlight`` family: its normals come from the sphere-at-the-origin assumption,
not from the receivers, so on the family's floor and wall it would measure that assumption rather than
the light. The ``listings`` experiment runs it on the projector scene's sphere, in coordinates centred
on the sphere and scaled to its radius.

References
  [1] Fore June, *An Introduction to 3D Computer Graphics, Stereoscopic Image, and Animation in OpenGL
      and C/C++*, ch. 20 §20.5, eqs. 20.36–20.47, vertex and fragment "Shader of uberlight-like model",
      Figure 20-17.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...gl.listing_harness import Placement, homogeneous
from .runner import run, smoothstep, unit

BOOK: dict[str, Any] = {"lightPos": (1.0, 1.0, 2.0, 1.0), "eyePos": (0.0, 0.0, 6.3, 1.0), "a": 0.2, "b": 0.3,
                        "A": 0.3, "B": 0.4, "d": 0.8, "zNear": 1.0, "zFar": 2.0, "nearEdge": 0.4, "farEdge": 0.8}
MAX_INTENSITY, D0, ALPHA = 2.0, 1.0, 1.0  # literals of the listing's main
AMBIENT = np.array([0.5, 0.2, 0.2])
SHININESS = 4.0


def rotation(light_pos: Any) -> np.ndarray:
    """R = R_y R_x of the vertex shader (eqs. 20.44–20.45; GLSL mat3 columns as printed), row-major."""
    lx, ly, lz = unit(np.asarray(light_pos, dtype=np.float64)[:3])
    d = np.sqrt(ly * ly + lz * lz)
    rx = np.array([[1, 0, 0], [0, lz / d, ly / d], [0, -ly / d, lz / d]]).T
    ry = np.array([[d, 0, lx], [0, 1, 0], [-lx, 0, d]]).T
    return ry @ rx


def super_ellipse_shape(pos: np.ndarray, u: Mapping[str, Any]) -> np.ndarray:
    """1 − smoothstep(q, r, 1), q = ab((bx)^{2/d} + (ay)^{2/d})^{−d/2}, r likewise with A, B (eq. 20.41–20.42)."""
    x, y = np.abs(pos[:, 0] / pos[:, 2]), np.abs(pos[:, 1] / pos[:, 2])
    e1, e2 = 2.0 / u["d"], -u["d"] / 2.0
    q = u["a"] * u["b"] * ((u["b"] * x) ** e1 + (u["a"] * y) ** e1) ** e2
    r = u["A"] * u["B"] * ((u["B"] * x) ** e1 + (u["A"] * y) ** e1) ** e2
    return 1.0 - smoothstep(q, r, 1.0)


def distance_attenuation(pos: np.ndarray, u: Mapping[str, Any], max_intensity: float = MAX_INTENSITY,
                         d0: float = D0, alpha: float = ALPHA) -> np.ndarray:
    """The listing's distanceAttenuation: zones × falloff on the depth z = |pos.z| (module docstring)."""
    z = np.abs(pos[:, 2])
    a = smoothstep(u["zNear"] - u["nearEdge"], u["zNear"], z) * (
        1.0 - smoothstep(u["zFar"], u["zFar"] + u["farEdge"], z))
    s = np.log(1.0 / max_intensity)
    beta = -alpha / s
    return a * np.where(z > d0, (d0 / z) ** alpha, max_intensity * np.exp(s * (z / d0) ** beta))


def light_coordinates(points: np.ndarray, u: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(vPosLC, normLC, eyeLC) of the vertex shader, (N, 3) each."""
    r = rotation(u["lightPos"])
    lp = np.asarray(u["lightPos"], dtype=np.float64)[:3]
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    eye = np.asarray(u["eyePos"], dtype=np.float64)[:3]
    return (p - lp) @ r.T, p @ r.T, np.broadcast_to((eye - lp) @ r.T, p.shape)


def terms(points: np.ndarray, u: Mapping[str, Any]) -> dict[str, np.ndarray]:
    """The fragment shader's parts: ``attenuation``, ``diffuse`` (att·max(N·L, 0)), ``specular``, ``ambient``."""
    pos, norm, eye = light_coordinates(points, u)
    att = super_ellipse_shape(pos, u) * distance_attenuation(pos, u)
    n, lv = unit(norm), -unit(pos)
    h = unit(lv + unit(eye - pos))
    diff = np.maximum(np.sum(n * lv, axis=1), 0.0)
    spec = np.maximum(np.sum(n * h, axis=1), 0.0)
    return {"attenuation": att, "diffuse": att * diff, "specular": att * spec ** SHININESS,
            "ambient": np.broadcast_to(AMBIENT, (len(pos), 3))}


def python(points: np.ndarray, u: Mapping[str, Any] = BOOK) -> np.ndarray:
    """(N, 4) gl_FragColor of the listing, float64: (diffuse + specular + ambient, 1)."""
    t = terms(points, u)
    rgb = (t["diffuse"] + t["specular"])[:, None] + t["ambient"]
    return np.c_[rgb, np.ones(len(rgb))]


def glsl(points: np.ndarray, u: Mapping[str, Any] = BOOK) -> np.ndarray:
    """(N, 4) float32 gl_FragColor of the listing run as printed (mvpMatrix = the per-receiver placement)."""
    p4 = homogeneous(points)
    return run("forejune_20_5", p4, placement=Placement("mvpMatrix"), attributes={"vPosition": p4},
               uniforms=dict(u))


__all__ = ["BOOK", "distance_attenuation", "glsl", "light_coordinates", "python", "rotation", "super_ellipse_shape",
           "terms"]
