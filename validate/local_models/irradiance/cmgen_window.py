"""Filament cmgen's automatic SH window (``--sh-window auto``, its default) as an irradiance technique.

What cmgen does (read in google/filament: ``tools/cmgen/src/cmgen.cpp``, ``sphericalHarmonics``; and
``libs/ibl/src/CubemapSH.cpp``, ``CubemapSH::sincWindow`` and ``CubemapSH::windowSH`` with its lambdas
``shmin`` and ``windowing``) [1]; this module is our own code for the same algorithm:

1. The shipping path (``--sh-shader`` / ``--deploy``) computes the *irradiance* SH of 3 bands,
   e_lm = A_l L_lm (``computeSH(…, 3, irradiance = true)``); ``g_sh_window = 0`` means "auto".
2. The window is a sinc to the 4th power over the band index with cut-off c (in bands):
   w_0 = 1, w_l = (sin(π l / c) / (π l / c))⁴ for 0 < l < c, 0 from l = c on [1, 2].
3. Auto: per colour channel, bisect c in [3, 13] (3 = the number of bands, 13 = 4·3 + 1): at most 16
   steps while l + 0.1 < r, m = (l + r)/2; if the windowed function's minimum over the sphere is < 0,
   r = m, else l = m; the channel's answer is l and the running cut-off is min(cut-off, l) (the next
   channel starts its bracket at that cut-off). The one cut-off is then applied to all channels.

So the windowed irradiance is non-negative on the whole sphere (the design property claimed in ``sh9``):
every accepted c was checked; c = 3 itself is never tested, but its kernel ¼ + 0.234 x + 0.0091 (3x² − 1)
is positive on [−1, 1], so it is non-negative for any non-negative lighting.

The minimum over the sphere: cmgen's ``shmin`` follows Sloan [3] (rotate the linear part onto z, close
form for the zonal and |m| = 2 parts, Newton's method for |m| = 1, in float). Here
:func:`sphere_min` solves the same problem exactly: an order-2 SH function on the sphere is
f(n) = c + b·n + nᵀQn (:func:`quadratic_form`), and min_{|n|=1} f is the trust-region subproblem,
whose Lagrangian dual max_{μ < λ_min(Q)} c + μ − Σ_i g_i² / (4(λ_i − μ)) (g = b in Q's eigenbasis) has no
gap (S-lemma) [4]; bisection on the dual's derivative returns a certified lower bound that converges to
the minimum. It is never less conservative than cmgen's: a cut-off accepted here has min ≥ 0 exactly.
cmgen also works on a 256² cube map after mirroring; the coefficients here come from the lat-long map
(:func:`validate.local_models.irradiance.sh.project_environment`), which only moves them by quadrature error.

Each map gets its own window, so ``sh9`` claims the Hölder bound of the map's own kernel
(:func:`validate.local_models.irradiance.windowed_sh.kernel_bound` of the chosen weights), not a fixed threshold.

References
  [1] google/filament, ``libs/ibl/src/CubemapSH.cpp`` (CubemapSH::sincWindow, CubemapSH::windowSH),
      ``tools/cmgen/src/cmgen.cpp`` (sphericalHarmonics; option ``--sh-window=cutoff|no|auto (default)``).
  [2] P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008 (windowing).
  [3] P.-P. Sloan, "Deringing Spherical Harmonics", SIGGRAPH Asia 2017 technical brief (shdering.pdf).
  [4] J. J. Moré, D. C. Sorensen, "Computing a trust region step", SIAM J. Sci. Stat. Comput. 4(3), 1983.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..families import irradiance as _irradiance
from . import sh

BANDS = 3
CUTOFF_START = 4 * BANDS + 1  # [1]: "start at a large band"
BISECTION_STEPS = 16  # [1]
BISECTION_WIDTH = 0.1  # [1]: stop when l + 0.1 ≥ r
DUAL_STEPS = 200  # bisection of the dual: stops earlier when the bracket no longer shrinks in float64

K0 = math.sqrt(1.0 / (4.0 * math.pi))
K1 = math.sqrt(3.0 / (4.0 * math.pi))
K2 = math.sqrt(15.0 / (4.0 * math.pi))
K20 = math.sqrt(5.0 / (16.0 * math.pi))
K22 = math.sqrt(15.0 / (16.0 * math.pi))


def sinc4_window(l: int, cutoff: float) -> float:
    """[1] CubemapSH::sincWindow: 1 at l = 0, 0 from l = cutoff on, else (sin(πl/c)/(πl/c))⁴."""
    if l == 0 or math.isinf(cutoff):  # inf: no window (cmgen's --sh-window no)
        return 1.0
    if l >= cutoff:
        return 0.0
    x = math.pi * l / cutoff
    return (math.sin(x) / x) ** 4


def window_weights(cutoff: float) -> np.ndarray:
    """(w_0, w_1, w_2) of the sinc⁴ window."""
    return np.array([sinc4_window(l, cutoff) for l in range(BANDS)])


def windowed(coeffs9: np.ndarray, cutoff: float) -> np.ndarray:
    """Coefficients (9, …) multiplied band by band by the sinc⁴ window."""
    w = window_weights(cutoff)[[sh.degree_of(k) for k in range(9)]]
    return w.reshape((9,) + (1,) * (coeffs9.ndim - 1)) * coeffs9


def quadratic_form(e9: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """f(n) = Σ_k e_k Y_k(n) (:mod:`.sh` conventions, one channel) as c + b·n + nᵀQn on the unit sphere
    (3z² − 1 = 2z² − x² − y² there): c = K0 e0, b = K1 (e3, e1, e2), Q from the five l = 2 terms."""
    e = np.asarray(e9, dtype=np.float64)
    c = K0 * e[0]
    b = K1 * np.array([e[3], e[1], e[2]])
    q = np.array([[-K20 * e[6] + K22 * e[8], 0.5 * K2 * e[4], 0.5 * K2 * e[7]],
                  [0.5 * K2 * e[4], -K20 * e[6] - K22 * e[8], 0.5 * K2 * e[5]],
                  [0.5 * K2 * e[7], 0.5 * K2 * e[5], 2.0 * K20 * e[6]]])
    return float(c), b, q


def sphere_min(e9: np.ndarray) -> float:
    """min over unit n of Σ_k e_k Y_k(n), from below: the dual of the trust-region subproblem [4] (module
    docstring) at the largest μ < λ_min found by bisection with |u(μ)| ≤ 1 — a lower bound for any μ
    (weak duality), equal to the minimum at the dual's maximum (no duality gap)."""
    c, b, q = quadratic_form(e9)
    lam, v = np.linalg.eigh(q)
    g2 = (v.T @ b) ** 2
    if not np.any(g2 > 0):
        return c + float(lam[0])
    keep = g2 > 0
    lam_k, g2_k = lam[keep], g2[keep]
    terms = list(zip(g2_k.tolist(), lam_k.tolist(), strict=True))

    def norm2(mu: float) -> float:  # |u(μ)|², u_i = −g_i / (2(λ_i − μ)); increasing on μ < λ_min
        # on Python floats: the float64 operations of g2_k / (4 (λ_k − μ)²) summed in order, as numpy sums ≤ 3 terms
        # (the same bits), without numpy's per-call cost on three numbers (this runs ~10⁶ times in worstcase)
        total = 0.0
        for g, lam_i in terms:
            d = lam_i - mu
            total += g / (4.0 * (d * d))
        return total

    lo, hi = float(lam[0]) - math.sqrt(float(g2.sum())) / 2.0, float(lam[0])  # |u(lo)| ≤ 1
    for _ in range(DUAL_STEPS):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if norm2(mid) <= 1.0:
            lo = mid
        else:
            hi = mid
    return c + lo - float(np.sum(g2_k / (4.0 * (lam_k - lo))))


@dataclass(frozen=True)
class AutoWindow:
    """cmgen's choice for one map: the cut-off, per channel the bisection's final bracket [l, r] (r may be
    the bracket's start, carried over from the previous channel, rather than a tested value), and the
    smallest cut-off any channel's bisection found negative (None when every tested cut-off passed)."""

    cutoff: float
    brackets: tuple[tuple[float, float], ...]
    rejected: float | None

    @property
    def weights(self) -> np.ndarray:
        return window_weights(self.cutoff)


def auto_window(coeffs: np.ndarray) -> AutoWindow:
    """[1] CubemapSH::windowSH with cutoff = 0 on the irradiance coefficients e = A_l L_lm of ``coeffs``
    ((≥ 9, 3) radiance SH): per channel the bisection of the module docstring; the min of the channels."""
    a = np.array([sh.clamped_cosine_al(sh.degree_of(k)) for k in range(9)])[:, None]
    e = a * np.asarray(coeffs, dtype=np.float64)[:9]
    cutoff = float(CUTOFF_START)
    brackets, rejected = [], []
    for ch in range(e.shape[1]):
        lo, hi = float(BANDS), cutoff
        for _ in range(BISECTION_STEPS):
            if not lo + BISECTION_WIDTH < hi:
                break
            mid = 0.5 * (lo + hi)
            if sphere_min(windowed(e[:, ch], mid)) < 0.0:
                hi = mid
                rejected.append(mid)
            else:
                lo = mid
        brackets.append((lo, hi))
        cutoff = min(cutoff, lo)
    return AutoWindow(cutoff, tuple(brackets), min(rejected) if rejected else None)


def render_windowed(coeffs: np.ndarray, cutoff: float, normals: np.ndarray) -> np.ndarray:
    """E′(n) = Σ_{l ≤ 2} w_l(c) A_l Σ_m L_lm Y_lm(n) at normals (N, 3) → (N, 3)."""
    return sh.render_irradiance(windowed(np.asarray(coeffs, dtype=np.float64)[:9], cutoff), normals, 2)


def render_windowed_exact(coeffs: np.ndarray, cutoff: float, normals: np.ndarray) -> np.ndarray:
    """The same in float64 numpy (for the non-negativity check; :func:`render_windowed` runs in float32)."""
    a = np.array([sh.clamped_cosine_al(sh.degree_of(k)) for k in range(9)])[:, None]
    return sh.eval_basis_numpy(normals, 2) @ windowed(a * np.asarray(coeffs, dtype=np.float64)[:9], cutoff)


@_irradiance.register("sh9_cmgen_auto", "SH9 with Filament cmgen's automatic sinc⁴ window (--sh-window auto: the "
                      "widest cut-off whose windowed irradiance is ≥ 0, per map)")
def sh9_cmgen_auto(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    coeffs = sh.project_environment(radiance, 2)
    return render_windowed(coeffs, auto_window(coeffs).cutoff, normals)
