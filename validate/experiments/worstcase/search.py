"""Worst-case lighting search: ascent over the lighting family of :mod:`.lighting`, with restarts.

Objective: a metric of :mod:`.errors` (default ``flux_luminance.max``) over a fixed set of N_s Fibonacci
normals, for the map rasterised from θ at H×2H, truth = the texel quadrature of that map.

* **drjit AD** (techniques with a drjit version in :mod:`.dr_models`, on an AD variant): the map, the
  technique and the truth are one drjit graph; the max over normals is smoothed to
  m + τ log Σ_n exp((e(n) − m)/τ) (m = the detached max, τ = :data:`TAU` · m: ≥ the max, ≤ max + τ log N_s)
  and ``dr.backward`` gives ∂/∂θ; one forward + backward pass counts as one evaluation of the budget.
* **SPSA** (any other technique — black boxes, plug-ins, engines; Spall 1992 [1]): the gradient estimate
  (f(θ + cΔ) − f(θ − cΔ)) / (2c) · Δ with a Rademacher Δ, two evaluations of the registered technique per
  step, c = :data:`SPSA_STEP`; the true (unsmoothed) max is the objective.

Both feed Adam [2] (ascent, lr :data:`LEARNING_RATE`); the budget of evaluations is split evenly over the
restarts, each from :meth:`.lighting.Family.random` with seed (seed, restart). **Random search** (the power
check of the claims) spends the same total budget on independent draws from that distribution.

Every reported number is recomputed with the registered technique: the best θ of each restart, its map,
then the worst normal refined off the search set (:func:`.errors.worst_normal`). Uncertainty: the same θ
rasterised at 2H (the truth's quadrature resolution: |e(2H) − e(H)|); the spread over restarts is reported
beside it.

References
  [1] J. C. Spall, "Multivariate stochastic approximation using a simultaneous perturbation gradient
      approximation", IEEE Trans. Automatic Control 37(3), 1992.
  [2] D. P. Kingma, J. Ba, "Adam: a method for stochastic optimization", ICLR 2015.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...metrics.irradiance_error import RELATIVE_FLOOR
from ...scenes.latlong import fibonacci_sphere
from . import dr_models
from .errors import Technique, check_metric, errors_at, registered, worst_normal
from .lighting import LUMINANCE, Family, Raster, describe

LEARNING_RATE = 0.3  # measured on sh9 at H = 16: 2 of 3 starts reach 99.9 % of 3/32 in 100 steps (0.1: 0 of 3)
TAU = 0.01  # smooth-max temperature relative to the current max
SPSA_STEP = 0.05
ADAM_BETAS = (0.9, 0.999)


@dataclass(frozen=True)
class SearchSettings:
    height: int = 32
    normals: int = 400
    budget: int = 400
    restarts: int = 4
    seed: int = 1234
    family: Family = Family()


@dataclass
class SearchResult:
    technique: str
    metric: str
    method: str
    value: float  # registered technique, best restart, refined normal, at H
    value_2x: float  # the same θ rasterised at 2H
    restart_values: list[float]
    random_value: float  # random search, same budget
    evaluations: int
    normal: list[float]
    wall_s: float
    theta: np.ndarray = field(repr=False)
    radiance: np.ndarray = field(repr=False)
    family: Family = field(default=Family(), repr=False)

    @property
    def uncertainty(self) -> float:
        """Quadrature resolution of the truth: |e(2H) − e(H)| for the same lighting."""
        return abs(self.value_2x - self.value)

    @property
    def lighting(self) -> str:
        """The worst lighting found, in words (:func:`.lighting.describe`)."""
        return describe(self.family, self.theta, self.radiance.shape[0])

    def to_json(self) -> dict[str, Any]:
        return {"technique": self.technique, "metric": self.metric, "method": self.method, "value": self.value,
                "lighting": self.lighting,
                "value_2x": self.value_2x, "uncertainty": self.uncertainty, "restart_values": self.restart_values,
                "random_value": self.random_value, "evaluations": self.evaluations, "normal": self.normal,
                "wall_s": self.wall_s}


def has_ad(name: str) -> bool:
    import drjit as dr
    import mitsuba as mi

    return name in dr_models.MODELS and bool(dr.is_diff_v(mi.Float))


@dataclass(frozen=True)
class Quadrature:
    """K[n, j] = max(0, n·ω_j) ΔΩ_j laid out both ways for gathers and block sums (no scatter): ``rows``
    (N·H·W, n-major) gives E = K L, ``cols`` (H·W·N, j-major) gives Kᵀ ∂E. A plain object: drjit does not
    traverse it when it is handed to the custom operation."""

    rows: Any
    cols: Any
    j: Any  # texel index of each entry of ``rows``
    n: Any  # normal index of each entry of ``cols``
    normals: int
    texels: int

    @staticmethod
    def of(kernel: np.ndarray) -> Quadrature:
        import mitsuba as mi

        n, hw = kernel.shape
        return Quadrature(mi.Float(kernel.reshape(-1).astype(np.float32)),
                          mi.Float(kernel.T.reshape(-1).astype(np.float32)),
                          mi.UInt32(np.tile(np.arange(hw, dtype=np.uint32), n)),
                          mi.UInt32(np.tile(np.arange(n, dtype=np.uint32), hw)), n, hw)


@functools.cache
def quadrature_op() -> type:
    """The truth E_c(n) = Σ_j K[n, j] L_jc as a drjit ``CustomOp``: forward K L, adjoint Kᵀ ∂E, each a gather
    and a block sum. Differentiated automatically, the gather's adjoint is a scatter-add of N·H·W atomics
    (819 200 per channel at N = 400, H = 32): ¾ of an AD evaluation; the transposed block sum costs what the
    forward pass does, and its float sums do not depend on the order of threads."""
    import drjit as dr
    import mitsuba as mi

    class QuadratureOp(dr.CustomOp):
        def eval(self, r: Any, g: Any, b: Any, q: Quadrature) -> tuple[Any, Any, Any]:
            self.q = q
            return self.apply((r, g, b), q.rows, q.j, q.texels)

        @staticmethod
        def apply(xs: Any, weights: Any, index: Any, block: int) -> tuple[Any, Any, Any]:
            out = tuple(dr.block_sum(weights * dr.gather(mi.Float, x, index), block) for x in xs)
            dr.eval(out)
            return out

        def forward(self) -> None:
            self.set_grad_out(self.apply([self.grad_in(k) for k in "rgb"], self.q.rows, self.q.j, self.q.texels))

        def backward(self) -> None:
            back = self.apply(self.grad_out(), self.q.cols, self.q.n, self.q.normals)
            for c, k in enumerate("rgb"):
                self.set_grad_in(k, back[c])

        def name(self) -> str:
            return "quadrature truth"

    return QuadratureOp


class AdObjective:
    """θ ↦ (max over the search normals, ∂ smooth max / ∂θ) through drjit for a :mod:`.dr_models` technique."""

    def __init__(self, name: str, raster: Raster, normals: np.ndarray, base: str) -> None:
        import mitsuba as mi

        self.model, self.raster, self.base = dr_models.MODELS[name], raster, base
        self.normals = [mi.Float(normals[:, i].astype(np.float32)) for i in range(3)]
        d, dw = (np.stack([np.array(c) for c in raster.dirs], axis=1), np.array(raster.dw))
        self.quadrature = Quadrature.of(np.maximum(normals @ d.T, 0.0) * dw[None, :])

    def truth(self, rad: list[Any]) -> list[Any]:
        """E_c = K L_c, a custom drjit operation (:func:`quadrature_op`)."""
        import drjit as dr

        return list(dr.custom(quadrature_op(), rad[0], rad[1], rad[2], self.quadrature))

    def errors(self, rad: list[Any], approx: list[Any], truth: list[Any]) -> list[Any]:
        import drjit as dr

        flux = [dr.sum(L * self.raster.dw) for L in rad]
        if self.base == "flux_rgb":
            return [dr.abs(approx[c] - truth[c]) / flux[c] for c in range(3)]
        ya = sum(LUMINANCE[c] * approx[c] for c in range(3))
        yt = sum(LUMINANCE[c] * truth[c] for c in range(3))
        if self.base == "flux_luminance":
            return [dr.abs(ya - yt) / sum(LUMINANCE[c] * flux[c] for c in range(3))]
        mask = dr.detach(yt) >= RELATIVE_FLOOR * dr.max(dr.detach(yt))
        return [dr.select(mask, dr.abs(ya - yt) / dr.maximum(yt, 1e-30), 0.0)]

    def value(self, theta_np: np.ndarray) -> float:
        """The forward pass only (the random search's objective)."""
        import drjit as dr
        import mitsuba as mi

        with dr.suspend_grad():
            rad = self.raster.radiance(mi.Float(theta_np.astype(np.float32)))
            dr.eval(rad)
            approx = self.model((rad, self.raster.dirs, self.raster.dw), self.normals)
            dr.eval(approx)
            e = self.errors(rad, approx, self.truth(rad))
            return float(max(np.max(np.array(ec)) for ec in e))

    def __call__(self, theta_np: np.ndarray) -> tuple[float, np.ndarray]:
        import drjit as dr
        import mitsuba as mi

        theta = mi.Float(theta_np.astype(np.float32))
        dr.enable_grad(theta)
        # evaluated stage by stage, with the changing max passed as opaque values: every iteration then
        # reuses the same compiled kernels (a Python float would be baked into a new kernel each time)
        rad = self.raster.radiance(theta)
        dr.eval(rad)
        approx = self.model((rad, self.raster.dirs, self.raster.dw), self.normals)
        dr.eval(approx)
        e = self.errors(rad, approx, self.truth(rad))
        dr.eval(e)
        m_val = float(max(np.max(np.array(ec)) for ec in e))
        m, tau = dr.opaque(mi.Float, m_val), dr.opaque(mi.Float, TAU * m_val + 1e-12)
        obj = m + tau * dr.log(sum(dr.sum(dr.exp((ec - m) / tau)) for ec in e))
        dr.backward(obj)
        return m_val, np.array(dr.grad(theta), dtype=np.float64)


def numpy_objective(fn: Technique, raster: Raster, normals: np.ndarray, base: str) -> Callable[[np.ndarray], float]:
    def f(theta: np.ndarray) -> float:
        e = errors_at(fn, raster.numpy(theta), normals, base)
        return float(e.max())
    return f


def adam_ascent(step: Callable[[np.ndarray], tuple[float, np.ndarray, int]], theta: np.ndarray,
                budget: int) -> tuple[np.ndarray, float, int]:
    """Adam on θ while evaluations remain; ``step(θ) → (value at θ, gradient, evaluations used)``.
    Returns (best θ seen, its value, evaluations)."""
    m, v = np.zeros_like(theta), np.zeros_like(theta)
    best, best_theta, used, t = -np.inf, theta.copy(), 0, 0
    while used < budget:
        val, g, n = step(theta)
        used += n
        if val > best:
            best, best_theta = val, theta.copy()
        if not np.all(np.isfinite(g)):
            break
        t += 1
        m = ADAM_BETAS[0] * m + (1 - ADAM_BETAS[0]) * g
        v = ADAM_BETAS[1] * v + (1 - ADAM_BETAS[1]) * g * g
        theta = theta + LEARNING_RATE * (m / (1 - ADAM_BETAS[0] ** t)) / (np.sqrt(v / (1 - ADAM_BETAS[1] ** t)) + 1e-8)
    return best_theta, best, used


def spsa_step(f: Callable[[np.ndarray], float], rng: np.random.Generator
              ) -> Callable[[np.ndarray], tuple[float, np.ndarray, int]]:
    def step(theta: np.ndarray) -> tuple[float, np.ndarray, int]:
        delta = rng.choice([-1.0, 1.0], size=theta.shape)
        fp, fm = f(theta + SPSA_STEP * delta), f(theta - SPSA_STEP * delta)
        return max(fp, fm), (fp - fm) / (2 * SPSA_STEP) * delta, 2
    return step


def random_search(f: Callable[[np.ndarray], float], fam: Family, budget: int, seed: int) -> tuple[np.ndarray, float]:
    rng = np.random.default_rng([seed, 9999])
    best, best_theta = -np.inf, None
    for _ in range(budget):
        th = fam.random(rng)
        val = f(th)
        if val > best:
            best, best_theta = val, th
    return best_theta, best


def search(name: str, s: SearchSettings, metric: str = "flux_luminance.max", fn: Technique | None = None,
           with_random: bool = True) -> SearchResult:
    """The worst lighting of technique ``name`` for ``metric`` (module docstring).

    drjit runs on one thread meanwhile: the adjoint of a gather is an atomic scatter-add, whose float sums
    depend on the threads' order; one thread makes the gradients, hence the restarts, reproducible (measured:
    a 120-step restart of zh3_hallucinated ended at 23.5 %, 23.9 % or 24.9 % on two threads)."""
    from ...backend import drjit_threads

    with drjit_threads(1):
        return _search(name, s, metric, fn, with_random)


def _search(name: str, s: SearchSettings, metric: str, fn: Technique | None, with_random: bool) -> SearchResult:
    base, stat = check_metric(metric)
    if stat != "max":
        raise ValidateError(f"worst case search: metric {metric!r}: the search maximises a .max metric")
    if s.budget < 2 * s.restarts:
        raise ValidateError(f"worst case search: budget {s.budget} must allow 2 evaluations per restart ({s.restarts})")
    t0 = time.perf_counter()
    ad = fn is None and has_ad(name)  # a caller's own function (a perturbation) is a black box
    fn = fn or registered(name)
    raster, normals = Raster(s.family, s.height), fibonacci_sphere(s.normals)
    f_np = numpy_objective(fn, raster, normals, base)
    if ad:
        obj = AdObjective(name, raster, normals, base)
    finals, thetas, used = [], [], 0
    for r in range(s.restarts):
        rng = np.random.default_rng([s.seed, r])
        th0 = s.family.random(rng)
        step = (lambda th: (*obj(th), 1)) if ad else spsa_step(f_np, rng)
        th, _, n = adam_ascent(step, th0, s.budget // s.restarts)
        used += n
        thetas.append(th)
        finals.append(worst_normal(fn, raster.numpy(th), metric)[0])
    k = int(np.argmax(finals))
    radiance = raster.numpy(thetas[k])
    value, normal = worst_normal(fn, radiance, metric)
    value_2x = worst_normal(fn, Raster(s.family, 2 * s.height).numpy(thetas[k]), metric)[0]
    rnd = np.nan
    if with_random:
        th_r, _ = random_search(obj.value if ad else f_np, s.family, s.budget, s.seed)
        rnd = worst_normal(fn, raster.numpy(th_r), metric)[0]
    method = "drjit AD (Adam)" if ad else "SPSA (2 evaluations per step, Adam)"
    return SearchResult(name, metric, method, value, value_2x, [float(v) for v in finals], float(rnd), used,
                        [float(x) for x in normal], round(time.perf_counter() - t0, 2), thetas[k], radiance, s.family)
