"""Linearly Transformed Cosines (LTC) for GGX under polygonal, disc and sphere lights; the ``specular_arealight``
family.

Family ``specular_arealight``
  ``fn(light, brdf, points (N, 3), normals (N, 3) unit, views (N, 3) unit towards the viewer) -> (N, 3)`` outgoing
  radiance L_o = ∫_light L_e f_r(l, v) (n·l) dω_l of a one-sided uniform emitter (front face towards
  ``normal``; a sphere and a tube emit everywhere). ``light``: {'shape': 'rectangle' | 'disc' | 'sphere' | 'tube',
  'center': (3,), 'normal': (3,) (rectangle, disc), 'radius' (disc, sphere, tube), 'size': (w, h) and 'tangent':
  (3,) along w (rectangle), 'axis': (3,) unit and 'length' ℓ ≥ 0 (tube: the capsule swept by a sphere of radius
  'radius' along the segment center ± (ℓ/2)·axis, a cylinder closed by two hemispheres), 'radiance': L_e}.
  ``brdf``: {'alpha': GGX α, 'f0': F₀ (scalar or RGB; Schlick's Fresnel)}; the microfacet BRDF is Walter et al.
  2007 eq. 20 with separable Smith G (Mitsuba's ``roughconductor``). A technique lists its shapes as meta
  ``shapes``.

LTC (Heitz, Dupuy, Hill, Neubelt 2016 [1])
  A linear transform M of the clamped cosine D_o(ω_o) = max(0, z)/π gives the distribution
  D(ω) = D_o(M⁻¹ω/‖M⁻¹ω‖) |det M⁻¹| / ‖M⁻¹ω‖³ ([1] eq. 1–3). Per (θ_v, α) the fit picks M so that
  E(θ_v, α)·D ≈ f_r(l, v)(n·l) (F = 1), E the directional albedo ([1] §4): M = [X Y Z]·R_y(φ)·[[m11, 0, m13],
  [0, m22, 0], [0, 0, 1]], Z the lobe's average direction, Nelder–Mead on (m11, m22, m13, φ) (the four free
  entries of the normalised M⁻¹ [1] §5; the authors' code fixes φ = 0, which we found leaves 1.4–2× the
  L¹ misfit at θ_v = 60°, α = 0.3–0.5) minimising
  ∫ |E·D − f cos|³ dω ([1] §4 and the authors' fitLTC code: the L³ error), rows fitted from α = 1 down, each
  started from its neighbour's solution. The integral is a fixed deterministic quadrature (our choice, so
  the objective is smooth): the balance-heuristic mixture of a GGX reflection rule (half vectors
  distributed by D(h)(n·h), Gauss–Legendre in the inverted CDF × uniform φ) and a uniform hemisphere rule.
  The table stores M⁻¹ normalised to m⁻¹₂₂ = 1 (four numbers), E, and the Schlick term E_f = ∫ f cos (1 − v·h)⁵
  (F = 1), on roughness r = √α ∈ [0, 1] (α ≥ 10⁻³) × √(1 − cos θ_v) ∈ [0, 1) ([1] §5), interpolated
  bilinearly; the fit error is stored per entry as ∫ |E·D − f cos| dω / E (fraction of the lobe misplaced).

  Under a polygon P, ∫_P D dω = ∫_{M⁻¹P} D_o dω_o, the clamped-cosine form factor of the transformed polygon
  clipped to the horizon, F = (1/2π) Σ_edges acos(p_i·p_j) ẑ·(p_i × p_j)/‖p_i × p_j‖ (Lambert/Arvo, [1] eq. 11).
  L_o = L_e (F₀ E + (1 − F₀) E_f) F ([1] §5.2). A disc is integrated as its inscribed regular 64-gon scaled to the
  disc's area; a sphere as the disc through its centre, facing the receiver, that subtends the same cone
  (radius r d/√(d² − r²)); a tube as the stadium in the plane through its axis facing the receiver (width
  2R h/√(h² − R²) for the axis at distance h, the cylinder's silhouette; ends two inscribed 32-segment half-circles
  of the same radius); no rule is exact (the paper's own disc/sphere extension, Heitz & Hill 2017,
  approximates ellipses differently) — they keep the LTC's error measurable on its own.

References
  [1] E. Heitz, J. Dupuy, S. Hill, D. Neubelt, "Real-time polygonal-light shading with linearly transformed
      cosines", ACM TOG 35(4) (SIGGRAPH 2016).
  [2] B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet models for refraction through rough surfaces",
      EGSR 2007.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...geometry import perp, unit
from ...scenes.area_lights import tube_geometry
from .. import precision
from ..brdf.common import ggx_d, smith_g1
from ..families import specular_arealight
from .common import Vec, brdf_params, dot, unit_dr

DATA = Path(__file__).resolve().parents[1] / "data" / "ltc_ggx.npz"  # local_models/data (package data)
MIN_ALPHA = 1e-3
DISC_SIDES = 64
SHAPES = ("rectangle", "disc", "sphere", "tube")
TUBE_ARC_SIDES = 32  # segments per half-circle end of a tube's stadium polygon


# ---------------------------------------------------------------------------------------------
# BRDF and quadrature used by the fit

def ggx_cos(l: np.ndarray, mu_v: float, alpha: float) -> np.ndarray:
    """f_r(l, v)(n·l) of GGX with F = 1 and separable Smith G [2] eq. 20, 33, 34; v = (sin θ_v, 0, cos θ_v)."""
    v = np.array([np.sqrt(max(1.0 - mu_v * mu_v, 0.0)), 0.0, mu_v])
    h = l + v
    h /= np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-300)
    ok = (l[:, 2] > 0.0) & (h[:, 2] > 0.0)
    g = smith_g1(np.where(ok, l[:, 2], 1.0), alpha, "ggx") * smith_g1(np.array([mu_v]), alpha, "ggx")
    return np.where(ok, ggx_d(h[:, 2], alpha) * g / (4.0 * mu_v), 0.0)


@dataclass(frozen=True)
class Quadrature:
    """Directions and weights with Σ w g(l) ≈ ∫_{S²} g dω for integrands vanishing below the horizon."""

    dirs: np.ndarray
    weights: np.ndarray


def fit_quadrature(mu_v: float, alpha: float, n: int = 32) -> Quadrature:
    """Balance-heuristic mixture of (1) l = reflect(v, h), h ~ D(h)(n·h) (GGX CDF cos²θ_h = (1 − u)/(1 + (α² − 1)u),
    Gauss–Legendre in u × n uniform φ; density p₁(l) = D(h)(n·h)/(4 v·h)) and (2) the uniform hemisphere
    (Gauss–Legendre in cos θ × uniform φ, p₂ = 1/2π): ∫ g = Σ_r Σ_i c_i g(l_i)/(p₁(l_i) + p₂(l_i)). Both rules and
    every integrand here are symmetric in y (v lies in the xz plane), so φ spans [0, π] with doubled weights."""
    x, w = np.polynomial.legendre.leggauss(n)
    u, wu = 0.5 * (x + 1.0), 0.5 * w
    phi = (np.arange(n) + 0.5) * (np.pi / n)
    c2 = (1.0 - u) / (1.0 + (alpha * alpha - 1.0) * u)
    ct, st = np.sqrt(c2), np.sqrt(np.maximum(1.0 - c2, 0.0))
    h = np.stack([np.outer(st, np.cos(phi)), np.outer(st, np.sin(phi)), np.outer(ct, np.ones(n))], -1).reshape(-1, 3)
    v = np.array([np.sqrt(max(1.0 - mu_v * mu_v, 0.0)), 0.0, mu_v])
    vh = h @ v
    l1 = 2.0 * vh[:, None] * h - v
    c1 = np.repeat(wu / n, n)
    keep = (vh > 1e-9) & (l1[:, 2] > 0.0)
    l1, c1 = l1[keep], c1[keep]
    s = np.sqrt(1.0 - u * u)
    l2 = np.stack([np.outer(s, np.cos(phi)), np.outer(s, np.sin(phi)), np.outer(u, np.ones(n))], -1).reshape(-1, 3)
    c2w = np.repeat(wu / n, n)
    dirs = np.concatenate([l1, l2])
    c = np.concatenate([c1, c2w])
    return Quadrature(dirs, c / (_p_reflect(dirs, v, alpha) + 1.0 / (2.0 * np.pi)))


def _p_reflect(l: np.ndarray, v: np.ndarray, alpha: float) -> np.ndarray:
    h = l + v
    h /= np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-300)
    vh = np.maximum(h @ v, 1e-12)
    return np.where(h[:, 2] > 0.0, ggx_d(h[:, 2], alpha) * h[:, 2] / (4.0 * vh), 0.0)


def ltc_density(m_inv: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    """D(ω) = D_o(M⁻¹ω/‖M⁻¹ω‖) |det M⁻¹| / ‖M⁻¹ω‖³, D_o = max(0, z)/π ([1] eq. 3)."""
    lo = dirs @ m_inv.T
    r = np.linalg.norm(lo, axis=-1)
    return np.maximum(lo[:, 2] / r, 0.0) / np.pi * abs(np.linalg.det(m_inv)) / r ** 3


# ---------------------------------------------------------------------------------------------
# Fit (Heitz et al. 2016 §4)

@dataclass(frozen=True)
class Entry:
    """One fitted table entry."""

    params: tuple[float, ...]  # (m11, m22, m13, φ)
    m_inv: np.ndarray  # (3, 3), normalised m⁻¹₂₂ = 1
    norm: float  # E = ∫ f cos (F = 1)
    fresnel: float  # E_f = ∫ f cos (1 − v·h)⁵
    l1_error: float  # ∫ |E·D − f cos| dω / E


def _frame(avg: np.ndarray) -> np.ndarray:
    z = np.array([avg[0], 0.0, avg[2]])
    z /= np.linalg.norm(z)
    return np.column_stack([[z[2], 0.0, -z[0]], [0.0, 1.0, 0.0], z])


def _matrix(frame: np.ndarray, p: np.ndarray) -> np.ndarray:
    """M = [X Y Z] R_y(φ) [[m11, 0, m13], [0, m22, 0], [0, 0, 1]] for p = (m11, m22, m13, φ): the QR form of every
    M with no x/z–y coupling (the four free entries of the normalised M⁻¹ of [1] §5)."""
    c, s = np.cos(p[3]), np.sin(p[3])
    rot = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return frame @ rot @ np.array([[p[0], 0.0, p[2]], [0.0, p[1], 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class FitProblem:
    """One (cos θ_v, α) entry's fit data: the quadrature, f cos at its nodes, E, E_f, the lobe frame, the start."""

    mu_v: float
    alpha: float
    quad: Quadrature
    target: np.ndarray  # f_r cos at quad.dirs (F = 1)
    norm: float
    fresnel: float
    frame: np.ndarray
    iso: bool  # normal incidence: one parameter (m11 = m22, m13 = φ = 0)
    x0: np.ndarray  # the start in the free parameters

    def full(self, p: np.ndarray) -> np.ndarray:
        """(m11, m22, m13, φ) from the free parameters."""
        return np.array([p[0], p[0], 0.0, 0.0]) if self.iso else np.asarray(p, dtype=np.float64)

    def l3_error(self, p: np.ndarray) -> float:
        """∫ |E·D_M − f cos|³ dω at the free parameters ``p`` (10³⁰ where m11 or m22 ≤ 10⁻⁷)."""
        pp = self.full(p)
        if pp[0] <= 1e-7 or pp[1] <= 1e-7:
            return 1e30
        d = ltc_density(np.linalg.inv(_matrix(self.frame, pp)), self.quad.dirs)
        return float(np.sum(self.quad.weights * np.abs(self.norm * d - self.target) ** 3))

    def entry(self, p: np.ndarray) -> Entry:
        pp = self.full(p)
        m_inv = np.linalg.inv(_matrix(self.frame, pp))
        m_inv = m_inv / m_inv[2, 2]
        q = self.quad
        l1 = float(np.sum(q.weights * np.abs(self.norm * ltc_density(m_inv, q.dirs) - self.target))) / self.norm
        return Entry(tuple(float(x) for x in pp), m_inv, self.norm, self.fresnel, l1)


def fit_problem(mu_v: float, alpha: float, init: tuple[float, ...] | None = None, n: int = 32) -> FitProblem:
    """The data of :func:`fit_entry`: quadrature (:func:`fit_quadrature`), E, E_f, the frame of the lobe's
    average direction, the start ``init`` or (α, α, 0, 0)."""
    q = fit_quadrature(mu_v, alpha, n)
    f = ggx_cos(q.dirs, mu_v, alpha)
    norm = float(np.sum(q.weights * f))
    v = np.array([np.sqrt(max(1.0 - mu_v * mu_v, 0.0)), 0.0, mu_v])
    h = q.dirs + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    fres = float(np.sum(q.weights * f * (1.0 - np.clip(h @ v, 0.0, 1.0)) ** 5))
    avg = np.sum((q.weights * f)[:, None] * q.dirs, axis=0)
    iso = mu_v > 1.0 - 1e-6
    p0 = np.asarray(init if init is not None else (alpha, alpha, 0.0, 0.0), dtype=np.float64)
    return FitProblem(mu_v, alpha, q, f, norm, fres, _frame(avg), iso, p0[:1] if iso else p0)


def fit_entry(mu_v: float, alpha: float, init: tuple[float, ...] | None = None, n: int = 32) -> Entry:
    """Fit M for one (cos θ_v, α): minimise ∫ |E·D_M − f cos|³ dω over (m11, m22, m13, φ) by Nelder–Mead, started
    from ``init`` (the neighbouring entry's solution, [1]'s procedure) or (α, α, 0, 0); at normal incidence the
    lobe is isotropic (m11 = m22, m13 = φ = 0: one parameter) as in [1]'s code. The table's path
    (scripts/fit_ltc.py); :func:`fit_entry_ad` is the same fit by gradients."""
    return fit_entry_scipy(fit_problem(mu_v, alpha, init, n))


def fit_entry_scipy(prob: FitProblem) -> Entry:
    """Nelder–Mead (scipy; xatol 10⁻⁵, at most 3000 evaluations) on :meth:`FitProblem.l3_error`."""
    from scipy.optimize import minimize

    res = minimize(prob.l3_error, prob.x0, method="Nelder-Mead",
                   options={"xatol": 1e-5, "fatol": 0.0, "maxiter": 3000, "maxfev": 3000})
    return prob.entry(res.x)


def l3_error_ad(prob: FitProblem) -> Any:
    """The objective ∫ |E·D_M − f cos|³ dω in drjit (:mod:`validate.numerics.adfit`): a function of the free parameters
    (width-1 Float64 arrays). M⁻¹ = S⁻¹ R_y(φ)ᵀ [X Y Z]ᵀ in closed form, S = [[m11, 0, m13], [0, m22, 0], [0, 0, 1]]
    (S⁻¹ = [[1/m11, 0, −m13/m11], [0, 1/m22, 0], [0, 0, 1]]), |det M⁻¹| = 1/(m11 m22) (the frame and R_y are
    rotations); D as :func:`ltc_density`."""
    import drjit as dr

    from ...numerics import adfit

    local = prob.quad.dirs @ prob.frame  # [X Y Z]ᵀ l, per row
    lx, ly, lz = (adfit.array(local[:, k]) for k in range(3))
    w, f = adfit.array(prob.quad.weights), adfit.array(prob.target)
    norm = prob.norm

    def objective(p: list[Any]) -> Any:
        if prob.iso:
            m11, m22, m13, c, s = p[0], p[0], 0.0, 1.0, 0.0
        else:
            m11, m22, m13 = p[0], p[1], p[2]
            c, s = dr.cos(p[3]), dr.sin(p[3])
        a, e = c * lx - s * lz, s * lx + c * lz
        ox, oy, oz = (a - m13 * e) / m11, ly / m22, e
        r = dr.sqrt(ox * ox + oy * oy + oz * oz)
        d = dr.maximum(oz / r, 0.0) / dr.pi / (m11 * m22) / (r * r * r)
        return dr.sum(w * dr.abs(norm * d - f) ** 3)

    return objective


def fit_entry_ad(prob: FitProblem) -> Entry:
    """:func:`l3_error_ad` minimised with drjit's reverse-mode gradient (:func:`validate.numerics.adfit.minimize`)
    from the same start: L-BFGS-B with m11, m22 ≥ 10⁻⁷ (the Nelder–Mead objective's wall; m13 and φ free as there), then
    BFGS from its result (the clamp max(0, z) of D_o makes the quadrature sum piecewise smooth — a kink where a
    node crosses the transformed horizon — and L-BFGS-B's line search can stop short at one: 10⁻⁵ above
    Nelder–Mead at r = 0.087, cos θ_v = 0.811); the lower of the two (:meth:`FitProblem.l3_error`, whose wall
    rejects a BFGS step to m ≤ 10⁻⁷)."""
    from ...numerics import adfit

    bounds = [(1e-7, None)] if prob.iso else [(1e-7, None), (1e-7, None), (None, None), (None, None)]
    obj = l3_error_ad(prob)
    first = adfit.minimize(obj, prob.x0, bounds=bounds)
    polish = adfit.minimize(obj, first.x, method="BFGS", gtol=1e-12, maxiter=400, restarts=0)
    best = min((first.x, polish.x), key=prob.l3_error)
    return prob.entry(best)


def table_axes(size: int) -> tuple[np.ndarray, np.ndarray]:
    """(roughness r_i = i/(size − 1), α = max(r², 10⁻³); cos θ_j = 1 − x_j², x_j = j/(size − 1) clamped to
    θ ≤ 1.57) ([1]'s parametrisation)."""
    r = np.arange(size) / (size - 1)
    x = np.arange(size) / (size - 1)
    return r, np.maximum(1.0 - x * x, np.cos(1.57))


def alpha_of(r: float) -> float:
    return max(r * r, MIN_ALPHA)


# ---------------------------------------------------------------------------------------------
# Table and evaluation

@dataclass(frozen=True)
class Table:
    """m_inv[i_r, j_θ] (4: m⁻¹₀₀, m⁻¹₀₂, m⁻¹₁₁, m⁻¹₂₀), norm, fresnel, l1_error on the :func:`table_axes` grid."""

    m_inv: np.ndarray
    norm: np.ndarray
    fresnel: np.ndarray
    l1_error: np.ndarray
    params: np.ndarray

    @property
    def size(self) -> int:
        return self.norm.shape[0]

    def lookup(self, alpha: float, mu_v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Bilinear (M⁻¹ (N, 3, 3), E (N,), E_f (N,)) at roughness √α and x = √(1 − μ_v)."""
        n = self.size
        fr = np.clip(np.sqrt(alpha), 0.0, 1.0) * (n - 1)
        fx = np.clip(np.sqrt(np.clip(1.0 - mu_v, 0.0, 1.0)), 0.0, 1.0) * (n - 1)
        i0 = min(int(np.floor(fr)), n - 2)
        j0 = np.minimum(np.floor(fx).astype(int), n - 2)
        tr, tx = fr - i0, (fx - j0)[:, None]

        def bil(a: np.ndarray) -> np.ndarray:
            a = a.reshape(n, n, -1)
            row = (1 - tr) * a[i0] + tr * a[i0 + 1]
            return (1 - tx) * row[j0] + tx * row[j0 + 1]

        k = bil(self.m_inv)
        m = np.zeros((len(mu_v), 3, 3))
        m[:, 0, 0], m[:, 0, 2], m[:, 1, 1], m[:, 2, 0], m[:, 2, 2] = k[:, 0], k[:, 1], k[:, 2], k[:, 3], 1.0
        return m, bil(self.norm)[:, 0], bil(self.fresnel)[:, 0]


def pack(entries: list[list[Entry]]) -> dict[str, np.ndarray]:
    """Arrays for the .npz (entries[i_r][j_θ])."""
    mi = np.array([[[e.m_inv[0, 0], e.m_inv[0, 2], e.m_inv[1, 1], e.m_inv[2, 0]] for e in row] for row in entries])
    return {"m_inv": mi, "norm": np.array([[e.norm for e in row] for row in entries]),
            "fresnel": np.array([[e.fresnel for e in row] for row in entries]),
            "l1_error": np.array([[e.l1_error for e in row] for row in entries]),
            "params": np.array([[e.params for e in row] for row in entries])}


@lru_cache(maxsize=1)
def load_table(path: str = str(DATA)) -> Table:
    """The shipped table (``scripts/fit_ltc.py`` writes it)."""
    if not Path(path).is_file():
        raise ValidateError(f"{path}: LTC table missing; run scripts/fit_ltc.py")
    with np.load(path) as z:
        return Table(z["m_inv"], z["norm"], z["fresnel"], z["l1_error"], z["params"])


def _perp_dr(n: Vec) -> Vec:
    """:func:`validate.geometry.perp` on drjit arrays: unit n × x̂, or n × ŷ where |n_x| ≥ 0.9."""
    import drjit as dr

    use_x = dr.abs(n[0]) < 0.9
    ax, ay = dr.select(use_x, 1.0, 0.0), dr.select(use_x, 0.0, 1.0)
    return unit_dr((-n[2] * ay, n[2] * ax, n[0] * ay - n[1] * ax))


def _cross(a: Vec, b: Vec) -> Vec:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def light_polygon_dr(light: Mapping[str, Any], points: np.ndarray, p: Vec, who: str) -> list[Vec]:
    """The light's polygon, K vertices (drjit (x, y, z) each, per receiver), relative to the receivers ``p``:
    counter-clockwise seen from the emitting side (rectangle, the equal-area 64-gon of a disc); the disc through a
    sphere's centre facing the receiver, radius scaled by d/√(d² − r²) (the same cone); a tube's stadium
    (:func:`tube_polygon_dr`). Per-light numbers (:func:`polygon_constants`) enter through
    :func:`~validate.local_models.precision.constants_dr`.
    ``points`` (N, 3) float64 is read only to refuse a receiver inside the light."""
    shape = light.get("shape")
    return polygon_dr(shape, precision.constants_dr(polygon_constants(light, points, who)), p)


def polygon_constants(light: Mapping[str, Any], points: np.ndarray, who: str) -> np.ndarray:
    """The light's numbers (float64, formed in numpy) that :func:`polygon_dr` builds its polygon from: rectangle the
    four corners (12); disc its centre, scale·t and scale·b (9; scale = the equal-area 64-gon's circumradius); sphere
    its centre, radius and that scale (5); tube its centre, axis, ℓ/2 and radius (8). Refuses a receiver of
    ``points`` (N, 3) inside a sphere or within a tube's radius of its axis."""
    shape = light.get("shape")
    c = np.asarray(light.get("center", (0.0, 0.0, 0.0)), dtype=np.float64)
    if shape == "rectangle":
        nrm = unit(light["normal"])
        t = unit(light.get("tangent", perp(nrm)))
        t = unit(t - nrm * np.dot(t, nrm))
        b = np.cross(nrm, t)
        w, h = (float(x) for x in light["size"])
        return np.array([c + 0.5 * (sx * w * t + sy * h * b) for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
                        ).ravel()
    if shape in ("disc", "sphere"):
        r = float(light["radius"])
        scale = r * np.sqrt(2.0 * np.pi / (DISC_SIDES * np.sin(2.0 * np.pi / DISC_SIDES)))  # equal area
        if shape == "disc":
            nrm = unit(light["normal"])
            t = perp(nrm)
            b = np.cross(nrm, t)
            return np.r_[c, scale * t, scale * b]
        if np.any(np.linalg.norm(points - c, axis=-1) <= r):
            raise ValidateError(f"technique '{who}' (specular_arealight): a receiver lies inside the sphere light")
        return np.r_[c, r, scale]
    if shape == "tube":
        c, ax, length, r = tube_geometry(light, f"technique '{who}' (specular_arealight)")
        q64 = np.asarray(points, dtype=np.float64) - c
        if np.any(np.linalg.norm(q64 - (q64 @ ax)[:, None] * ax, axis=-1) <= r):
            raise ValidateError(f"technique '{who}' (specular_arealight): a receiver lies within the tube's radius "
                                "of its axis")
        return np.r_[c, ax, 0.5 * length, r]
    raise ValidateError(f"technique '{who}' (specular_arealight): light shape {shape!r}; expected one of {SHAPES}")


def polygon_dr(shape: str, k: list[Any], p: Vec) -> list[Vec]:
    """The polygon of :func:`light_polygon_dr` from the light's numbers ``k`` (:func:`polygon_constants` as drjit
    arrays: width 1 for one light, or one entry per receiver for a light per receiver) and the receivers ``p``."""
    if shape == "rectangle":
        return [(k[3 * i] - p[0], k[3 * i + 1] - p[1], k[3 * i + 2] - p[2]) for i in range(4)]
    ang = 2.0 * np.pi * np.arange(DISC_SIDES) / DISC_SIDES
    if shape == "disc":
        cc, tt, bb = k[0:3], k[3:6], k[6:9]
        return [tuple(cc[i] + float(np.cos(a)) * tt[i] + float(np.sin(a)) * bb[i] - p[i] for i in range(3))
                for a in ang]  # type: ignore[misc]
    if shape == "sphere":
        import drjit as dr

        to_p = (p[0] - k[0], p[1] - k[1], p[2] - k[2])
        d2 = dot(to_p, to_p)
        d = dr.sqrt(d2)
        nrm = (to_p[0] / d, to_p[1] / d, to_p[2] / d)
        s = k[4] * d / dr.sqrt(d2 - k[3] * k[3])  # the disc subtending the sphere's cone
        t = _perp_dr(nrm)
        b = _cross(nrm, t)
        # vertex − p = (c − p) + s (cos a t + sin a b) = −to_p + …
        return [tuple(s * (float(np.cos(a)) * t[i] + float(np.sin(a)) * b[i]) - to_p[i] for i in range(3))
                for a in ang]  # type: ignore[misc]
    if shape == "tube":
        return _tube_polygon(k, p)
    raise ValidateError(f"ltc polygon_dr: light shape {shape!r}; expected one of {SHAPES}")


def tube_polygon_dr(light: Mapping[str, Any], points: np.ndarray, p: Vec, who: str) -> list[Vec]:
    """The stadium (2·(TUBE_ARC_SIDES + 1) vertices relative to each receiver) standing in for a capsule: in the
    plane through the axis whose normal points at the receiver, the rectangle ℓ × 2R′ closed by half-circles of
    radius R′ = R h/√(h² − R²) about the ends (h: the receiver's distance to the axis)."""
    return _tube_polygon(precision.constants_dr(polygon_constants(dict(light, shape="tube"), points, who)), p)


def _tube_polygon(k: list[Any], p: Vec) -> list[Vec]:
    """:func:`tube_polygon_dr` from the tube's numbers k = (centre, axis, ℓ/2, R) (drjit)."""
    import drjit as dr

    cc, aa, half, rad = k[0:3], k[3:6], k[6], k[7]
    q = (p[0] - cc[0], p[1] - cc[1], p[2] - cc[2])
    qa = dot(q, aa)
    qp = (q[0] - qa * aa[0], q[1] - qa * aa[1], q[2] - qa * aa[2])
    h2 = dot(qp, qp)
    h = dr.sqrt(h2)
    b = unit_dr(_cross(qp, aa))
    rr = rad * h / dr.sqrt(h2 - rad * rad)
    th = np.linspace(-0.5 * np.pi, 0.5 * np.pi, TUBE_ARC_SIDES + 1)
    out: list[Vec] = []
    for sign in (1.0, -1.0):
        for t in th:
            ca, sa = sign * float(np.cos(t)), sign * float(np.sin(t))
            # centre ± (ℓ/2) axis + R′ (±cos t · axis ± sin t · b) − p = −q ± …
            out.append(tuple((sign * half + rr * ca) * aa[i] + (rr * sa) * b[i] - q[i] for i in range(3)))  # type: ignore[arg-type]
    return out


def _edge(a: Vec, b: Vec) -> Any:
    """atan2(‖a × b‖, a·b) ẑ·(a × b)/‖a × b‖ for unit a, b (0 where ‖a × b‖ ≤ 10⁻¹²): one edge of [1] eq. 11.
    atan2 instead of acos(a·b): acos loses √u of the angle of a short edge in float32, atan2 keeps u."""
    import drjit as dr

    cr = _cross(a, b)
    crn = dr.sqrt(dot(cr, cr))
    ok = crn > 1e-12
    return dr.select(ok, dr.atan2(crn, dot(a, b)) * cr[2] / dr.select(ok, crn, 1.0), 0.0)


def form_factor_dr(poly: list[Vec]) -> Any:
    """(1/2π) |Σ_edges atan2(‖p_i × p_j‖, p_i·p_j) ẑ·(p_i × p_j)/‖p_i × p_j‖| of the polygon (K vertices, drjit)
    clipped to z ≥ 0 and projected on the unit sphere: ∫_poly max(0, z)/π dω ([1] eq. 11), either winding.

    Clipping (Sutherland–Hodgman on the horizon): each edge contributes its part above z = 0 — the whole edge,
    vertex → exit point, or entry point → vertex — and each entry point is joined to the exit point before it
    (cyclically) along the horizon. Vertices with z ≥ 0 count as above; a clipped polygon of fewer than three
    points (vertices above + crossings) integrates to 0."""
    import drjit as dr

    k = len(poly)
    above = [v[2] >= 0.0 for v in poly]
    units = [unit_dr(v) for v in poly]
    cross_pts, exits, entries = [], [], []
    count = dr.zeros(type(poly[0][2]), dr.width(poly[0][2]))
    for i in range(k):
        j = (i + 1) % k
        a, b = poly[i], poly[j]
        dz = a[2] - b[2]
        t = dr.select(dz != 0.0, a[2] / dr.select(dz != 0.0, dz, 1.0), 0.0)
        x = unit_dr((dr.fma(t, b[0] - a[0], a[0]), dr.fma(t, b[1] - a[1], a[1]), a[2] * 0.0))
        cross_pts.append(x)
        exits.append(above[i] & ~above[j])
        entries.append(~above[i] & above[j])
        count += dr.select(above[i], 1.0, 0.0) + dr.select(above[i] != above[j], 1.0, 0.0)
    zero = count * 0.0
    pending = (zero, zero, zero)  # the last exit point of the cycle: the exit that precedes the first entry
    for i in range(k):
        pending = tuple(dr.select(exits[i], cross_pts[i][c], pending[c]) for c in range(3))  # type: ignore[assignment]
    total = zero
    for i in range(k):
        j = (i + 1) % k
        both = above[i] & above[j]
        start = tuple(dr.select(entries[i], cross_pts[i][c], units[i][c]) for c in range(3))
        end = tuple(dr.select(exits[i], cross_pts[i][c], units[j][c]) for c in range(3))
        total += dr.select(both | exits[i] | entries[i], _edge(start, end), 0.0)  # type: ignore[arg-type]
        total += dr.select(entries[i], _edge(pending, cross_pts[i]), 0.0)  # type: ignore[arg-type]
        pending = tuple(dr.select(exits[i], cross_pts[i][c], pending[c]) for c in range(3))  # type: ignore[assignment]
    return dr.select(count >= 3.0, dr.abs(total), 0.0) / (2.0 * np.pi)


def clipped_form_factor(poly: np.ndarray) -> np.ndarray:
    """:func:`form_factor_dr` of polygons given as numpy (N, K, 3), in the active dtype → (N,) float64."""
    poly = np.asarray(poly, dtype=np.float64)
    n, k, _ = poly.shape
    cols = precision.packed_to_dr(*(poly[:, i, c] for i in range(k) for c in range(3)))
    return precision.to_np(form_factor_dr([tuple(cols[3 * i:3 * i + 3]) for i in range(k)]), (n,))  # type: ignore[misc]


def local_frames(normals: np.ndarray, views: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rows [X, Y, n] (N, 3, 3) with v in the XZ plane, μ_v = n·v) in numpy float64 (the analysis path of the
    arealights experiment; the evaluation uses :func:`local_frames_dr`)."""
    n = unit(normals)
    v = unit(views)
    mu = np.sum(n * v, -1)
    x = v - mu[:, None] * n
    xn = np.linalg.norm(x, axis=-1, keepdims=True)
    fallback = perp(n)
    x = np.where(xn > 1e-9, x / np.maximum(xn, 1e-300), fallback)
    return np.stack([x, np.cross(n, x), n], axis=1), mu


def local_frames_dr(n: Vec, v: Vec) -> tuple[Vec, Vec, Any, Any]:
    """(X, Y, μ_v = n·v, x = ‖n − v‖/√2) for unit n, v (drjit): X = (v − μ n)/‖v − μ n‖ (perp(n) at normal
    incidence), Y = n × X. The table coordinate x = √(1 − μ_v) is taken as ‖n − v‖/√2 (equal for unit vectors):
    1 − μ_v from a float32 μ_v carries an absolute u, so √(1 − μ_v) would carry √u ≈ 2.4·10⁻⁴ near normal
    incidence; ‖n − v‖ carries u."""
    import drjit as dr

    mu = dot(n, v)
    xv = (v[0] - mu * n[0], v[1] - mu * n[1], v[2] - mu * n[2])
    xn = dr.sqrt(dot(xv, xv))
    ok = xn > 1e-9
    fb = _perp_dr(n)
    inv = 1.0 / dr.select(ok, xn, 1.0)
    x_axis = tuple(dr.select(ok, xv[i] * inv, fb[i]) for i in range(3))
    d = (n[0] - v[0], n[1] - v[1], n[2] - v[2])
    return x_axis, _cross(n, x_axis), mu, dr.sqrt(dot(d, d)) * (1.0 / np.sqrt(2.0))  # type: ignore[return-value]


def table_row(tab: Table, alpha: float) -> np.ndarray:
    """(size, 6): the table interpolated in roughness √α (per light: numpy set-up), columns m⁻¹₀₀, m⁻¹₀₂, m⁻¹₁₁,
    m⁻¹₂₀, E, E_f along x = √(1 − cos θ_v)."""
    n = tab.size
    fr = float(np.clip(np.sqrt(alpha), 0.0, 1.0)) * (n - 1)
    i0 = min(int(np.floor(fr)), n - 2)
    tr = fr - i0
    a = np.concatenate([tab.m_inv.reshape(n, n, 4), tab.norm[..., None], tab.fresnel[..., None]], axis=-1)
    return (1 - tr) * a[i0] + tr * a[i0 + 1]


def ltc_integral_dr(light: Mapping[str, Any], alpha: float, points: np.ndarray, normals: np.ndarray,
                    views: np.ndarray, who: str = "ltc", table: Table | None = None) -> tuple[Any, Any, Any]:
    """(∫_light D_ltc dω, E, E_f) per receiver as drjit arrays of the active dtype: the table row at √α (numpy
    set-up), then per receiver the frame, the bilinear lookup in x (a gather), the polygon in the frame transformed
    by M⁻¹ and its clipped form factor (:func:`form_factor_dr`); zero behind a one-sided light or for n·v ≤ 0."""
    tab = table or load_table()
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    kpoly = precision.constants_dr(polygon_constants(light, pts, who))
    shape = light.get("shape")
    kfront = None if shape in ("sphere", "tube") else precision.constants_dr(_front_constants(light))
    return _ltc_integral(shape, kpoly, kfront, table_row(tab, alpha).T.ravel(), None, tab.size, pts, normals, views)


def ltc_integral_many_dr(lights: Sequence[Mapping[str, Any]], alphas: Sequence[float], points: np.ndarray,
                         normals: np.ndarray, views: np.ndarray, who: str = "ltc", table: Table | None = None
                         ) -> tuple[Any, Any, Any]:
    """:func:`ltc_integral_dr` with a light and an α per receiver (M lights of one shape, M α, M receivers), in one
    drjit evaluation: receiver m's numbers are those :func:`ltc_integral_dr` gives for (lights[m], alphas[m]) and
    receiver m alone — the same operations on the same values, the light's numbers and the table rows read per
    receiver (the rows of the distinct α side by side, an offset per receiver) instead of once per call."""
    tab = table or load_table()
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    m = len(pts)
    shapes = {light.get("shape") for light in lights}
    if len(lights) != m or len(alphas) != m or len(shapes) != 1:
        raise ValidateError(f"technique '{who}' (specular_arealight): ltc_integral_many_dr needs one light and one α "
                            f"per receiver, all of one shape (got {len(lights)} lights of shapes "
                            f"{sorted(map(str, shapes))}, {len(alphas)} α, {m} receivers)")
    shape = shapes.pop()
    kpoly = precision.packed_to_dr(*np.stack([polygon_constants(light, pts[i:i + 1], who)
                                              for i, light in enumerate(lights)]).T)
    kfront = None if shape in ("sphere", "tube") else precision.packed_to_dr(
        *np.stack([_front_constants(light) for light in lights]).T)
    distinct = sorted(set(float(a) for a in alphas))
    rows = np.concatenate([table_row(tab, a).T.ravel() for a in distinct])
    offsets = np.array([distinct.index(float(a)) for a in alphas], dtype=np.uint32) * np.uint32(6 * tab.size)
    return _ltc_integral(shape, kpoly, kfront, rows, offsets, tab.size, pts, normals, views)


def _front_constants(light: Mapping[str, Any]) -> np.ndarray:
    """A one-sided light's centre and normal (6), for the receiver-in-front test."""
    return np.r_[np.asarray(light.get("center"), dtype=np.float64),
                 np.asarray(light.get("normal", (0.0, 0.0, 0.0)), dtype=np.float64)]


def _ltc_integral(shape: str, kpoly: list[Any], kfront: list[Any] | None, rows_np: np.ndarray,
                  offsets: np.ndarray | None, size_t: int, pts: np.ndarray, normals: np.ndarray, views: np.ndarray
                  ) -> tuple[Any, Any, Any]:
    """The drjit part of :func:`ltc_integral_dr`: ``rows_np`` the table rows (:func:`table_row`, column-major, one
    block of 6·size per α), ``offsets`` per receiver the start of its α's block (None: one block), ``kpoly`` the
    polygon's numbers (:func:`polygon_dr`), ``kfront`` a one-sided light's centre and normal (None: none)."""
    import drjit as dr

    col = precision.packed_to_dr(*pts.T, *unit(normals).T, *unit(views).T)
    p, n, v = (col[0], col[1], col[2]), unit_dr((col[3], col[4], col[5])), unit_dr((col[6], col[7], col[8]))
    x_axis, y_axis, mu, x = local_frames_dr(n, v)
    rows = precision.to_dr(rows_np)  # column-major: entry c of node j at c·size + j
    dr.make_opaque(rows)
    fx = dr.clip(x, 0.0, 1.0) * float(size_t - 1)
    j0 = dr.minimum(dr.floor(fx), float(size_t - 2))
    tx = fx - j0
    u = precision.uint_type()
    j = u(j0)
    if offsets is not None:
        j = j + u(offsets)
    ft = precision.float_type()
    m00, m02, m11, m20, norm, fres = (dr.lerp(dr.gather(ft, rows, j + c * size_t),
                                              dr.gather(ft, rows, j + c * size_t + 1), tx) for c in range(6))
    poly = []
    for w in polygon_dr(shape, kpoly, p):
        lx, ly, lz = dot(x_axis, w), dot(y_axis, w), dot(n, w)
        poly.append((dr.fma(m02, lz, m00 * lx), m11 * ly, dr.fma(m20, lx, lz)))
    ff = form_factor_dr(poly)
    front = mu > 0.0
    if kfront is not None:
        k = kfront
        front &= ((k[0] - p[0]) * k[3] + (k[1] - p[1]) * k[4] + (k[2] - p[2]) * k[5]) < 0.0
    return dr.select(front, ff, 0.0), norm, fres


def ltc_integral(light: Mapping[str, Any], alpha: float, points: np.ndarray, normals: np.ndarray,
                 views: np.ndarray, who: str = "ltc", table: Table | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`ltc_integral_dr` as (N,) float64 numpy arrays (∫_light D_ltc dω, E, E_f)."""
    import drjit as dr

    ff, norm, fres = ltc_integral_dr(light, alpha, points, normals, views, who, table)
    dr.eval(ff, norm, fres)
    n = len(np.asarray(points).reshape(-1, 3))
    return precision.to_np(ff, (n,)), precision.to_np(norm, (n,)), precision.to_np(fres, (n,))


def ltc_integral_many(lights: Sequence[Mapping[str, Any]], alphas: Sequence[float], points: np.ndarray,
                      normals: np.ndarray, views: np.ndarray, who: str = "ltc", table: Table | None = None
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`ltc_integral_many_dr` as (M,) float64 numpy arrays (∫_light D_ltc dω, E, E_f)."""
    import drjit as dr

    ff, norm, fres = ltc_integral_many_dr(lights, alphas, points, normals, views, who, table)
    dr.eval(ff, norm, fres)
    m = len(np.asarray(points).reshape(-1, 3))
    return precision.to_np(ff, (m,)), precision.to_np(norm, (m,)), precision.to_np(fres, (m,))


@specular_arealight.register("ltc", "Linearly Transformed Cosines (Heitz et al. 2016), GGX table fitted here "
                             "(scripts/fit_ltc.py); disc as an equal-area 64-gon, sphere as its silhouette disc, tube "
                             "as its silhouette stadium",
                             shapes=SHAPES)
def ltc(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
        views: np.ndarray) -> np.ndarray:
    """L_o = L_e F (F₀ E + (1 − F₀) E_f) per channel ([1] §5.2), in the family's dtype (:func:`ltc_integral_dr`)."""
    alpha, f0 = brdf_params(brdf, "ltc")
    ff, norm, fres = ltc_integral_dr(light, alpha, np.asarray(points, dtype=np.float64), normals, views)
    k = precision.constants_dr(np.r_[float(light.get("radiance", 1.0)), f0])
    return _ltc_radiance(k, ff, norm, fres, len(np.asarray(points).reshape(-1, 3)))


def ltc_many(lights: Sequence[Mapping[str, Any]], brdfs: Sequence[Mapping[str, Any]], points: np.ndarray,
             normals: np.ndarray, views: np.ndarray) -> np.ndarray:
    """:func:`ltc` with a light and a brdf per receiver (M of each, the lights of one shape) in one drjit
    evaluation (:func:`ltc_integral_many_dr`): row m equals ``ltc(lights[m], brdfs[m], receiver m)``. Call it with
    the family's precision active (:func:`~validate.local_models.precision.family_precision`), as
    :meth:`~validate.local_models.registry.Family.call` does for :func:`ltc`."""
    params = [brdf_params(b, "ltc") for b in brdfs]
    pts = np.asarray(points, dtype=np.float64)
    ff, norm, fres = ltc_integral_many_dr(lights, [a for a, _ in params], pts, normals, views)
    k = precision.packed_to_dr(*np.stack([np.r_[float(light.get("radiance", 1.0)), f0]
                                          for light, (_, f0) in zip(lights, params, strict=True)]).T)
    return _ltc_radiance(k, ff, norm, fres, len(pts.reshape(-1, 3)))


def _ltc_radiance(k: list[Any], ff: Any, norm: Any, fres: Any, n: int) -> np.ndarray:
    """L_e F (F₀ E + (1 − F₀) E_f) per channel, k = (L_e, F₀ RGB) (drjit), as (n, 3) float64."""
    import drjit as dr

    lf = k[0] * ff
    out = [lf * dr.fma(k[1 + c], norm - fres, fres) for c in range(3)]
    dr.eval(*out)
    return precision.rgb_to_np(*out, n)


__all__ = ["specular_arealight", "fit_entry", "fit_entry_ad", "fit_entry_scipy", "fit_problem", "FitProblem",
           "l3_error_ad", "fit_quadrature", "ggx_cos", "ltc_density", "table_axes", "alpha_of",
           "pack", "load_table", "Table", "Entry", "clipped_form_factor", "form_factor_dr", "light_polygon_dr",
           "local_frames", "local_frames_dr", "ltc_integral", "ltc_integral_dr", "ltc_integral_many",
           "ltc_integral_many_dr", "ltc_many", "polygon_constants", "polygon_dr", "table_row", "brdf_params",
           "tube_polygon_dr"]
