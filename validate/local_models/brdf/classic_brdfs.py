"""The textbooks' reflection models as local techniques of the ``brdf`` family.

Contract (family ``brdf``)
  ``fn(params, normals, lights, views) -> (N, 3)``: the *cosine-weighted BRDF*
  f_r(l, v) · max(0, n·l) for unit normals n, unit directions l towards the light and v towards the
  viewer (all (N, 3), any frame, y up by the suite's convention). It is the reflected radiance per unit
  irradiance E_⊥ arriving perpendicular to a point or directional light: L_o = E_⊥ · out. It is what
  Mitsuba's ``BSDF.eval(ctx, si, wo)`` returns with ``si.wi`` = v and ``wo`` = l (eval includes the
  cosine of ``wo``). Non-negative; zero when l or v is below the horizon of n.

  ``params`` is a mapping of physical parameters; each technique reads what it needs (scalar or RGB):
  ``albedo`` ρ (diffuse), ``ks`` (specular scale), ``exponent`` (n·h lobe), ``phong_exponent`` (r·v
  lobe), ``alpha`` (microfacet roughness = Beckmann slope m or GGX α), ``distribution``
  ('beckmann' | 'ggx'), ``eta``, ``k`` (complex index of refraction η + ik of the specular interface),
  ``sigma`` (Oren–Nayar facet-slope standard deviation, radians), ``minnaert_k``.

Precision
  Per direction in drjit, in the family's float32 (:mod:`validate.local_models.precision`; the terms are
  :mod:`.common`'s ``*_dr``); the parameters are read and checked in numpy at the boundary.

The shader's light unit
  A textbook shader returns C = I · S(n, l, v) with the light's colour I. Its diffuse term
  S = k_d max(0, n·l) equals the physical L_o = (ρ/π) E_⊥ cos θ for albedo ρ = k_d when I = E_⊥/π,
  "the π folded into the light" [7]. Every textbook technique below returns S/π under that convention,
  so its Lambert term is exact and its other terms are measured as printed.

Models
  * ``lambert``: ρ/π · (n·l).
  * ``phong`` [1, 2, 3]: S = k_d (n·l) + k_s max(0, r·v)^s, r = 2(n·l)n − l, specular only where n·l > 0
    (as the Red Book examples do: no specular where the diffuse factor is 0), s = ``phong_exponent``; not
    energy normalised.
  * ``blinn_phong`` [3, 4]: S = k_d (n·l) + k_s max(0, n·h)^s, h = (l + v)/|l + v|, s = ``exponent``.
  * ``phong_normalized`` — modified Phong [5]: f_r = ρ/π + k_s (s + 2)/(2π) max(0, r·v)^s (the suite's
    ``modphong`` BSDF), s = ``phong_exponent``.
  * ``blinn_phong_normalized``: f_r = ρ/π + k_s (s + 8)/(8π) (n·h)^s [7], s = ``exponent``.
  * ``cook_torrance_printed`` — one *reading* of Ganovelli et al. §6.10.1 eq. 6.60–6.66 [1], not the printed
    text: the seed prints G2 = (n·h)(n·l)/(v·h) without the 2 of G1 (eq. 6.63) and eq. 6.60 without the
    factor n·l; the readings of the text as printed are ``brdf.ganovelli_cook_torrance``. This one:
    S = F D G / ((n·l)(n·v)) · (n·l) (colour from F; ``ks`` unused), with the Beckmann distribution as in
    Cook & Torrance [6]
    D = exp(−tan²θ_h/m²)/(m² cos⁴θ_h) (no 1/π), the V-cavity G = min{1, 2(n·h)(n·v)/(v·h),
    2(n·h)(n·l)/(v·h)} [6], Schlick's F with (1 − n·l)⁵ (the printed argument; Schlick [8] uses the
    angle to the microfacet normal, v·h), F₀ = ((η−1)² + k²)/((η+1)² + k²), and no π or 4 in the
    denominator. Under the π-folded light convention S/π = F D_norm G/((n·l)(n·v)) (n·l) with the
    normalised Beckmann D_norm = D/π: Cook & Torrance's 1982 form, 4× the microfacet BRDF of [9].
  * ``cook_torrance`` — the corrected microfacet form [9] eq. 20: f_r = F(v·h) D G₁(l) G₁(v) /
    (4 (n·l)(n·v)) + ρ/π, D normalised Beckmann or GGX (``distribution``), Smith's G₁ exact for both
    (Beckmann: G₁ = 1/(1 + Λ), Λ = (erf(a) − 1)/2 + exp(−a²)/(2a√π), a = 1/(α tan θ) [9] eq. 25–26;
    GGX: G₁ = 2/(1 + √(1 + α² tan²θ)) [9] eq. 34), F the exact unpolarised Fresnel reflectance of the
    complex index η + ik (s and p amplitudes averaged in power; conductors and dielectrics; ``ks`` unused:
    F carries the colour).
  * ``oren_nayar`` — the qualitative model [10] eq. 30 (Ganovelli eq. 6.67–6.71):
    f_r = ρ/π (A + B max(0, cos(φ_v − φ_l)) sin α tan β), A = 1 − 0.5σ²/(σ² + 0.33),
    B = 0.45σ²/(σ² + 0.09), α = max(θ_l, θ_v), β = min(θ_l, θ_v).
  * ``oren_nayar_full`` — [10] eq. 27–29: direct term ρ/π [C₁ + cos Δφ C₂ tan β + (1 − |cos Δφ|) C₃
    tan((α + β)/2)] with C₁ = A, C₂ = 0.45σ²/(σ² + 0.09) sin α (cos Δφ ≥ 0) or 0.45σ²/(σ² + 0.09)
    (sin α − (2β/π)³) (cos Δφ < 0), C₃ = 0.125σ²/(σ² + 0.09)(4αβ/π²)², plus the two-bounce
    inter-reflection term 0.17 ρ²/π σ²/(σ² + 0.13) [1 − cos Δφ (2β/π)²].
  * ``minnaert`` [11] (Ganovelli eq. 6.72): f_r = ρ/π (cos θ_l cos θ_v)^{K−1}, K = ``minnaert_k``.

References
  [1] F. Ganovelli, M. Corsini, S. Pattanaik, M. Di Benedetto, *Introduction to Computer Graphics: A
      Practical Learning Approach*, CRC 2014, ch. 6 (§6.8 Phong, §6.10.1 Cook–Torrance, §6.10.2
      Oren–Nayar, §6.10.3 Minnaert).
  [2] B. T. Phong, "Illumination for computer generated pictures", CACM 18(6), 1975.
  [3] J. Kessenich, G. Sellers, D. Shreiner, *OpenGL Programming Guide* (Red Book), 9th ed., ch. 7,
      Examples 7.3–7.8.
  [4] J. F. Blinn, "Models of light reflection for computer synthesized pictures", SIGGRAPH 1977.
  [5] E. Lafortune, Y. Willems, "Using the modified Phong reflectance model for physically based
      rendering", KU Leuven CW197, 1994.
  [6] R. L. Cook, K. E. Torrance, "A reflectance model for computer graphics", ACM TOG 1(1), 1982.
  [7] N. Hoffman, "Physically-based shading models in film and game production", SIGGRAPH 2010 course
      (π folded into the light's colour; the (s + 8)/(8π) Blinn–Phong normalisation), also
      Akenine-Möller, Haines, Hoffman, *Real-Time Rendering*, 3rd ed., §7.6.
  [8] C. Schlick, "An inexpensive BRDF model for physically-based rendering", CGF 13(3), 1994.
  [9] B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet models for refraction through rough
      surfaces", EGSR 2007.
  [10] M. Oren, S. K. Nayar, "Generalization of Lambert's reflectance model", SIGGRAPH 1994.
  [11] M. Minnaert, "The reciprocity principle in lunar photometry", ApJ 93, 1941.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..families import brdf
from .common import (
    GeometryDr,
    alpha_beta_dr,
    below_half_pi,
    cook_torrance_printed_dr,
    microfacet_specular_dr,
    opaque,
    opaque_rgb,
    oren_nayar_ab,
    oren_nayar_full_dr,
    power_dr,
    rgb_param,
    scalar_param,
)

# ---------------------------------------------------------------------------------------------
# Techniques

FLOAT32 = ("Mitsuba evaluates BSDFs in float32 (2⁻²⁴ ≈ 6·10⁻⁸ per operation, a few dozen operations): an exact "
           "formula agrees to < 10⁻⁴ relative")


@brdf.register("lambert", "Lambert: ρ/π · (n·l)", thresholds={"max_rel.diffuse_r0.8": 1e-4}, source=FLOAT32)
def lambert(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    g = GeometryDr(normals, lights, views)
    return g.finish(opaque_rgb(rgb_param(params, "albedo", "lambert") / np.pi) * g.cl)


@brdf.register("phong", "textbook Phong: [k_d (n·l) + k_s max(0, r·v)^s] / π, not normalised (Ganovelli §6.8)")
def phong(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    import drjit as dr

    g = GeometryDr(normals, lights, views)
    s = scalar_param(params, "phong_exponent", "phong", 0.0)
    spec = power_dr(dr.maximum(g.rv, 0.0), s)
    return g.finish((opaque_rgb(rgb_param(params, "albedo", "phong")) * g.cl
                     + opaque_rgb(rgb_param(params, "ks", "phong")) * spec) / np.pi)


@brdf.register("blinn_phong", "textbook Blinn–Phong: [k_d (n·l) + k_s (n·h)^s] / π, not normalised")
def blinn_phong(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:

    g = GeometryDr(normals, lights, views)
    s = scalar_param(params, "exponent", "blinn_phong", 0.0)
    spec = power_dr(g.ch, s)
    return g.finish((opaque_rgb(rgb_param(params, "albedo", "blinn_phong")) * g.cl
                     + opaque_rgb(rgb_param(params, "ks", "blinn_phong")) * spec) / np.pi)


@brdf.register("phong_normalized", "modified Phong: [ρ/π + k_s (s+2)/(2π) max(0, r·v)^s] (n·l) (Lafortune 1994)",
               thresholds={"max_rel.modphong_s20": 1e-4}, source=FLOAT32)
def phong_normalized(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                     views: np.ndarray) -> np.ndarray:
    import drjit as dr

    g = GeometryDr(normals, lights, views)
    s = scalar_param(params, "phong_exponent", "phong_normalized", 0.0)
    (norm,) = opaque((s + 2.0) / (2.0 * np.pi))
    lobe = norm * power_dr(dr.maximum(g.rv, 0.0), s)
    f = (opaque_rgb(rgb_param(params, "albedo", "phong_normalized") / np.pi)
         + opaque_rgb(rgb_param(params, "ks", "phong_normalized")) * lobe)
    return g.finish(f * g.cl)


@brdf.register("blinn_phong_normalized", "normalised Blinn–Phong: [ρ/π + k_s (s+8)/(8π) (n·h)^s] (n·l) (RTR3 §7.6)")
def blinn_phong_normalized(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                           views: np.ndarray) -> np.ndarray:

    g = GeometryDr(normals, lights, views)
    s = scalar_param(params, "exponent", "blinn_phong_normalized", 0.0)
    (norm,) = opaque((s + 8.0) / (8.0 * np.pi))
    lobe = norm * power_dr(g.ch, s)
    f = (opaque_rgb(rgb_param(params, "albedo", "blinn_phong_normalized") / np.pi)
         + opaque_rgb(rgb_param(params, "ks", "blinn_phong_normalized")) * lobe)
    return g.finish(f * g.cl)


@brdf.register("cook_torrance_printed", "Cook–Torrance after Ganovelli eq. 6.60–6.66, read with an n·l factor and "
               "the 2 in both G terms (neither printed): F_Schlick(n·l) D G_Vcavity / ((n·l)(n·v)), no π or 4")
def cook_torrance_printed(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                          views: np.ndarray) -> np.ndarray:
    g = GeometryDr(normals, lights, views)
    diffuse = opaque_rgb(rgb_param(params, "albedo", "cook_torrance_printed") / np.pi) * g.cl
    return g.finish(diffuse + cook_torrance_printed_dr(params, g))


@brdf.register("cook_torrance", "microfacet BRDF (Walter 2007 eq. 20): F(v·h) D G1(l)G1(v) / (4(n·l)(n·v)), exact "
               "Smith G and Fresnel, Beckmann or GGX D",
               thresholds={"max_rel.conductor_beckmann_a0.2": 0.0071, "max_rel.conductor_beckmann_a0.5": 0.0071,
                           "max_rel.conductor_ggx_a0.3": 1e-4},
               source=("Walter et al. 2007 eq. 27: Mitsuba's Beckmann G₁ is a rational approximation within 0.35 % of "
                       "the exact Smith G₁, applied for l and v (≤ 0.70 %, + float32 → 0.71 %); GGX's G₁ is exact "
                       "([9] eq. 34): " + FLOAT32))
def cook_torrance(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                  views: np.ndarray) -> np.ndarray:
    g = GeometryDr(normals, lights, views)
    diffuse = opaque_rgb(rgb_param(params, "albedo", "cook_torrance") / np.pi) * g.cl
    return g.finish(diffuse + microfacet_specular_dr(params, g))


@brdf.register("oren_nayar", "Oren–Nayar qualitative model: ρ/π (A + B max(0, cos Δφ) sin α tan β) (eq. 30)")
def oren_nayar(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    import drjit as dr

    g = GeometryDr(normals, lights, views)
    a, b = opaque(*oren_nayar_ab(scalar_param(params, "sigma", "oren_nayar", 0.0)))
    al, be = alpha_beta_dr(g)
    shape = a + b * dr.maximum(g.cos_dphi, 0.0) * dr.sin(al) * dr.tan(dr.minimum(be, below_half_pi()))
    return g.finish(opaque_rgb(rgb_param(params, "albedo", "oren_nayar") / np.pi) * (shape * g.cl))


@brdf.register("oren_nayar_full",
               "Oren–Nayar full model: C1, C2, C3 direct terms + 0.17ρ² inter-reflection (eq. 27–29)")
def oren_nayar_full(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                    views: np.ndarray) -> np.ndarray:
    g = GeometryDr(normals, lights, views)
    l1, l2 = oren_nayar_full_dr(scalar_param(params, "sigma", "oren_nayar_full", 0.0),
                                   rgb_param(params, "albedo", "oren_nayar_full"), g)
    return g.finish(l1 + l2)


@brdf.register("minnaert", "Minnaert: ρ/π (cos θ_l cos θ_v)^(K−1) (n·l)")
def minnaert(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    import drjit as dr

    g = GeometryDr(normals, lights, views)
    kk = scalar_param(params, "minnaert_k", "minnaert", 0.0)
    shape = power_dr(dr.maximum(g.cl * g.cv, 1e-30), kk - 1.0)
    return g.finish(opaque_rgb(rgb_param(params, "albedo", "minnaert") / np.pi) * (shape * g.cl))


