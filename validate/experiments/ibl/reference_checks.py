"""Experiment ``ibl``, part 3: checks of the reference BSDFs and the independent bounds the claims use.

* **χ² of the modified-Phong sampling** (:func:`phong_chi2`): Mitsuba's ``ChiSquareTest`` with its
  ``BSDFAdapter`` (:func:`validate.reference.ibl_render.chi2_bsdf`), every exponent × view; the power
  check runs the same histogram against the pdf of exponent s + 1 (the classic off-by-one between
  the lobe cos^s and the inverse CDF u^{1/(s+1)}).
* **White furnace through the path integrator** (:func:`phong_furnace`): the sphere under a uniform
  unit environment returns the directional albedo, here from an independent Gauss–Legendre quadrature
  of the BRDF (:func:`validate.reference.ibl_render.phong_albedo`); the path integrator's MIS uses
  ``eval`` and ``pdf`` as well as ``sample``. Power: ``eval`` scaled by (s + 1)/(s + 2).
* **Split sum under a constant environment** (:func:`split_sum_constant`): P_α ≡ 1, so the technique
  returns F0·A + B of its DFG table; at the table's cell centres (no interpolation) it must equal
  Mitsuba's ``roughconductor`` albedo from the same furnace. The table's own quadrature error is
  measured by refining it (4× the Hammersley points) and allowed for.
* **Phong map at normal incidence** (:func:`phong_bound`): a per-pixel error bound from textbook
  theorems, computed from the environment — not the module's documented 2 %:

  - bilinear interpolation of f on a grid of spacing h errs by ≤ h²/8 (|f_xx| + |f_yy|) [1]; the map
    is sampled in face coordinates (spacing h = 2/N), where θ = atan x gives |f_xx| ≤ |f_θθ| + 0.65|f_θ|
    (|θ'| ≤ 1, |θ''| ≤ 3√3/8 = 0.65). For P(r) = ∫ L K_m(r·ω) dω (m = s + 1, K_m(c) = (m + 1)/2π c^m),
    |∂_θ P| ≤ ∫ L (m + 1)/2π · m c^{m−1} √(1 − c²) and |∂²_θ P| ≤ ∫ L (m + 1)/2π · m ((m − 1) c^{m−2}
    (1 − c²) + c^m) (differentiating K(r(t)·ω) twice along a great circle, |u·ω| ≤ √(1 − c²));
  - the view term: at v ≠ n the BRDF weights ω by (s + 2)/2π cos^s α · cos θ_ω, the map by
    (s + 2)/2π cos^{s+1} α, and |cos θ_ω − cos α| ≤ θ_v sin(α + θ_v) ≤ θ_v (√(1 − c²) + θ_v) since
    |θ_ω − α| ≤ θ_v (triangle inequality on the sphere); directions below the horizon that the map still
    counts have cos α ≤ sin θ_v.

  The integrals are zonal convolutions of the environment (ratio estimator over texel nodes), evaluated
  at each crop pixel's reflection vector: U(p) = (h²/4)(B₂ + 0.65 B₁) + θ_v B_v + B_h. The claim
  compares Σ_p |Y(A) − Y(R)| with Σ_p Y(U).

References
  [1] E. Süli, D. Mayers, "An Introduction to Numerical Analysis", CUP 2003, Thm 6.2 and §6.3 (linear
      interpolation error h²/8 max|f''|; its tensor-product extension).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...local_models import specular
from ...local_models.irradiance import irradiance_map as im
from ...local_models.specular import prefiltered_specular as ps
from ...local_models.specular import split_sum as ss
from ...local_models.specular.common import block_deg_for_width, reflect
from ...reference import ibl_render as rr
from ...scenes import latlong
from ...stats import sidak_alpha, sidak_critical, t_to_z
from .settings import Settings

ALPHA = 0.01  # family-wise significance level of every statistical claim here
DFG_REFINE = 4  # the table's error is estimated against 4× its Hammersley points
FACE_CURVATURE = 3.0 * math.sqrt(3.0) / 8.0  # max |d²/dx² atan x| = 0.65 (at x = 1/√3)


@dataclass
class Chi2Check:
    exponents: list[float]
    cos_views: list[float]
    p_values: list[float]
    p_values_off_by_one: list[float]
    level: float  # Šidák per-test level α₁

    @property
    def min_p(self) -> float:
        return min(self.p_values)


def phong_chi2(st: Settings) -> Chi2Check:
    """χ² of ``modphong``'s ``sample`` against its ``pdf`` (and, for power, against the pdf of s + 1)."""
    cases = [(s, mu) for s in st.chi2_exponents for mu in st.chi2_cos_views]
    p = [rr.chi2_bsdf({"type": rr.PHONG_PLUGIN, "exponent": s}, mu, samples=st.chi2_samples).p_value
         for s, mu in cases]
    q = [rr.chi2_bsdf({"type": rr.PHONG_PLUGIN, "exponent": s}, mu, {"type": rr.PHONG_PLUGIN, "exponent": s + 1.0},
                      samples=st.chi2_samples).p_value for s, mu in cases]
    return Chi2Check([c[0] for c in cases], [c[1] for c in cases], p, q, sidak_alpha(ALPHA, len(cases)))


@dataclass
class ZCheck:
    """Per test: value, reference, standard error (P − 1 dof), a deterministic allowance; |z| and the bound."""

    labels: list[str]
    measured: np.ndarray
    expected: np.ndarray
    stderr: np.ndarray
    allowance: np.ndarray
    dof: int
    perturbed: np.ndarray  # the measured values under the power check's perturbation

    def z(self, measured: np.ndarray | None = None) -> np.ndarray:
        m = self.measured if measured is None else measured
        excess = np.maximum(np.abs(m - self.expected) - self.allowance, 0.0)
        return np.abs(t_to_z(excess / np.maximum(self.stderr, 1e-300), self.dof))

    @property
    def critical(self) -> float:
        return sidak_critical(len(self.labels), ALPHA)


def phong_furnace(st: Settings) -> ZCheck:
    """Path-traced white furnace of ``modphong`` vs the quadrature albedo, every exponent × view."""
    labels, meas, exp, se, pert = [], [], [], [], []
    mus = np.asarray(st.furnace_cos_views)
    for s in st.chi2_exponents:
        albedo = np.array([rr.phong_albedo(s, m) for m in mus])
        f = rr.furnace({"type": rr.PHONG_PLUGIN, "exponent": s}, mus, spp=st.furnace_spp)
        g = rr.furnace({"type": rr.PHONG_PLUGIN, "exponent": s, "eval_scale": (s + 1.0) / (s + 2.0)}, mus,
                       spp=st.furnace_spp)
        labels += [f"s = {s:g}, μ = {m:g}" for m in mus]
        meas.append(f.mean)
        exp.append(albedo)
        se.append(f.stderr)
        pert.append(g.mean)
    cat = np.concatenate
    return ZCheck(labels, cat(meas), cat(exp), cat(se), np.zeros(len(labels)), 7, cat(pert))


def dfg_cell(i: int, j: int, size: int = ss.DFG_SIZE) -> tuple[float, float]:
    """(μ, α) at the centre of DFG-table cell (i, j), where the bilinear lookup returns the stored value."""
    return (i + 0.5) / size, (j + 0.5) / size


def split_sum_constant(st: Settings) -> ZCheck:
    """The ``split_sum_ggx`` technique (F0 = 1) under a constant unit environment at DFG cell centres vs
    Mitsuba's ``roughconductor`` in the path-traced furnace; allowance = |table − refined table|."""
    ones = np.ones((16, 32, 3), dtype=np.float32)
    labels, meas, exp, se, allow = [], [], [], [], []
    for alpha in sorted({dfg_cell(0, j)[1] for _, j in st.dfg_cells}):
        mus = np.array([dfg_cell(i, j)[0] for i, j in st.dfg_cells if dfg_cell(i, j)[1] == alpha])
        n = np.tile([0.0, 0.0, 1.0], (len(mus), 1))
        v = np.stack([np.sqrt(1 - mus ** 2), np.zeros_like(mus), mus], -1)
        split = specular.call("split_sum_ggx", ones, {"model": "ggx", "alpha": alpha}, n, v)[:, 0]
        a, b = ss.dfg_terms(mus, alpha, ss.DFG_SAMPLES * DFG_REFINE)
        f = rr.furnace({"type": "roughconductor", "distribution": "ggx", "alpha": alpha}, mus, spp=st.furnace_spp)
        labels += [f"α = {alpha:g}, μ = {m:g}" for m in mus]
        meas.append(split)
        exp.append(f.mean)
        se.append(f.stderr)
        allow.append(np.abs(split - (a + b)))
    cat = np.concatenate
    m, e = cat(meas), cat(exp)
    return ZCheck(labels, m, e, cat(se), cat(allow), 7, m / 1.01)  # power: Mitsuba's albedo 1 % higher


# ---------------------------------------------------------------------------------------------
# Phong map at normal incidence: the independent bound
# ---------------------------------------------------------------------------------------------

def _kernel_integral(kernel: ps.Kernel, nodes: int = 1 << 17) -> float:
    """∫ K dω = 2π ∫₀^π K(cos θ) sin θ dθ by the midpoint rule on ``nodes`` intervals (step 2.4·10⁻⁵ rad,
    ≪ the narrowest lobe here, 1/√1001 = 0.03 rad)."""
    th = (np.arange(nodes) + 0.5) * (math.pi / nodes)
    return float(2.0 * math.pi * np.sum(kernel(np.cos(th)) * np.sin(th)) * (math.pi / nodes))


def _zonal(nodes: im.EnvironmentNodes, dirs: np.ndarray, kernel: ps.Kernel) -> np.ndarray:
    return im.convolve_zonal(nodes, dirs, kernel, _kernel_integral(kernel))


def phong_bound(radiance: np.ndarray, s: float, normals: np.ndarray, views: np.ndarray) -> np.ndarray:
    """U(p) (K, 3): the per-pixel bound on |map of exponent s + 1 − modified-Phong L_o| (module doc)."""
    m = s + 1.0
    cn = (m + 1.0) / (2.0 * math.pi)
    h = 2.0 / ps.phong_face_size(m)

    def k1(c: np.ndarray) -> np.ndarray:
        c = np.clip(np.asarray(c, dtype=np.float64), 0.0, 1.0)
        return np.where(c > 0, cn * m * c ** (m - 1.0) * np.sqrt(1.0 - c * c), 0.0)

    def k2(c: np.ndarray) -> np.ndarray:
        c = np.clip(np.asarray(c, dtype=np.float64), 0.0, 1.0)
        return np.where(c > 0, cn * m * ((m - 1.0) * c ** (m - 2.0) * (1.0 - c * c) + c ** m), 0.0)

    n = np.asarray(normals, dtype=np.float64)
    v = np.asarray(views, dtype=np.float64)
    theta_v = np.arccos(np.clip(np.sum(n * v, axis=-1), -1.0, 1.0))[:, None]
    tmax = float(theta_v.max())

    def kv(c: np.ndarray) -> np.ndarray:  # the view term, per unit θ_v
        c = np.clip(np.asarray(c, dtype=np.float64), 0.0, 1.0)
        return np.where(c > 0, cn * c ** s * (np.sqrt(1.0 - c * c) + tmax), 0.0)

    def kh(c: np.ndarray) -> np.ndarray:  # below the horizon but inside the map's lobe
        c = np.clip(np.asarray(c, dtype=np.float64), 0.0, 1.0)
        return np.where((c > 0) & (c <= math.sin(tmax)), cn * c ** m, 0.0)

    sin_tmax, same_power = math.sin(tmax), (m - 1.0) == s

    def fused(c: np.ndarray) -> list[np.ndarray]:
        """[k2, k1, kv, kh (when θ_v > 0)] at once, sharing c, its powers and √(1 − c²): the same operations
        on the same values as the four functions above, so the same bits."""
        c = np.clip(np.asarray(c, dtype=np.float64), 0.0, 1.0)
        pos = c > 0
        p_m1, p_m, omc = c ** (m - 1.0), c ** m, 1.0 - c * c
        p_s = p_m1 if same_power else c ** s
        sq = np.sqrt(omc)
        out = [np.where(pos, cn * m * ((m - 1.0) * c ** (m - 2.0) * omc + p_m), 0.0),
               np.where(pos, cn * m * p_m1 * sq, 0.0),
               np.where(pos, cn * p_s * (sq + tmax), 0.0)]
        if tmax > 0:
            out.append(np.where(pos & (c <= sin_tmax), cn * p_m, 0.0))
        return out

    nodes = im.environment_nodes(radiance, block_deg_for_width(ps.phong_lobe_width(m)))
    r = reflect(n, v)
    kernels = [k2, k1, kv] + ([kh] if tmax > 0 else [])
    z = im.convolve_zonal_dense_many(nodes, r, fused, [_kernel_integral(k) for k in kernels])
    interp = 0.25 * h * h * (z[0] + FACE_CURVATURE * z[1])
    horizon = z[3] if tmax > 0 else 0.0
    return interp + theta_v * z[2] + horizon


def luminance_sum(x: np.ndarray) -> float:
    return float(np.sum(latlong.luminance(x)))
