"""Closed forms that judge the ``sh9`` experiment's reference quadrature (numbers only).

Each built-in with an exact irradiance gets one, computed *independently of the model under test*
(nothing here calls :mod:`validate.local_models.irradiance.sh`):

* ``constant``  L: E(n) = πL (∫ max(0, n·ω) dω = π over the sphere).
* ``two_tone``  sky L_s above the horizon, ground L_g below: E = π(L_s(1 + cos β)/2 + L_g(1 − cos β)/2),
  β = angle(n, +y) (view factors of the two hemispheres of a tilted plane).
* ``bandlimited`` L = Σ_{l≤2} L_lm Y_lm with the analytic coefficients the environment is built from
  (:data:`validate.scenes.procedural.BANDLIMITED_SH`, basis :func:`~validate.scenes.procedural.sh9_basis`):
  by the Funk–Hecke theorem E = Σ_l A_l Σ_m L_lm Y_lm(n) with the clamped-cosine coefficients
  (Ramamoorthi & Hanrahan, JOSA A 18(10) 2001, eq. 19)

      A_0 = π,  A_1 = 2π/3,  A_l = 0 for odd l > 1,
      A_l = 2π (−1)^{l/2 − 1} / ((l + 2)(l − 1)) · l! / (2^l ((l/2)!)²)  for even l ≥ 2   (A_2 = π/4),

  written out here from the formula, not taken from the model's table.
* ``near_directional`` a uniform cap of half-angle α (radiance 1) at direction d: the cap irradiance
  of Snyder 1996 / Lagarde & de Rousiers 2014 §4.7.2 (:func:`validate.local_models.arealight.sphere_cap.cap_irradiance`,
  itself checked against brute-force quadrature to 4·10⁻¹⁴ of π sin²α), E = π sin²α cos β where the
  cap is wholly above the horizon. Its error is normalised by the peak π sin²α (E = 0 on half the sphere).

The built-ins are recognised by name *and* ``kind == "procedural"`` (a probe file called
``constant.exr`` is not one of them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...local_models.arealight.sphere_cap import cap_irradiance
from ...scenes import procedural
from ...scenes.environment import Environment


@dataclass(frozen=True)
class ClosedForm:
    """Exact E (N, 3) at the normals, the per-normal normalisation of the error, and what it is."""

    exact: np.ndarray
    norm: np.ndarray  # (N, 3) or broadcastable: error = |E − exact| / norm
    metric: str
    formula: str


def clamped_cosine_coefficient(l: int) -> float:
    """A_l of max(cos θ, 0) (R&H JOSA 2001 eq. 19), from the general formula.

    Written here on purpose rather than imported from :mod:`validate.local_models.irradiance.sh`: these closed
    forms judge the reference, and ground truth never reuses the approximation's own code."""
    if l == 0:
        return math.pi
    if l == 1:
        return 2.0 * math.pi / 3.0
    if l % 2:
        return 0.0
    h = l // 2
    return (2.0 * math.pi * (-1) ** (h - 1) / ((l + 2) * (l - 1))
            * math.factorial(l) / (2**l * math.factorial(h) ** 2))


def bandlimited_irradiance(normals: np.ndarray, coeffs: np.ndarray = procedural.BANDLIMITED_SH) -> np.ndarray:
    """E(n) = Σ_l A_l Σ_m L_lm Y_lm(n) for order-2 coefficients (9, 3) in R&H's order."""
    degree = np.array([0, 1, 1, 1, 2, 2, 2, 2, 2])
    a = np.array([clamped_cosine_coefficient(int(l)) for l in degree])
    return (procedural.sh9_basis(normals) * a) @ coeffs


def cap_direction() -> np.ndarray:
    return procedural.direction_from_elevation(procedural.NEAR_DIRECTIONAL_ELEVATION_DEG,
                                               procedural.NEAR_DIRECTIONAL_AZIMUTH_DEG)


def closed_form(env: Environment, normals: np.ndarray) -> ClosedForm | None:
    """The exact irradiance of a built-in that has one (module docstring), else None."""
    if env.kind != "procedural":
        return None
    if env.name == "constant":
        exact = np.pi * np.broadcast_to(procedural.CONSTANT, normals.shape)
        return ClosedForm(exact, exact, "max |E − E_exact| / E_exact", "E = πL")
    if env.name == "two_tone":
        c = normals[:, 1:2]
        exact = np.pi * (procedural.SKY * (1 + c) / 2 + procedural.GROUND * (1 - c) / 2)
        return ClosedForm(exact, exact, "max |E − E_exact| / E_exact", "E = π(L_s(1 + cos β) + L_g(1 − cos β))/2")
    if env.name == "bandlimited":
        exact = bandlimited_irradiance(normals)
        return ClosedForm(exact, exact, "max |E − E_exact| / E_exact",
                          "E = Σ A_l L_lm Y_lm, analytic coefficients, A_l from R&H JOSA 2001 eq. 19")
    if env.name == "near_directional":
        s2 = math.sin(math.radians(procedural.NEAR_DIRECTIONAL_HALF_ANGLE_DEG)) ** 2
        e = cap_irradiance(normals @ cap_direction(), s2)
        exact = np.repeat(e[:, None], 3, axis=1)
        return ClosedForm(exact, np.full_like(exact, np.pi * s2), "max |E − E_cap| / (π sin²α)",
                          "uniform cap (Snyder 1996; Lagarde & de Rousiers 2014 §4.7.2)")
    return None
