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
    factor n·l; the readings of the text as printed are ``listings.ganovelli_cook_torrance``. This one:
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
from scipy.special import erf

from ..errors import ValidateError
from .registry import define_family

brdf = define_family(
    "brdf",
    "fn(params: mapping of physical parameters (albedo, ks, exponent, phong_exponent, alpha, distribution, eta, k, "
    "sigma, minnaert_k), normals: (N, 3) unit, lights: (N, 3) unit towards the light, views: (N, 3) unit towards "
    "the viewer) -> (N, 3) cosine-weighted BRDF f_r(l, v)·max(0, n·l) (= Mitsuba's BSDF.eval with wi = v, wo = l)",
    lambda params, normals, lights, views, **_: (len(normals), 3),
    lower=0.0,
    bounds_reason="a BRDF times a clamped cosine is non-negative",
)

DEFAULTS: dict[str, Any] = {"albedo": 0.0, "ks": 0.0, "exponent": 10.0, "phong_exponent": 10.0, "alpha": 0.3,
                            "distribution": "beckmann", "eta": 0.0, "k": 1.0, "sigma": 0.0, "minnaert_k": 1.0}


def param(params: Mapping[str, Any], key: str, who: str) -> np.ndarray:
    """``params[key]`` (or its default) as a float array broadcastable to (N, 3): scalar or RGB."""
    value = params.get(key, DEFAULTS[key])
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim > 1 or (arr.ndim == 1 and arr.shape[0] != 3) or not np.all(np.isfinite(arr)):
        raise ValidateError(f"technique '{who}' (brdf): parameter {key}={value!r} must be a finite scalar or RGB")
    return arr if arr.ndim == 1 else arr.reshape(())


def _unit(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.float64)
    return x / np.maximum(np.linalg.norm(x, axis=-1, keepdims=True), 1e-300)


class Geometry:
    """Per-sample dot products of (n, l, v): cosines, half vector, mirror direction, azimuth difference."""

    def __init__(self, normals: np.ndarray, lights: np.ndarray, views: np.ndarray):
        self.n, self.l, self.v = _unit(normals), _unit(lights), _unit(views)
        self.cl = np.sum(self.n * self.l, axis=-1)
        self.cv = np.sum(self.n * self.v, axis=-1)
        self.h = _unit(self.l + self.v)
        self.ch = np.clip(np.sum(self.n * self.h, axis=-1), 0.0, 1.0)
        self.vh = np.clip(np.sum(self.v * self.h, axis=-1), 0.0, 1.0)
        r = 2.0 * self.cl[:, None] * self.n - self.l
        self.rv = np.sum(r * self.v, axis=-1)
        self.front = (self.cl > 0.0) & (self.cv > 0.0)
        lt = self.l - self.cl[:, None] * self.n
        vt = self.v - self.cv[:, None] * self.n
        norm = np.linalg.norm(lt, axis=-1) * np.linalg.norm(vt, axis=-1)
        self.cos_dphi = np.where(norm > 1e-12, np.sum(lt * vt, axis=-1) / np.maximum(norm, 1e-300), 0.0)
        self.theta_l = np.arccos(np.clip(self.cl, -1.0, 1.0))
        self.theta_v = np.arccos(np.clip(self.cv, -1.0, 1.0))

    def finish(self, f_cos: np.ndarray) -> np.ndarray:
        """(N, 3), zero where l or v is below the horizon."""
        out = np.broadcast_to(np.asarray(f_cos, dtype=np.float64).reshape(len(self.cl), -1), (len(self.cl), 3))
        return np.where(self.front[:, None], np.maximum(out, 0.0), 0.0)


def _col(x: np.ndarray) -> np.ndarray:
    return np.asarray(x, dtype=np.float64)[:, None]


# ---------------------------------------------------------------------------------------------
# Terms (public: the experiment's term-by-term analysis calls them directly)

def fresnel_exact(cos_theta: np.ndarray, eta: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Unpolarised Fresnel reflectance of the complex index η + ik at incidence cos θ (conductor or dielectric):
    r_s = (c − ñ c_t)/(c + ñ c_t), r_p = (ñ c − c_t)/(ñ c + c_t), c_t = √(1 − (1 − c²)/ñ²), F = (|r_s|² + |r_p|²)/2."""
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0)[:, None]
    n = (np.asarray(eta, dtype=np.float64) + 1j * np.asarray(k, dtype=np.float64)) * np.ones((1, 3))
    n = np.where(np.abs(n) < 1e-12, 1e-12 + 0j, n)
    ct = np.sqrt(1.0 - (1.0 - c * c) / (n * n) + 0j)
    rs = (c - n * ct) / (c + n * ct)
    rp = (n * c - ct) / (n * c + ct)
    return 0.5 * (np.abs(rs) ** 2 + np.abs(rp) ** 2)


def fresnel_f0(eta: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Normal-incidence reflectance F₀ = ((η − 1)² + k²)/((η + 1)² + k²) (RGB, (3,))."""
    eta, k = np.asarray(eta, dtype=np.float64) * np.ones(3), np.asarray(k, dtype=np.float64) * np.ones(3)
    return ((eta - 1.0) ** 2 + k * k) / ((eta + 1.0) ** 2 + k * k)


def fresnel_schlick(cos_theta: np.ndarray, f0: np.ndarray) -> np.ndarray:
    """Schlick [8]: F = F₀ + (1 − F₀)(1 − cos θ)⁵, (N, 3)."""
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0)[:, None]
    return f0 + (1.0 - f0) * (1.0 - c) ** 5


def beckmann_d(cos_h: np.ndarray, m: float, normalised: bool = True) -> np.ndarray:
    """Beckmann D = exp(−tan²θ_h/m²)/(π m² cos⁴θ_h) ([9] eq. 25); without the π as printed in [6]."""
    c2 = np.maximum(np.asarray(cos_h, dtype=np.float64) ** 2, 1e-12)
    d = np.exp(-(1.0 - c2) / (c2 * m * m)) / (m * m * c2 * c2)
    return np.where(cos_h > 1e-6, d / np.pi if normalised else d, 0.0)


def ggx_d(cos_h: np.ndarray, alpha: float) -> np.ndarray:
    """GGX D = α²/(π cos⁴θ_h (α² + tan²θ_h)²) ([9] eq. 33)."""
    c2 = np.asarray(cos_h, dtype=np.float64) ** 2
    a2 = alpha * alpha
    return np.where(cos_h > 0.0, a2 / (np.pi * (c2 * (a2 - 1.0) + 1.0) ** 2), 0.0)


def smith_g1(cos_theta: np.ndarray, alpha: float, distribution: str) -> np.ndarray:
    """Smith's monodirectional masking G₁ for Beckmann ([9] eq. 25–26, exact, with erf) or GGX ([9] eq. 34)."""
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 1e-12, 1.0)
    tan = np.sqrt(np.maximum(1.0 - c * c, 0.0)) / c
    if distribution == "ggx":
        return 2.0 / (1.0 + np.sqrt(1.0 + alpha * alpha * tan * tan))
    a = np.minimum(1.0 / np.maximum(alpha * tan, 1e-300), 1e8)  # Λ(a) < 1e-300 beyond a ≈ 26: no masking
    lam = np.where(a < 30.0, 0.5 * (erf(a) - 1.0) + np.exp(-np.minimum(a * a, 700.0)) / (2.0 * a * np.sqrt(np.pi)),
                   0.0)
    return 1.0 / (1.0 + lam)


def vcavity_g(g: Geometry) -> np.ndarray:
    """Cook–Torrance's V-cavity G = min{1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h)} [6]."""
    vh = np.maximum(g.vh, 1e-12)
    return np.minimum(1.0, np.minimum(2.0 * g.ch * g.cv / vh, 2.0 * g.ch * g.cl / vh))


def oren_nayar_ab(sigma: float) -> tuple[float, float]:
    """A = 1 − 0.5σ²/(σ² + 0.33), B = 0.45σ²/(σ² + 0.09) [10] eq. 30."""
    s2 = sigma * sigma
    return 1.0 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)


def _scalar(params: Mapping[str, Any], key: str, who: str, low: float = -np.inf) -> float:
    arr = param(params, key, who)
    if arr.ndim != 0 or not float(arr) >= low:
        raise ValidateError(f"technique '{who}' (brdf): parameter {key}={arr.tolist()!r} must be a scalar ≥ {low:g}")
    return float(arr)


def _distribution(params: Mapping[str, Any], who: str) -> str:
    d = str(params.get("distribution", DEFAULTS["distribution"])).lower()
    if d not in ("beckmann", "ggx"):
        raise ValidateError(f"technique '{who}' (brdf): distribution={d!r}; expected 'beckmann' or 'ggx'")
    return d


# ---------------------------------------------------------------------------------------------
# Techniques

FLOAT32 = ("Mitsuba evaluates BSDFs in float32 (2⁻²⁴ ≈ 6·10⁻⁸ per operation, a few dozen operations): an exact "
           "formula agrees to < 10⁻⁴ relative")


@brdf.register("lambert", "Lambert: ρ/π · (n·l)", thresholds={"max_rel.diffuse_r0.8": 1e-4}, source=FLOAT32)
def lambert(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    return g.finish(param(params, "albedo", "lambert") / np.pi * _col(g.cl))


@brdf.register("phong", "textbook Phong: [k_d (n·l) + k_s max(0, r·v)^s] / π, not normalised (Ganovelli §6.8)")
def phong(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    s = _scalar(params, "phong_exponent", "phong", 0.0)
    spec = np.power(np.maximum(g.rv, 0.0), s)
    return g.finish((param(params, "albedo", "phong") * _col(g.cl) + param(params, "ks", "phong") * _col(spec)) / np.pi)


@brdf.register("blinn_phong", "textbook Blinn–Phong: [k_d (n·l) + k_s (n·h)^s] / π, not normalised")
def blinn_phong(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    s = _scalar(params, "exponent", "blinn_phong", 0.0)
    spec = np.power(g.ch, s)
    return g.finish((param(params, "albedo", "blinn_phong") * _col(g.cl)
                     + param(params, "ks", "blinn_phong") * _col(spec)) / np.pi)


@brdf.register("phong_normalized", "modified Phong: [ρ/π + k_s (s+2)/(2π) max(0, r·v)^s] (n·l) (Lafortune 1994)",
               thresholds={"max_rel.modphong_s20": 1e-4}, source=FLOAT32)
def phong_normalized(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                     views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    s = _scalar(params, "phong_exponent", "phong_normalized", 0.0)
    lobe = (s + 2.0) / (2.0 * np.pi) * np.power(np.maximum(g.rv, 0.0), s)
    f = param(params, "albedo", "phong_normalized") / np.pi + param(params, "ks", "phong_normalized") * _col(lobe)
    return g.finish(f * _col(g.cl))


@brdf.register("blinn_phong_normalized", "normalised Blinn–Phong: [ρ/π + k_s (s+8)/(8π) (n·h)^s] (n·l) (RTR3 §7.6)")
def blinn_phong_normalized(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                           views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    s = _scalar(params, "exponent", "blinn_phong_normalized", 0.0)
    lobe = (s + 8.0) / (8.0 * np.pi) * np.power(g.ch, s)
    f = (param(params, "albedo", "blinn_phong_normalized") / np.pi
         + param(params, "ks", "blinn_phong_normalized") * _col(lobe))
    return g.finish(f * _col(g.cl))


def cook_torrance_printed_terms(params: Mapping[str, Any], g: Geometry, fresnel: str = "schlick_nl",
                                geometry: str = "vcavity", denominator: str = "printed",
                                normalised_d: bool = False) -> np.ndarray:
    """The specular part of Ganovelli's Cook–Torrance with each term switchable (term-by-term analysis):
    ``fresnel`` 'schlick_nl' (printed) | 'schlick_vh' | 'exact'; ``geometry`` 'vcavity' | 'smith';
    ``denominator`` 'printed' ((n·l)(n·v)) | 'walter' (4(n·l)(n·v)); ``normalised_d`` adds the 1/π.
    Returns S/π (π-folded light) ≙ f_r·(n·l), (N, 3)."""
    who = "cook_torrance_printed"
    m = _scalar(params, "alpha", who, 1e-4)
    eta, k = param(params, "eta", who), param(params, "k", who)
    f0 = fresnel_f0(eta, k)
    if fresnel == "schlick_nl":
        f = fresnel_schlick(g.cl, f0)
    elif fresnel == "schlick_vh":
        f = fresnel_schlick(g.vh, f0)
    else:
        f = fresnel_exact(g.vh, eta, k)
    d = beckmann_d(g.ch, m, normalised=normalised_d)
    gg = vcavity_g(g) if geometry == "vcavity" else smith_g1(g.cl, m, "beckmann") * smith_g1(g.cv, m, "beckmann")
    denom = np.maximum(g.cl * g.cv, 1e-12) * (4.0 if denominator == "walter" else 1.0)
    spec = f * _col(d * gg / denom * g.cl)
    return spec / np.pi


@brdf.register("cook_torrance_printed", "Cook–Torrance after Ganovelli eq. 6.60–6.66, read with an n·l factor and "
               "the 2 in both G terms (neither printed): F_Schlick(n·l) D G_Vcavity / ((n·l)(n·v)), no π or 4")
def cook_torrance_printed(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                          views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    diffuse = param(params, "albedo", "cook_torrance_printed") / np.pi * _col(g.cl)
    return g.finish(diffuse + cook_torrance_printed_terms(params, g))


def microfacet_specular(params: Mapping[str, Any], g: Geometry, who: str = "cook_torrance") -> np.ndarray:
    """F(v·h) D G₁(l) G₁(v) / (4 (n·l)(n·v)) · (n·l) [9] eq. 20, (N, 3)."""
    a = _scalar(params, "alpha", who, 1e-4)
    dist = _distribution(params, who)
    d = beckmann_d(g.ch, a) if dist == "beckmann" else ggx_d(g.ch, a)
    gg = smith_g1(g.cl, a, dist) * smith_g1(g.cv, a, dist)
    f = fresnel_exact(g.vh, param(params, "eta", who), param(params, "k", who))
    return f * _col(d * gg / (4.0 * np.maximum(g.cv, 1e-12)))


@brdf.register("cook_torrance", "microfacet BRDF (Walter 2007 eq. 20): F(v·h) D G1(l)G1(v) / (4(n·l)(n·v)), exact "
               "Smith G and Fresnel, Beckmann or GGX D",
               thresholds={"max_rel.conductor_beckmann_a0.2": 0.0071, "max_rel.conductor_beckmann_a0.5": 0.0071,
                           "max_rel.conductor_ggx_a0.3": 1e-4},
               source=("Walter et al. 2007 eq. 27: Mitsuba's Beckmann G₁ is a rational approximation within 0.35 % of "
                       "the exact Smith G₁, applied for l and v (≤ 0.70 %, + float32 → 0.71 %); GGX's G₁ is exact "
                       "([9] eq. 34): " + FLOAT32))
def cook_torrance(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                  views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    diffuse = param(params, "albedo", "cook_torrance") / np.pi * _col(g.cl)
    return g.finish(diffuse + microfacet_specular(params, g))


def _alpha_beta(g: Geometry) -> tuple[np.ndarray, np.ndarray]:
    return np.maximum(g.theta_l, g.theta_v), np.minimum(g.theta_l, g.theta_v)


@brdf.register("oren_nayar", "Oren–Nayar qualitative model: ρ/π (A + B max(0, cos Δφ) sin α tan β) (eq. 30)")
def oren_nayar(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    a, b = oren_nayar_ab(_scalar(params, "sigma", "oren_nayar", 0.0))
    al, be = _alpha_beta(g)
    shape = a + b * np.maximum(g.cos_dphi, 0.0) * np.sin(al) * np.tan(np.minimum(be, np.pi / 2 - 1e-9))
    return g.finish(param(params, "albedo", "oren_nayar") / np.pi * _col(shape * g.cl))


def oren_nayar_full_terms(sigma: float, albedo: np.ndarray, g: Geometry) -> tuple[np.ndarray, np.ndarray]:
    """(direct L₁, inter-reflection L₂) of the full model [10] eq. 27–29, each as f_r·(n·l), (N, 3)."""
    s2 = sigma * sigma
    al, be = _alpha_beta(g)
    be = np.minimum(be, np.pi / 2 - 1e-9)
    cd = g.cos_dphi
    c1 = 1.0 - 0.5 * s2 / (s2 + 0.33)
    c2 = np.where(cd >= 0.0, 0.45 * s2 / (s2 + 0.09) * np.sin(al),
                  0.45 * s2 / (s2 + 0.09) * (np.sin(al) - (2.0 * be / np.pi) ** 3))
    c3 = 0.125 * s2 / (s2 + 0.09) * (4.0 * al * be / np.pi ** 2) ** 2
    direct = c1 + cd * c2 * np.tan(be) + (1.0 - np.abs(cd)) * c3 * np.tan(0.5 * (al + be))
    inter = 0.17 * s2 / (s2 + 0.13) * (1.0 - cd * (2.0 * be / np.pi) ** 2)
    return (albedo / np.pi * _col(direct * g.cl), albedo * albedo / np.pi * _col(inter * g.cl))


@brdf.register("oren_nayar_full",
               "Oren–Nayar full model: C1, C2, C3 direct terms + 0.17ρ² inter-reflection (eq. 27–29)")
def oren_nayar_full(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                    views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    l1, l2 = oren_nayar_full_terms(_scalar(params, "sigma", "oren_nayar_full", 0.0),
                                   param(params, "albedo", "oren_nayar_full"), g)
    return g.finish(l1 + l2)


@brdf.register("minnaert", "Minnaert: ρ/π (cos θ_l cos θ_v)^(K−1) (n·l)")
def minnaert(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    g = Geometry(normals, lights, views)
    kk = _scalar(params, "minnaert_k", "minnaert", 0.0)
    shape = np.power(np.maximum(g.cl * g.cv, 1e-300), kk - 1.0)
    return g.finish(param(params, "albedo", "minnaert") / np.pi * _col(shape * g.cl))


__all__ = ["brdf", "DEFAULTS", "Geometry", "param", "fresnel_exact", "fresnel_f0", "fresnel_schlick", "beckmann_d",
           "ggx_d", "smith_g1", "vcavity_g", "oren_nayar_ab", "oren_nayar_full_terms", "cook_torrance_printed_terms",
           "microfacet_specular"]
