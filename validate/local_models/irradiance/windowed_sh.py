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

Declared thresholds (claims ``<experiment>.technique.<name>.flux_rgb.max``):

* Windowed SH9 is linear in L with the zonal kernel (addition theorem, Σ_m Y_lm(n) Y_lm(ω) =
  (2l+1)/(4π) P_l(n·ω))

      E′(n) = ∫ L(ω) K̃_w(n·ω) dω,   K̃_w(x) = Σ_{l ≤ 2} w_l A_l (2l+1)/(4π) P_l(x),

  so for ANY non-negative lighting, per channel (Hölder, L¹–L^∞; the argument of R&H's 3/32 bound
  [3, 4]: w = (1, 1, 1) gives K̃ = 3/32 + x/2 + 15x²/32 and the sup 3/32)

      max_n |E′(n) − E(n)| ≤ sup_{x ∈ [−1, 1]} |K̃_w(x) − max(x, 0)| · ∫ L dω,

  and the flux metrics divide by exactly ∫ L dω (:mod:`validate.metrics.irradiance_error`:
  ``flux_rgb`` per channel; ``flux_luminance`` ≤ the same since Y is a positive combination).
  :func:`kernel_bound` computes the sup exactly (K̃_w is a polynomial: ends, kink at 0 and stationary
  points of each piece): Hanning 0.29688 (at x = 1, the blur of the peak), Lanczos 0.20729; a
  directional light attains it. The declared threshold adds :data:`CLOSED_FORM_TOLERANCE`: the model
  integrates the map's texels, the reference Mitsuba's bilinear map; their irradiances agree within
  the suite's closed-form tolerance (claims ``reference.closed_form.*``, measured ≤ 3.3·10⁻⁴ Φ).
* Geomerics L1 (and hallucinated ZH3, :mod:`.zh3`) depend on L only through L00 and L1, i.e. per
  channel through the flux Φ and the mean direction vector m = ∫ L ω dω / Φ (|m| = ρ): for grey
  lighting E′(n) = Φ k_ρ(n·m̂) with a closed-form kernel (:func:`geomerics_kernel`; ρ = 1, a
  directional light: k = ((1 + x)/2)³, error |k − max(x, 0)| ≤ 1/8 at the horizon x = 0). For
  lighting inside a cone of half-angle α about its axis, Jensen (max(·, 0) convex) gives
  E(n) ≥ Φ max(ρ n·m̂, 0), the cone gives E(n) ≤ Φ max(n·m̂ + 2α, 0) and ρ ≥ cos α, so

      |E′ − E| / Φ ≤ max_{ρ ∈ [cos α, 1]} max( sup_x [k_ρ(x) − max(ρx, 0)], sup_x [max(x + 2α, 0) − k_ρ(x)] )

  (:func:`near_directional_bound`), judged on ``near_directional`` with α = its disc's half-angle
  plus one texel diagonal (the texels the disc touches).

References
  [1] P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008, §"Windowing" (Hanning and
      Lanczos windows over the band index).
  [2] G. Hazel (Geomerics), "Converting SH radiance to irradiance" (reconstruction of irradiance from
      L1 SH as a non-negative power of the half cosine), 2013; also Iwanicki & Sloan, "Precomputed
      lighting in Call of Duty: Infinite Warfare", SIGGRAPH 2017 course, which discusses it.
  [3] R. Ramamoorthi, P. Hanrahan, "On the relationship between radiance and irradiance", JOSA A 18(10),
      2001 (A_l, eq. 19) and [4] "An Efficient Representation for Irradiance Environment Maps", SIGGRAPH
      2001 (the directional worst case 3/32 of Φ).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from ...scenes.latlong import CLOSED_FORM_TOLERANCE
from ...scenes.procedural import near_directional_half_angle
from ..families import irradiance as _irradiance
from ..precision import rgb_to_np, vec_to_dr
from . import sh
from .kernel_bounds import near_directional_bound

WINDOW_WIDTH = 3.0  # W = l_max + 1 for SH9


# -- windowed-SH kernel and its exact Hölder bound -------------------------------------------------------------


def window_weights(window: Callable[[int], float], lmax: int = 2) -> np.ndarray:
    """(w_0, …, w_lmax) of a window over the band index."""
    return np.array([window(l) for l in range(lmax + 1)], dtype=np.float64)


def kernel_legendre(weights: Sequence[float]) -> np.ndarray:
    """Legendre coefficients of K̃_w(x) = Σ_l w_l A_l (2l+1)/(4π) P_l(x) (addition theorem, [3] eq. 19 A_l)."""
    return np.array([w * sh.clamped_cosine_al(l) * (2 * l + 1) / (4 * math.pi) for l, w in enumerate(weights)])


def zonal_kernel(weights: Sequence[float], x: np.ndarray) -> np.ndarray:
    """K̃_w at x = n·ω ∈ [−1, 1]: windowed SH irradiance of a unit-flux directional light."""
    return np.polynomial.legendre.legval(np.asarray(x, dtype=np.float64), kernel_legendre(weights))


def kernel_bound(weights: Sequence[float]) -> float:
    """sup_{x ∈ [−1, 1]} |K̃_w(x) − max(x, 0)|, exactly: on [−1, 0] and [0, 1] the difference is a polynomial,
    so the sup is at an end, at 0 or at a real root of its derivative inside the piece. w = (1, 1, 1) → 3/32."""
    k = np.polynomial.Polynomial(np.polynomial.legendre.leg2poly(kernel_legendre(weights)))
    best = 0.0
    for lo, hi, piece in ((-1.0, 0.0, k), (0.0, 1.0, k - np.polynomial.Polynomial([0.0, 1.0]))):
        roots = piece.deriv().roots() if piece.degree() > 1 else np.array([])
        xs = [lo, hi] + [float(r.real) for r in np.atleast_1d(roots) if abs(r.imag) < 1e-12 and lo < r.real < hi]
        best = max(best, float(np.max(np.abs(piece(np.array(xs))))))
    return best


def kernel_mean(weights: Sequence[float], samples: int = 200001) -> float:
    """½ ∫_{−1}^{1} |K̃_w(x) − max(x, 0)| dx: the mean error over normals for a directional light (any
    lighting's mean error is at most this, by the triangle inequality and rotation invariance)."""
    x = np.linspace(-1.0, 1.0, samples)
    return float(np.trapezoid(np.abs(zonal_kernel(weights, x) - np.maximum(x, 0.0)), x) / 2)


def geomerics_kernel(rho: float, x: np.ndarray) -> np.ndarray:
    """[2] per unit flux, written from the paper's formula (not from :func:`geomerics_l1`): R0 = Φ/4,
    |R1| = ρΦ/4, q = (1 + x)/2, p = 1 + 2ρ, a = (1 − ρ)/(1 + ρ): k_ρ(x) = ¼ (a + (1 − a)(p + 1) q^p)."""
    q = 0.5 * (1.0 + np.asarray(x, dtype=np.float64))
    p, a = 1.0 + 2.0 * rho, (1.0 - rho) / (1.0 + rho)
    return 0.25 * (a + (1.0 - a) * (p + 1.0) * np.power(q, p))


GEOMERICS_BOUND = near_directional_bound(geomerics_kernel, near_directional_half_angle())
HOLDER_SOURCE = ("Hölder (L¹·L^∞) on the windowed zonal kernel K̃_w(x) = Σ w_l A_l (2l+1)/(4π) P_l(x), as in R&H JOSA "
                 "2001 / SIGGRAPH 2001's 3/32 bound for SH9: max_n |E′ − E| ≤ sup|K̃_w − max(x, 0)| Φ for any "
                 "lighting; sup computed exactly from the window "
                 "(validate.local_models.irradiance.windowed_sh.kernel_bound) "
                 "+ 0.1 % Φ, the reference's closed-form tolerance (texels vs Mitsuba's bilinear map)")


def hanning(l: int, width: float = WINDOW_WIDTH) -> float:
    """(1 + cos(π l / W)) / 2, zero from l = W on [1]."""
    return 0.5 * (1.0 + math.cos(math.pi * l / width)) if l < width else 0.0


def lanczos(l: int, width: float = WINDOW_WIDTH) -> float:
    """sinc(l / W) = sin(π l / W) / (π l / W) [1]; 1 at l = 0."""
    return 1.0 if l == 0 else math.sin(math.pi * l / width) / (math.pi * l / width)


HANNING_BOUND = kernel_bound(window_weights(hanning))
LANCZOS_BOUND = kernel_bound(window_weights(lanczos))


def windowed_sh9(radiance: np.ndarray, normals: np.ndarray, window: Callable[[int], float]) -> np.ndarray:
    """E′(n) = Σ_{l ≤ 2} w_l A_l Σ_m L_lm Y_lm(n) (module docstring, [1])."""
    coeffs = sh.project_environment(radiance, 2)
    w = np.array([window(sh.degree_of(k)) for k in range(9)])[:, None]
    return sh.render_irradiance(w * coeffs, normals, 2)


@_irradiance.register("sh9_hanning", "SH9 with a Hanning window (1, 0.75, 0.25) over the bands (Sloan 2008)",
                      thresholds={"flux_rgb.max": HANNING_BOUND + CLOSED_FORM_TOLERANCE},
                      source=f"{HOLDER_SOURCE}: Hanning sup = {HANNING_BOUND:.5f} (at x = 1)")
def sh9_hanning(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return windowed_sh9(radiance, normals, hanning)


@_irradiance.register("sh9_lanczos", "SH9 with a Lanczos window (1, 0.827, 0.413) over the bands (Sloan 2008)",
                      thresholds={"flux_rgb.max": LANCZOS_BOUND + CLOSED_FORM_TOLERANCE},
                      source=f"{HOLDER_SOURCE}: Lanczos sup = {LANCZOS_BOUND:.5f} (at x = 1)")
def sh9_lanczos(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return windowed_sh9(radiance, normals, lanczos)


def geomerics_l1(coeffs4: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """[2]'s reconstruction (module docstring) from L1 coefficients (4, 3) at normals (N, 3) → (N, 3); the
    per-channel constants (R0, ρ, the axis) in float64, the per-normal part in drjit in the active dtype
    (:mod:`..precision`: the irradiance family's float32)."""
    import drjit as dr

    r0 = math.pi * 0.5 * math.sqrt(1.0 / math.pi) * coeffs4[0]  # A0 Y00 L00, per channel
    half_a1 = 0.5 * (2.0 * math.pi / 3.0) * 0.5 * math.sqrt(3.0 / math.pi)  # ½ A1 · 0.488603 = c2
    r1 = half_a1 * np.stack([coeffs4[3], coeffs4[1], coeffs4[2]], axis=-1)  # (3 channels, xyz)
    x, y, z = vec_to_dr(normals)
    out = []
    for c in range(3):
        length = float(np.linalg.norm(r1[c]))
        if r0[c] <= 0 or length == 0.0:
            out.append(max(float(r0[c]), 0.0))
            continue
        rho = min(length / float(r0[c]), 1.0)
        u = r1[c] / length
        q = 0.5 * (1.0 + x * float(u[0]) + y * float(u[1]) + z * float(u[2]))
        p = 1.0 + 2.0 * rho
        a = (1.0 - rho) / (1.0 + rho)
        out.append(float(r0[c]) * (a + (1.0 - a) * (p + 1.0) * dr.power(dr.maximum(q, 0.0), p)))
    return rgb_to_np(*out, len(normals))


@_irradiance.register("sh1_geomerics", "L1 SH with Geomerics' non-negative reconstruction (Hazel 2013)",
                      thresholds={"flux_rgb.max": GEOMERICS_BOUND + CLOSED_FORM_TOLERANCE},
                      environments=("near_directional",),
                      source="closed form on a directional light (Hazel 2013's k = ((1 + x)/2)³ for ρ = 1: error ≤ 1/8 "
                             "at the horizon), widened for near_directional's 0.5° disc + one texel by Jensen's "
                             "inequality and the cone (validate.local_models.irradiance.kernel_bounds."
                             "near_directional_bound: "
                             f"{GEOMERICS_BOUND:.5f}) + 0.1 % Φ, the reference's closed-form tolerance")
def sh1_geomerics(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return geomerics_l1(sh.project_environment(radiance, 1), normals)
