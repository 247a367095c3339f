"""Multiple-scattering energy compensation for microfacet BRDFs, as techniques of the ``brdf`` family.

A single-scattering microfacet BRDF f_ss (Walter et al. 2007 eq. 20, :func:`.classic_brdfs.microfacet_specular`)
loses the light that bounces more than once on the microsurface: its directional albedo under F = 1,

    E(μ) = ∫ f_ss(l, v; F = 1) (n·l) dω_l,   μ = n·v,

falls to ≈ 0.4–0.45 at α = 1 (GGX, Smith separable G). The techniques below add that energy back, each as
its paper prints it; all reduce to cook_torrance's single scattering (+ ρ/π diffuse from ``albedo``) plus a
compensation term, read the same ``params`` (``alpha``, ``distribution``, ``eta``, ``k``, ``albedo``), and the
metalness pair reads ``metalness`` (default 1) and ``base_color`` (default F₀ of η + ik):

* ``ggx_kulla_conty`` — Kulla & Conty 2017 [1] (slides 16–18): f = f_ss + F_ms f_ms with
  f_ms(l, v) = (1 − E(μ_o))(1 − E(μ_i)) / (π (1 − E_avg)), E_avg = 2∫₀¹ E(μ) μ dμ, and the multiple-scattering
  Fresnel F_ms = F_avg² E_avg / (1 − F_avg (1 − E_avg)), F_avg = 2∫₀¹ F(μ) μ dμ of the exact Fresnel of η + ik.
  For F = 1: ∫ f_ms (n·l) dω_l = 1 − E(μ_o) exactly, so the albedo is 1 (energy conservation by construction).
* ``ggx_fdez_aguera`` — Fdez-Agüera 2019 [2] eq. 9–15 (the split-sum form): the single-scattering albedo
  FssEss = F₀ A(μ) + B(μ) (Karis's split-sum DFG terms [4] A = ∫ f_ss/F (1 − (1 − v·h)⁵) cos, B = ∫ f_ss/F
  (1 − v·h)⁵ cos), Ems = 1 − E(μ), F_avg = F₀ + (1 − F₀)/21, FmsEms = Ems FssEss F_avg / (1 − Ems F_avg), added
  as a cosine lobe FmsEms(μ_o)/π (as engines add it to the irradiance term). Albedo = E_F(μ) + FmsEms.
* ``ggx_turquin`` — Turquin 2019 [3] eq. 16: f = f_ss (1 + F₀ (1/E(μ_o) − 1)); F = 1 gives albedo exactly 1.
* ``ggx_metalness_fdez_aguera`` — a metalness workflow (Karis 2013 [4]: F₀ = mix(0.04, base, m), diffuse
  base (1 − m)) with Schlick's Fresnel, where the compensation is computed *per path* and mixed after:
  mix(dielectric(F₀ = 0.04) + base·(1 − E_spec)/π, metal(F₀ = base), m), as three.js 32190 and Bevy 23203 fixed.
* ``ggx_metalness_blended_f0_bug`` — the shipped bug (three.js before PR 32190, Bevy before PR 23203): one
  specular path with the blended F₀ = mix(0.04, base, m) put through FmsEms (non-linear in F₀), diffuse
  base (1 − m)(1 − FssEss − FmsEms)/π. Under a white furnace (base = 1) it loses m (1 − FssEss − FmsEms at the
  blended F₀) of the light: a regression technique that must fail the furnace.

E, A, B are tabulated per (distribution, α) on 64 Gauss–Legendre nodes in μ (linear interpolation between
them), each by a 64 × 128 quadrature over the half vector, distributed by D(h)(n·h) (the GGX/Beckmann CDF
inverted in closed form, Gauss–Legendre in the CDF variable × uniform φ): accurate to ~10⁻⁴ for α ≥ 0.02 (the
rule follows the lobe, so smaller α stay accurate at grazing μ only as far as 64 μ nodes resolve E(μ)).

Precision: the tables and F_avg are per-(distribution, α) set-up in numpy float64; the per-direction evaluation
(the single-scattering term, the table interpolation :meth:`Tables.lookup_dr`, the compensation lobes) is drjit in
the family's float32 (:mod:`validate.local_models.precision`, :mod:`.common`'s ``*_dr`` terms).

References
  [1] C. Kulla, A. Conty, "Revisiting physically based shading at Imageworks", SIGGRAPH 2017 course
      (Physically Based Shading in Theory and Practice), slides 16–18; S. Hill, "A multi-faceted exploration
      (part 2)", 2018, for F_ms written out.
  [2] C. Fdez-Agüera, "A multiple-scattering microfacet model for real-time image-based lighting", JCGT 8(1), 2019.
  [3] E. Turquin, "Practical multiple scattering compensation for microfacet models", ILM tech. report, 2019.
  [4] B. Karis, "Real shading in Unreal Engine 4", SIGGRAPH 2013 course notes (split sum, metalness).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from ...errors import ValidateError
from ..families import brdf
from .common import (
    RGB,
    GeometryDr,
    fresnel_exact,
    fresnel_f0,
    fresnel_schlick_dr,
    microfacet_specular_dr,
    param,
    rgb_param,
    smith_g1,
)

N_MU = 64  # Gauss–Legendre nodes of the μ tables
N_U, N_PHI = 64, 128  # half-vector quadrature (CDF variable × azimuth)
DIELECTRIC_F0 = 0.04  # the metalness workflow's dielectric F₀ (Karis 2013 [4])


@dataclass(frozen=True)
class Tables:
    """Directional albedo tables of f_ss at one (distribution, α), on Gauss–Legendre μ nodes."""

    mu: np.ndarray  # (N_MU,) nodes in (0, 1)
    weights: np.ndarray  # (N_MU,) Gauss–Legendre weights on [0, 1]
    e: np.ndarray  # E(μ), F = 1
    a: np.ndarray  # split-sum scale: ∫ f_ss/F (1 − (1 − v·h)⁵) cos
    b: np.ndarray  # split-sum bias: ∫ f_ss/F (1 − v·h)⁵ cos

    @property
    def e_avg(self) -> float:
        """E_avg = 2∫₀¹ E(μ) μ dμ."""
        return float(np.sum(2.0 * self.weights * self.mu * self.e))

    def lookup(self, table: np.ndarray, mu: np.ndarray) -> np.ndarray:
        return np.interp(np.clip(mu, 0.0, 1.0), self.mu, table)

    def lookup_dr(self, table: np.ndarray, mu: Any) -> Any:
        """:meth:`lookup` on a drjit array: the same piecewise-linear interpolant (constant beyond the end nodes)
        written as y₀ + Σ_j s_j clip(μ − μ_j, 0, μ_{j+1} − μ_j), s_j the segment's slope — no gather, so it runs
        alike on every drjit backend."""
        import drjit as dr

        x = dr.clip(mu, 0.0, 1.0)
        dx = np.diff(self.mu)
        slope = np.diff(table) / dx
        out = float(table[0]) + 0.0 * x
        for xj, dj, sj in zip(self.mu[:-1], dx, slope, strict=True):
            out = dr.fma(float(sj), dr.clip(x - float(xj), 0.0, float(dj)), out)
        return out


def _half_vectors(distribution: str, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """(h (M, 3), weights (M,)) distributed by D(h)(n·h) dω_h (Σ w = 1): the CDF P(θ_h) inverted in closed form,
    GGX cos²θ = (1 − u)/(1 + (α² − 1) u), Beckmann tan²θ = −α² ln(1 − u) [Walter 2007 eq. 28, 35]."""
    x, w = np.polynomial.legendre.leggauss(N_U)
    u, wu = 0.5 * (x + 1.0), 0.5 * w
    if distribution == "ggx":
        c2 = (1.0 - u) / (1.0 + (alpha * alpha - 1.0) * u)
    else:
        c2 = 1.0 / (1.0 - alpha * alpha * np.log1p(-u))
    ct = np.sqrt(c2)
    st = np.sqrt(np.maximum(1.0 - c2, 0.0))
    phi = (np.arange(N_PHI) + 0.5) * (2.0 * np.pi / N_PHI)
    h = np.stack([np.outer(st, np.cos(phi)), np.outer(st, np.sin(phi)), np.outer(ct, np.ones(N_PHI))], axis=-1)
    return h.reshape(-1, 3), np.repeat(wu / N_PHI, N_PHI)


@lru_cache(maxsize=512)
def tables(distribution: str, alpha: float) -> Tables:
    """E, A, B of f_ss at roughness α: with l = reflect(v, h), f_ss cos dω_l = G₁(l)G₁(v) (v·h) / (μ (n·h)) ×
    D(h)(n·h) dω_h (the Jacobian dω_l = 4 (v·h) dω_h), summed over :func:`_half_vectors`."""
    x, w = np.polynomial.legendre.leggauss(N_MU)
    mu, wmu = 0.5 * (x + 1.0), 0.5 * w
    h, wh = _half_vectors(distribution, alpha)
    e, a, b = (np.empty(N_MU) for _ in range(3))
    for i, m in enumerate(mu):
        v = np.array([np.sqrt(1.0 - m * m), 0.0, m])
        vh = h @ v
        l_z = 2.0 * vh * h[:, 2] - m
        ok = (vh > 0.0) & (l_z > 0.0)
        g = smith_g1(np.where(ok, l_z, 1.0), alpha, distribution) * smith_g1(np.array([m]), alpha, distribution)
        q = np.where(ok, g * vh / (m * h[:, 2]), 0.0) * wh
        s = (1.0 - np.clip(vh, 0.0, 1.0)) ** 5
        e[i], a[i], b[i] = q.sum(), (q * (1.0 - s)).sum(), (q * s).sum()
    return Tables(mu, wmu, e, a, b)


def _alpha_dist(params: Mapping[str, Any], who: str) -> tuple[float, str]:
    a = np.asarray(params.get("alpha", 0.3), dtype=np.float64)
    d = str(params.get("distribution", "beckmann")).lower()
    if a.ndim != 0 or not float(a) >= 1e-4:
        raise ValidateError(f"technique '{who}' (brdf): alpha={a.tolist()!r} must be a scalar ≥ 1e-4")
    if d not in ("ggx", "beckmann"):
        raise ValidateError(f"technique '{who}' (brdf): distribution={d!r}; expected 'ggx' or 'beckmann'")
    return round(float(a), 6), d


def f_avg_exact(eta: np.ndarray, k: np.ndarray) -> np.ndarray:
    """F_avg = 2∫₀¹ F(μ) μ dμ of the exact Fresnel of η + ik (RGB, (3,)), 64-node Gauss–Legendre."""
    x, w = np.polynomial.legendre.leggauss(64)
    mu, wmu = 0.5 * (x + 1.0), 0.5 * w
    return np.sum(2.0 * (wmu * mu)[:, None] * fresnel_exact(mu, eta, k), axis=0)


def _single(params: Mapping[str, Any], g: GeometryDr, who: str) -> RGB:
    return microfacet_specular_dr({**params, "alpha": params.get("alpha", 0.3)}, g, who)


def _diffuse(params: Mapping[str, Any], g: GeometryDr, who: str) -> RGB:
    return rgb_param(params, "albedo", who) / np.pi * g.cl


def kulla_conty_lobe(t: Tables, mu_o: Any, mu_i: Any, f_avg: np.ndarray) -> RGB:
    """F_ms f_ms(l, v) (n·l) [1]: (1 − E(μ_o))(1 − E(μ_i)) / (π (1 − E_avg)) · F_avg² E_avg / (1 − F_avg (1 − E_avg))
    · μ_i, on drjit arrays (F_avg per channel, numbers)."""
    import drjit as dr

    ea = t.e_avg
    f_ms = RGB.of(f_avg ** 2 * ea / (1.0 - f_avg * (1.0 - ea)))
    lobe = ((1.0 - t.lookup_dr(t.e, mu_o)) * (1.0 - t.lookup_dr(t.e, mu_i)) / (np.pi * (1.0 - ea))
            * dr.maximum(mu_i, 0.0))
    return f_ms * lobe


def fms_ems(t: Tables, mu: Any, f0: RGB) -> tuple[RGB, RGB]:
    """(FssEss, FmsEms) of Fdez-Agüera [2] eq. 9–15 at F₀ (per channel) on drjit arrays: FssEss = F₀ A + B,
    Ems = 1 − E, F_avg = F₀ + (1 − F₀)/21, FmsEms = Ems FssEss F_avg / (1 − Ems F_avg)."""
    f0 = RGB.of(f0)
    ems = 1.0 - t.lookup_dr(t.e, mu)
    fss_ess = f0 * t.lookup_dr(t.a, mu) + t.lookup_dr(t.b, mu)
    f_avg = f0 + (1.0 - f0) / 21.0
    return fss_ess, fss_ess * f_avg * ems / (1.0 - f_avg * ems)


@brdf.register("ggx_kulla_conty", "single-scattering microfacet + Kulla–Conty 2017 multiple-scattering lobe "
               "(1−E(μo))(1−E(μi))/(π(1−E_avg)) × F_ms", compensation=True)
def ggx_kulla_conty(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                    views: np.ndarray) -> np.ndarray:
    who = "ggx_kulla_conty"
    alpha, dist = _alpha_dist(params, who)
    g = GeometryDr(normals, lights, views)
    t = tables(dist, alpha)
    f_avg = f_avg_exact(param(params, "eta", who), param(params, "k", who))
    ms = kulla_conty_lobe(t, g.cv, g.cl, f_avg)
    return g.finish(_diffuse(params, g, who) + _single(params, g, who) + ms)


@brdf.register("ggx_fdez_aguera", "single-scattering microfacet + Fdez-Agüera 2019 FmsEms(μo)/π cosine lobe "
               "(F_avg = F0 + (1−F0)/21)", compensation=True)
def ggx_fdez_aguera(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                    views: np.ndarray) -> np.ndarray:
    who = "ggx_fdez_aguera"
    alpha, dist = _alpha_dist(params, who)
    g = GeometryDr(normals, lights, views)
    t = tables(dist, alpha)
    f0 = RGB.of(fresnel_f0(param(params, "eta", who), param(params, "k", who)))
    _, ms = fms_ems(t, g.cv, f0)
    return g.finish(_diffuse(params, g, who) + _single(params, g, who) + ms / np.pi * g.cl)


@brdf.register("ggx_turquin", "single-scattering microfacet × (1 + F0 (1/E(μo) − 1)) (Turquin 2019 eq. 16)",
               compensation=True)
def ggx_turquin(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    import drjit as dr

    who = "ggx_turquin"
    alpha, dist = _alpha_dist(params, who)
    g = GeometryDr(normals, lights, views)
    t = tables(dist, alpha)
    f0 = RGB.of(fresnel_f0(param(params, "eta", who), param(params, "k", who)))
    scale = 1.0 + f0 * (1.0 / dr.maximum(t.lookup_dr(t.e, g.cv), 1e-6) - 1.0)
    return g.finish(_diffuse(params, g, who) + _single(params, g, who) * scale)


def _metalness(params: Mapping[str, Any], who: str) -> tuple[np.ndarray, np.ndarray]:
    m = np.asarray(params.get("metalness", 1.0), dtype=np.float64)
    if m.ndim != 0 or not 0.0 <= float(m) <= 1.0:
        raise ValidateError(f"technique '{who}' (brdf): metalness={m.tolist()!r} must be a scalar in [0, 1]")
    base = params.get("base_color")
    if base is None:
        base = fresnel_f0(param(params, "eta", who), param(params, "k", who))
    return m, np.broadcast_to(np.asarray(base, dtype=np.float64), (3,))


def _schlick_single(g: GeometryDr, alpha: float, dist: str, f0: RGB) -> RGB:
    """f_ss (n·l) with Schlick's F(v·h) at F₀ (drjit arrays)."""
    d_only = microfacet_specular_dr({"alpha": alpha, "distribution": dist}, g, "metalness", fresnel=RGB(1.0))
    return d_only * fresnel_schlick_dr(g.vh, f0)


def metalness_parts(params: Mapping[str, Any], g: GeometryDr, who: str, blended_bug: bool) -> RGB:
    """Metalness workflow with Fdez-Agüera compensation: correct (per path, mixed after) or the blended-F₀ bug."""
    alpha, dist = _alpha_dist(params, who)
    m, base = _metalness(params, who)
    m, base_rgb = float(m), RGB.of(base)
    t = tables(dist, alpha)
    cos_l = g.cl
    if blended_bug:
        f0 = base_rgb * m + (1.0 - m) * DIELECTRIC_F0
        ss_e, ms_e = fms_ems(t, g.cv, f0)
        diffuse = base_rgb * (1.0 - m) * (1.0 - ss_e - ms_e) / np.pi * cos_l
        return _schlick_single(g, alpha, dist, f0) + ms_e / np.pi * cos_l + diffuse
    dielectric_f0 = RGB(DIELECTRIC_F0)
    d_ss, d_ms = fms_ems(t, g.cv, dielectric_f0)
    dielectric = (_schlick_single(g, alpha, dist, dielectric_f0) + d_ms / np.pi * cos_l
                  + base_rgb * (1.0 - d_ss - d_ms) / np.pi * cos_l)
    _, m_ms = fms_ems(t, g.cv, base_rgb)
    metal = _schlick_single(g, alpha, dist, base_rgb) + m_ms / np.pi * cos_l
    return dielectric * (1.0 - m) + metal * m


@brdf.register("ggx_metalness_fdez_aguera", "metalness workflow, Fdez-Agüera compensation per path (dielectric "
               "F0 = 0.04, metal F0 = base) mixed after (three.js 32190, Bevy 23203 fix)",
               compensation=True, metalness=True)
def ggx_metalness_fdez_aguera(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                              views: np.ndarray) -> np.ndarray:
    g = GeometryDr(normals, lights, views)
    return g.finish(metalness_parts(params, g, "ggx_metalness_fdez_aguera", blended_bug=False))


@brdf.register("ggx_metalness_blended_f0_bug", "REGRESSION: F0 = mix(0.04, base, metalness) blended before the "
               "Fdez-Agüera compensation (three.js before 32190, Bevy before 23203)", compensation=True,
               metalness=True, regression=True)
def ggx_metalness_blended_f0_bug(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                                 views: np.ndarray) -> np.ndarray:
    g = GeometryDr(normals, lights, views)
    return g.finish(metalness_parts(params, g, "ggx_metalness_blended_f0_bug", blended_bug=True))


__all__ = ["Tables", "tables", "f_avg_exact", "fms_ems", "kulla_conty_lobe", "metalness_parts", "DIELECTRIC_F0"]
