"""Multiple-scattering reference for a GGX conductor: Heitz et al. 2016's random walk on the Smith microsurface.

Heitz, Hanika, d'Eon, Dachsbacher, "Multiple-scattering microfacet BSDFs with the Smith model", ACM TOG 35(4)
2016, §4–5 (Algorithm 1, conductor phase function): a ray enters the microsurface from direction ω_i at height
+∞ and, with the uncorrelated height distribution P¹(h) uniform on [−1, 1] (C¹(h) = (h + 1)/2):

* next height: escape with probability G¹(ω_r, h_r) = C¹(h_r)^Λ(ω_r) (ω_r upward), else
  h ← C¹⁻¹(C¹(h_r)/(1 − U)^{1/Λ(ω_r)}) (eq. 24–26), with GGX's Λ(ω) = (−1 + sgn √(1 + α² tan²θ))/2
  (Λ(ω) < −1 for downward ω, the paper's extension);
* next direction: a visible normal ω_m ~ D_{−ω_r}(ω_m) (sampled with Dupuy & Benyoub 2023's spherical-cap method,
  valid for directions below the horizon too), ω_r ← reflect(−ω_r, ω_m), energy × F(−ω_r·ω_m).

The walk's first bounce is the height-correlated single-scattering BRDF D G₂/(4 μ_i μ_o), G₂ = 1/(1 + Λ_i + Λ_o)
(§4.3), not Mitsuba's separable G₁G₁; with F = 1 every walker leaves with energy 1 (the microsurface absorbs
nothing). Fresnel: Schlick's F = F₀ + (1 − F₀)(1 − cos)⁵ at each bounce, several F₀ on the same paths.
Estimates are means over walkers ± their standard error; deterministic seed.

This numpy walk (float64) is the slow, plain version; :mod:`validate.reference.microsurface_bsdf` runs the same
walk in drjit as a Mitsuba BSDF (sample / stochastic eval / pdf), and its tests compare the two.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

START_HEIGHT = 1.0 + (2.0 * 0.999 - 1.0)  # 1 + C¹⁻¹(0.999), as in the authors' code


def lambda_ggx(w: np.ndarray, alpha: float) -> np.ndarray:
    """Smith Λ(ω) for GGX, signed for downward directions (Heitz et al. 2016 §5.1)."""
    z = np.clip(w[:, 2], -1.0, 1.0)
    s2 = np.maximum(1.0 - z * z, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_a2 = alpha * alpha * s2 / np.maximum(z * z, 1e-300)
        lam = 0.5 * (-1.0 + np.sign(z) * np.sqrt(1.0 + inv_a2))
    return np.where(z > 0.9999, 0.0, np.where(z < -0.9999, -1.0, lam))


def _c1(h: np.ndarray) -> np.ndarray:
    return np.clip(0.5 * (h + 1.0), 0.0, 1.0)


def _inv_c1(u: np.ndarray) -> np.ndarray:
    return np.clip(2.0 * u - 1.0, -1.0, 1.0)


def sample_height(wr: np.ndarray, hr: np.ndarray, u: np.ndarray, alpha: float) -> np.ndarray:
    """Next height along ω_r from h_r (np.inf: the ray leaves the microsurface)."""
    z = wr[:, 2]
    lam = lambda_ggx(wr, alpha)
    g1 = np.where(z > 0.9999, 1.0, np.where(z <= 0.0, 0.0, _c1(hr) ** np.where(z > 0.0, lam, 1.0)))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        h = _inv_c1(_c1(hr) / (1.0 - u) ** (1.0 / np.where(np.abs(lam) > 1e-12, lam, 1e-12)))
    h = np.where(z < -0.9999, _inv_c1(u * _c1(hr)), h)
    h = np.where(np.abs(z) < 1e-4, hr, h)
    return np.where((z > 0.9999) | (u > 1.0 - g1), np.inf, h)


def sample_vndf(wi: np.ndarray, alpha: float, u1: np.ndarray, u2: np.ndarray) -> np.ndarray:
    """Visible GGX normal for direction ω_i (any hemisphere): Dupuy & Benyoub 2023, spherical cap in the stretched
    configuration, ω_m = normalise(α h_x, α h_y, h_z)."""
    s = wi * np.array([alpha, alpha, 1.0])
    s /= np.linalg.norm(s, axis=-1, keepdims=True)
    phi = 2.0 * np.pi * u1
    z = (1.0 - u2) * (1.0 + s[:, 2]) - s[:, 2]
    st = np.sqrt(np.clip(1.0 - z * z, 0.0, 1.0))
    h = np.stack([st * np.cos(phi), st * np.sin(phi), z], -1) + s
    m = h * np.array([alpha, alpha, 1.0])
    return m / np.maximum(np.linalg.norm(m, axis=-1, keepdims=True), 1e-300)


@dataclass(frozen=True)
class WalkResult:
    f0s: tuple[float, ...]
    albedo: np.ndarray  # (n_f0,) mean energy leaving
    albedo_se: np.ndarray
    single: np.ndarray  # (n_f0,) energy leaving after exactly one bounce
    single_se: np.ndarray
    mean_order: float
    truncated: float  # fraction of walkers stopped at max_order


def walk(alpha: float, mu_i: float, f0s: tuple[float, ...], n: int, seed: int, max_order: int = 64) -> WalkResult:
    """Directional albedo of the multiple-scattering GGX conductor at incidence μ_i = cos θ_i (F₀ per bounce)."""
    rng = np.random.default_rng(seed)
    f0 = np.asarray(f0s, dtype=np.float64)
    wr = np.tile([-np.sqrt(max(1.0 - mu_i * mu_i, 0.0)), 0.0, -mu_i], (n, 1))
    hr = np.full(n, START_HEIGHT)
    energy = np.ones((n, len(f0)))
    out = np.zeros((n, len(f0)))
    order = np.zeros(n, dtype=int)
    alive = np.ones(n, dtype=bool)
    for _ in range(max_order):
        idx = np.nonzero(alive)[0]
        if len(idx) == 0:
            break
        h = sample_height(wr[idx], hr[idx], rng.random(len(idx)), alpha)
        esc = ~np.isfinite(h)
        out[idx[esc]] = energy[idx[esc]]
        alive[idx[esc]] = False
        go = idx[~esc]
        hr[go] = h[~esc]
        wi = -wr[go]
        m = sample_vndf(wi, alpha, rng.random(len(go)), rng.random(len(go)))
        c = np.sum(wi * m, -1)
        wr[go] = 2.0 * c[:, None] * m - wi
        energy[go] *= f0 + (1.0 - f0) * (1.0 - np.clip(c, 0.0, 1.0))[:, None] ** 5
        order[go] += 1
    single = np.where((order == 1)[:, None], out, 0.0)
    se = np.sqrt(n)
    return WalkResult(tuple(f0s), out.mean(0), out.std(0) / se, single.mean(0), single.std(0) / se,
                      float(order[~alive].mean()) if (~alive).any() else float("nan"), float(alive.mean()))


__all__ = ["walk", "WalkResult", "lambda_ggx", "sample_height", "sample_vndf"]
