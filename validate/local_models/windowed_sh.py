"""Windowed SH9 (deringing) and L1 SH with Geomerics' non-linear reconstruction.

Windowed SH [1]: the order-2 coefficients are multiplied band by band by a window w_l before the
cosine convolution (both are diagonal in l, so the order does not matter),

    E(n) = Σ_{l ≤ 2} w_l A_l Σ_m L_lm Y_lm(n),

which trades ringing (negative lobes opposite a bright light) for blur. With window width W = 3
(= l_max + 1, the band limit):

* ``sh9_hanning``  w_l = (1 + cos(π l / W)) / 2            → (1, 0.75, 0.25);
* ``sh9_lanczos``  w_l = sinc(l / W) = sin(π l / W)/(π l / W) → (1, 0.827, 0.413).

L1 Geomerics [2] (``sh1_geomerics``): from the irradiance's constant term R0 = A0 Y00 L00 (its mean
over all normals) and half its linear coefficient vector R1 = ½ A1 (0.488603) (L11, L1m1, L10) (so
E_lin(n) = 2 R1·n; R1 = c2 (L11, L1m1, L10) with R&H's c2 = 0.511664), per channel with
ρ = |R1| / R0 clamped to [0, 1] (1 for a directional light):

    q = (1 + n·R1/|R1|) / 2,   p = 1 + 2ρ,   a = (1 − ρ) / (1 + ρ),
    E(n) = R0 (a + (1 − a)(p + 1) q^p),

non-negative by construction, with the exact mean R0 over the sphere (q is uniform on [0, 1], so
mean (p + 1) q^p = 1), and exact for a directional light (ρ = 1: E = ((1 + n·d)/2)³ · 4 R0 equals
the true E at n = ±d). |R1| = 0 gives E = R0.

References
  [1] P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008, §"Windowing" (Hanning and
      Lanczos windows over the band index).
  [2] G. Hazel (Geomerics), "Converting SH radiance to irradiance" (reconstruction of irradiance from
      L1 SH as a non-negative power of the half cosine), 2013; also Iwanicki & Sloan, "Precomputed
      lighting in Call of Duty: Infinite Warfare", SIGGRAPH 2017 course, which discusses it.
"""

from __future__ import annotations

import math

import numpy as np

from . import sh
from .families import irradiance as _irradiance

WINDOW_WIDTH = 3.0  # W = l_max + 1 for SH9


def hanning(l: int, width: float = WINDOW_WIDTH) -> float:
    """(1 + cos(π l / W)) / 2, zero from l = W on [1]."""
    return 0.5 * (1.0 + math.cos(math.pi * l / width)) if l < width else 0.0


def lanczos(l: int, width: float = WINDOW_WIDTH) -> float:
    """sinc(l / W) = sin(π l / W) / (π l / W) [1]; 1 at l = 0."""
    return 1.0 if l == 0 else math.sin(math.pi * l / width) / (math.pi * l / width)


def windowed_sh9(radiance: np.ndarray, normals: np.ndarray, window) -> np.ndarray:  # noqa: ANN001 (callable)
    coeffs = sh.project_environment(radiance, 2)
    w = np.array([window(sh.degree_of(k)) for k in range(9)])[:, None]
    return sh.render_irradiance(w * coeffs, normals, 2)


@_irradiance.register("sh9_hanning", "SH9 with a Hanning window (1, 0.75, 0.25) over the bands (Sloan 2008)")
def sh9_hanning(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return windowed_sh9(radiance, normals, hanning)


@_irradiance.register("sh9_lanczos", "SH9 with a Lanczos window (1, 0.827, 0.413) over the bands (Sloan 2008)")
def sh9_lanczos(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return windowed_sh9(radiance, normals, lanczos)


def geomerics_l1(coeffs4: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """[2]'s reconstruction (module docstring) from L1 coefficients (4, 3) at normals (N, 3) → (N, 3)."""
    r0 = math.pi * 0.5 * math.sqrt(1.0 / math.pi) * coeffs4[0]  # A0 Y00 L00, per channel
    half_a1 = 0.5 * (2.0 * math.pi / 3.0) * 0.5 * math.sqrt(3.0 / math.pi)  # ½ A1 · 0.488603 = c2
    r1 = half_a1 * np.stack([coeffs4[3], coeffs4[1], coeffs4[2]], axis=-1)  # (3 channels, xyz)
    out = np.empty((len(normals), 3))
    for c in range(3):
        length = float(np.linalg.norm(r1[c]))
        if r0[c] <= 0 or length == 0.0:
            out[:, c] = max(float(r0[c]), 0.0)
            continue
        rho = min(length / float(r0[c]), 1.0)
        q = 0.5 * (1.0 + normals @ (r1[c] / length))
        p = 1.0 + 2.0 * rho
        a = (1.0 - rho) / (1.0 + rho)
        out[:, c] = r0[c] * (a + (1.0 - a) * (p + 1.0) * np.power(q, p))
    return out


@_irradiance.register("sh1_geomerics", "L1 SH with Geomerics' non-negative reconstruction (Hazel 2013)")
def sh1_geomerics(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return geomerics_l1(sh.project_environment(radiance, 1), normals)
