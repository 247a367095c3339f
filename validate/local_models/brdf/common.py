"""The brdf family's shared terms: the shading geometry, Fresnel, microfacet distributions and masking, and the
Oren–Nayar and Cook–Torrance terms that several techniques (and the specular area-light family) evaluate.
References are numbered as in :mod:`validate.local_models.brdf.classic_brdfs`; nothing here registers a technique."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from scipy.special import erf

from ...errors import ValidateError
from ...geometry import unit

DEFAULTS: dict[str, Any] = {"albedo": 0.0, "ks": 0.0, "exponent": 10.0, "phong_exponent": 10.0, "alpha": 0.3,
                            "distribution": "beckmann", "eta": 0.0, "k": 1.0, "sigma": 0.0, "minnaert_k": 1.0}


def param(params: Mapping[str, Any], key: str, who: str) -> np.ndarray:
    """``params[key]`` (or its default) as a float array broadcastable to (N, 3): scalar or RGB."""
    value = params.get(key, DEFAULTS[key])
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim > 1 or (arr.ndim == 1 and arr.shape[0] != 3) or not np.all(np.isfinite(arr)):
        raise ValidateError(f"technique '{who}' (brdf): parameter {key}={value!r} must be a finite scalar or RGB")
    return arr if arr.ndim == 1 else arr.reshape(())


class Geometry:
    """Per-sample dot products of (n, l, v): cosines, half vector, mirror direction, azimuth difference."""

    def __init__(self, normals: np.ndarray, lights: np.ndarray, views: np.ndarray):
        self.n, self.l, self.v = unit(normals), unit(lights), unit(views)
        self.cl = np.sum(self.n * self.l, axis=-1)
        self.cv = np.sum(self.n * self.v, axis=-1)
        self.h = unit(self.l + self.v)
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


def column(x: np.ndarray) -> np.ndarray:
    return np.asarray(x, dtype=np.float64)[:, None]


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


def scalar_param(params: Mapping[str, Any], key: str, who: str, low: float = -np.inf) -> float:
    arr = param(params, key, who)
    if arr.ndim != 0 or not float(arr) >= low:
        raise ValidateError(f"technique '{who}' (brdf): parameter {key}={arr.tolist()!r} must be a scalar ≥ {low:g}")
    return float(arr)


def distribution_param(params: Mapping[str, Any], who: str) -> str:
    d = str(params.get("distribution", DEFAULTS["distribution"])).lower()
    if d not in ("beckmann", "ggx"):
        raise ValidateError(f"technique '{who}' (brdf): distribution={d!r}; expected 'beckmann' or 'ggx'")
    return d


def cook_torrance_printed_terms(params: Mapping[str, Any], g: Geometry, fresnel: str = "schlick_nl",
                                geometry: str = "vcavity", denominator: str = "printed",
                                normalised_d: bool = False) -> np.ndarray:
    """The specular part of Ganovelli's Cook–Torrance with each term switchable (term-by-term analysis):
    ``fresnel`` 'schlick_nl' (printed) | 'schlick_vh' | 'exact'; ``geometry`` 'vcavity' | 'smith';
    ``denominator`` 'printed' ((n·l)(n·v)) | 'walter' (4(n·l)(n·v)); ``normalised_d`` adds the 1/π.
    Returns S/π (π-folded light) ≙ f_r·(n·l), (N, 3)."""
    who = "cook_torrance_printed"
    m = scalar_param(params, "alpha", who, 1e-4)
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
    spec = f * column(d * gg / denom * g.cl)
    return spec / np.pi


def microfacet_specular(params: Mapping[str, Any], g: Geometry, who: str = "cook_torrance") -> np.ndarray:
    """F(v·h) D G₁(l) G₁(v) / (4 (n·l)(n·v)) · (n·l) [9] eq. 20, (N, 3)."""
    a = scalar_param(params, "alpha", who, 1e-4)
    dist = distribution_param(params, who)
    d = beckmann_d(g.ch, a) if dist == "beckmann" else ggx_d(g.ch, a)
    gg = smith_g1(g.cl, a, dist) * smith_g1(g.cv, a, dist)
    f = fresnel_exact(g.vh, param(params, "eta", who), param(params, "k", who))
    return f * column(d * gg / (4.0 * np.maximum(g.cv, 1e-12)))


def alpha_beta(g: Geometry) -> tuple[np.ndarray, np.ndarray]:
    return np.maximum(g.theta_l, g.theta_v), np.minimum(g.theta_l, g.theta_v)


def oren_nayar_full_terms(sigma: float, albedo: np.ndarray, g: Geometry) -> tuple[np.ndarray, np.ndarray]:
    """(direct L₁, inter-reflection L₂) of the full model [10] eq. 27–29, each as f_r·(n·l), (N, 3)."""
    s2 = sigma * sigma
    al, be = alpha_beta(g)
    be = np.minimum(be, np.pi / 2 - 1e-9)
    cd = g.cos_dphi
    c1 = 1.0 - 0.5 * s2 / (s2 + 0.33)
    c2 = np.where(cd >= 0.0, 0.45 * s2 / (s2 + 0.09) * np.sin(al),
                  0.45 * s2 / (s2 + 0.09) * (np.sin(al) - (2.0 * be / np.pi) ** 3))
    c3 = 0.125 * s2 / (s2 + 0.09) * (4.0 * al * be / np.pi ** 2) ** 2
    direct = c1 + cd * c2 * np.tan(be) + (1.0 - np.abs(cd)) * c3 * np.tan(0.5 * (al + be))
    inter = 0.17 * s2 / (s2 + 0.13) * (1.0 - cd * (2.0 * be / np.pi) ** 2)
    return (albedo / np.pi * column(direct * g.cl), albedo * albedo / np.pi * column(inter * g.cl))
