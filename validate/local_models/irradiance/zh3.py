"""ZH3: linear SH plus one quadratic zonal harmonic along the linear SH's axis [1].

Radiance model (real SH without the Condon–Shortley phase, :mod:`.sh` conventions):

    L(ω) ≈ L00 Y00 + Σ_m L1m Y1m(ω) + z2 Y20(a·ω),   Y20(t) = √(5/16π) (3t² − 1),

with a = the unit vector of the *luminance* L1 coefficients (L11, L1m1, L10) ↔ (x, y, z) — one axis
shared by the three channels, the variant [1] recommends for shaders (a zero L1 vector falls back to
a = +y and z2 = 0). By the Funk–Hecke theorem (R&H 2001 [2], eq. 8; A_l of R&H JOSA 2001 [3] eq. 19)
the irradiance is

    E(n) = A0 L00 Y00 + A1 Σ_m L1m Y1m(n) + A2 z2 Y20(a·n),   A0 = π, A1 = 2π/3, A2 = π/4.

Two ways to get z2 (both registered):

* ``zh3_stored`` — the projection of the radiance on the zonal harmonic about a (one extra number per
  channel): z2 = ∫ L(ω) Y20(a·ω) dω = √(4π/5) Σ_m Y2m(a) L2m (addition theorem), from the order-2
  coefficients.
* ``zh3_hallucinated`` — from L1 alone, [1] §3.4.3's curve fit: with r = |L1·a| / L00 (per channel),
  z2 = L00 (0.08 r + 0.6 r²). For a directional light (r = √3) this gives 0.547 Y00-units against the
  exact Y20(1) = 0.631: the fit targets measured probes, not the extreme.

Both parts are irradiance E (not E/π): the zonal term carries A2 = π/4, the linear part A0, A1.

Declared threshold of ``zh3_hallucinated`` (judged on ``near_directional``): it depends on L only through
L00 and L1, so for grey lighting of flux Φ and mean direction vector ρ m̂ (L00 = Y00 Φ, L1 = √(3/4π) Φ ρ m̂,
r = √3 ρ) its output is Φ k_ρ(n·m̂) with the closed-form kernel (:func:`hallucinated_kernel`)

    k_ρ(x) = ¼ + ρx/2 + A2 √(5/16π) Y00 (0.08 r + 0.6 r²) (3x² − 1),   r = √3 ρ,

for a directional light (ρ = 1) k = ¼ + x/2 + 0.13546 (3x² − 1): error |k − max(x, 0)| ≤ 0.1145 at the
horizon (SH9: 3/32 = 0.094 there; plain L1: ¼). Widened for the disc and its texels as in
:func:`.kernel_bounds.near_directional_bound` (Jensen below, the cone above), plus the reference's closed-form
tolerance (:data:`.windowed_sh.CLOSED_FORM_TOLERANCE`).

References
  [1] T. Roughton, P.-P. Sloan, A. Silvennoinen, M. Iwanicki, P. Shirley, "ZH3: Quadratic Zonal
      Harmonics", Proc. ACM Comput. Graph. Interact. Tech. (i3D) 2024.
  [2] R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
      SIGGRAPH 2001.
  [3] R. Ramamoorthi, P. Hanrahan, "On the relationship between radiance and irradiance", JOSA A 18(10), 2001.
"""

from __future__ import annotations

import math

import numpy as np

from ...scenes.latlong import CLOSED_FORM_TOLERANCE
from ...scenes.procedural import near_directional_half_angle
from ..families import irradiance as _irradiance
from ..precision import rgb_to_np, vec_to_dr
from . import sh
from .kernel_bounds import near_directional_bound

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
Y20_NORM = math.sqrt(5.0 / (16.0 * math.pi))
A2 = math.pi / 4.0
HALLUCINATE_LINEAR, HALLUCINATE_QUADRATIC = 0.08, 0.6  # [1] §3.4.3 curve fit


def zonal_axis(coeffs: np.ndarray) -> np.ndarray:
    """Unit axis of the luminance L1 vector (L11, L1m1, L10) → (x, y, z); +y when it vanishes."""
    v = np.array([coeffs[3] @ LUMINANCE, coeffs[1] @ LUMINANCE, coeffs[2] @ LUMINANCE])
    n = float(np.linalg.norm(v))
    return v / n if n > 1e-12 * max(abs(float(coeffs[0] @ LUMINANCE)), 1e-30) else np.array([0.0, 1.0, 0.0])


def stored_z2(coeffs: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """z2 = √(4π/5) Σ_m Y2m(a) L2m per channel (3,), from order-2 coefficients (9, 3)."""
    y2 = sh.eval_basis_numpy(axis[None, :], 2)[0, 4:9]
    return math.sqrt(4.0 * math.pi / 5.0) * (y2 @ coeffs[4:9])


def hallucinated_z2(coeffs: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """[1] §3.4.3: r = |L1·a| / L00, z2 = L00 (0.08 r + 0.6 r²) per channel (0 where L00 ≤ 0)."""
    l00 = coeffs[0]
    l1 = np.stack([coeffs[3], coeffs[1], coeffs[2]], axis=0)  # (3 xyz, 3 channels)
    r = np.abs(axis @ l1) / np.where(l00 > 0, l00, 1.0)
    return np.where(l00 > 0, l00 * (HALLUCINATE_LINEAR * r + HALLUCINATE_QUADRATIC * r * r), 0.0)


def render_zh3(coeffs: np.ndarray, axis: np.ndarray, z2: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """E(n) = A0 L00 Y00 + A1 L1·Y1(n) + A2 z2 Y20(a·n) at normals (N, 3) → (N, 3); per normal in drjit, in the
    active dtype (:mod:`..precision`: the irradiance family's float32)."""
    x, y, z = vec_to_dr(normals)
    basis = sh.eval_basis(x, y, z, 1)
    t = x * float(axis[0]) + y * float(axis[1]) + z * float(axis[2])
    zonal = (3.0 * t * t - 1.0) * (A2 * Y20_NORM)
    out = []
    for c in range(3):
        e = zonal * float(z2[c])
        for k in range(4):
            e = e + basis[k] * float(sh.clamped_cosine_al(sh.degree_of(k)) * coeffs[k, c])
        out.append(e)
    return rgb_to_np(*out, len(normals))


# Declared threshold: lighting zonal about its own L1 axis (a directional light, a small disc) has only the
# zonal L2 coefficient about that axis, so stored ZH3 = SH9 there and R&H's bound max|E′ − E| ≤ 3/32 Φ
# applies; judged on near_directional only (on other lighting ZH3 has no such bound: measured 3.5 % mean on
# sunsky_5deg, above SH9's 3.07 %).
@_irradiance.register("zh3_stored", "ZH3: L1 SH + stored zonal L2 along the luminance L1 axis (Roughton et al. 2024)",
                      thresholds={"flux_rgb.max": 3.0 / 32.0}, environments=("near_directional",),
                      source="stored ZH3 keeps the zonal L2 part along the L1 axis (Roughton et al. 2024), which is "
                             "the whole L2 band for lighting zonal about that axis, so ZH3 = SH9 there; R&H JOSA 2001: "
                             "|K̃(x) − max(x, 0)| ≤ 3/32")
def zh3_stored(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    coeffs = sh.project_environment(radiance, 2)
    axis = zonal_axis(coeffs)
    return render_zh3(coeffs, axis, stored_z2(coeffs, axis), normals)


def hallucinated_kernel(rho: float, x: np.ndarray) -> np.ndarray:
    """Per unit flux, from [1] §3.4.3's formulas (not from :func:`zh3_hallucinated`): linear part
    A0 Y00² + A1 (3/4π) ρ x = ¼ + ρx/2; zonal part A2 √(5/16π) (3x² − 1) z2 with z2 = Y00 (0.08 r + 0.6 r²),
    r = √3 ρ (|L1·a| / L00 for L1 = √(3/4π) ρ a)."""
    x = np.asarray(x, dtype=np.float64)
    y00 = math.sqrt(1.0 / (4.0 * math.pi))
    r = math.sqrt(3.0) * rho
    z2 = y00 * (HALLUCINATE_LINEAR * r + HALLUCINATE_QUADRATIC * r * r)
    return 0.25 + 0.5 * rho * x + A2 * Y20_NORM * (3.0 * x * x - 1.0) * z2


HALLUCINATED_BOUND = near_directional_bound(hallucinated_kernel, near_directional_half_angle())


@_irradiance.register("zh3_hallucinated", "ZH3 hallucinated from L1 (Roughton et al. 2024 §3.4.3 curve fit)",
                      thresholds={"flux_rgb.max": HALLUCINATED_BOUND + CLOSED_FORM_TOLERANCE},
                      environments=("near_directional",),
                      source="closed form on a directional light (Roughton et al. 2024 §3.4.3: z2 = L00 (0.08 r "
                             "+ 0.6 r²), r = √3: kernel ¼ + x/2 + 0.1355 (3x² − 1), error ≤ 0.1145 Φ at the "
                             "horizon), widened for near_directional's 0.5° disc + one texel by Jensen's "
                             "inequality and the cone (validate.local_models.irradiance.kernel_bounds."
                             "near_directional_bound: "
                             f"{HALLUCINATED_BOUND:.5f}) + 0.1 % Φ, the reference's closed-form tolerance")
def zh3_hallucinated(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    coeffs = sh.project_environment(radiance, 1)
    axis = zonal_axis(coeffs)
    return render_zh3(coeffs, axis, hallucinated_z2(coeffs, axis), normals)
