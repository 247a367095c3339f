"""Fits by automatic differentiation: drjit objectives minimised by scipy with drjit's exact derivatives.

An objective is written once in drjit on the active AD variant's 64-bit float (``mi.Float64`` of
``llvm_ad_rgb`` / ``cuda_ad_rgb``, chosen by :mod:`validate.backend`): it takes one width-1 array per
parameter and returns a width-1 value (:func:`minimize`) or a residual vector (:func:`least_squares`). The
derivatives come from drjit's AD, never from differences:

* :func:`value_and_grad` — reverse mode (``dr.backward``): ∂F/∂p_k for every k in one pass;
* :func:`residuals_and_jacobian` — forward mode (``dr.forward_to`` once per parameter): the columns
  ∂r/∂p_k of the Jacobian, for the trust-region Gauss–Newton of ``scipy.optimize.least_squares``.

The optimisers are scipy's: L-BFGS-B (Byrd, Lu, Nocedal, Zhu 1995 [1]) for :func:`minimize` (``jac=True``: value
and gradient from :func:`value_and_grad`), and the trust-region reflective least squares (Branch, Coleman, Li
1999 [2]) for :func:`least_squares` (``jac=``: the AD Jacobian). Parameters are optimised as u = p / scale
(``scale``: the size of each parameter), so one tolerance suits them all; bounds are scaled alike.

Parameter values enter the kernels as *opaque* arrays (``dr.opaque``), not literals, so every evaluation
reuses the same compiled kernel (a literal that changes per iteration would recompile it each time).

:func:`available` says whether the active variant has AD (``scalar_rgb`` has none: the callers then keep
their scipy fits).

References
  [1] R. H. Byrd, P. Lu, J. Nocedal, C. Zhu, "A limited memory algorithm for bound constrained optimization",
      SIAM J. Sci. Comput. 16(5), 1995.
  [2] M. A. Branch, T. F. Coleman, Y. Li, "A subspace, interior, and conjugate gradient method for large-scale
      bound-constrained minimization problems", SIAM J. Sci. Comput. 21(1), 1999.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..backend import init

Objective = Callable[[list[Any]], Any]


def available() -> bool:
    """True when the active Mitsuba variant is an AD one (``*_ad_*``)."""
    return "_ad_" in init().variant


def float64() -> Any:
    """The differentiable 64-bit dynamic float of the active AD variant (``mi.Float64``)."""
    import mitsuba as mi

    if not available():
        from ..errors import ValidateError

        raise ValidateError(f"variant {init().variant} has no automatic differentiation; the AD fits need an "
                            "*_ad_* variant (llvm_ad_rgb or cuda_ad_rgb)")
    return mi.Float64


def array(values: Any) -> Any:
    """A constant (non-differentiable) Float64 array of ``values`` (numpy, float64)."""
    return float64()(np.ascontiguousarray(np.asarray(values, dtype=np.float64).ravel()))


def _params(x: np.ndarray) -> list[Any]:
    import drjit as dr

    f64 = float64()
    return [dr.opaque(f64, float(v), 1) for v in x]


def _scalar(v: Any) -> float:
    import drjit as dr

    return float(dr.ravel(v).numpy()[0]) if dr.is_array_v(v) else float(v)


def value_and_grad(objective: Objective, x: Sequence[float]) -> tuple[float, np.ndarray]:
    """(F(x), ∇F(x)) with the gradient by drjit reverse-mode AD (``dr.backward``)."""
    import drjit as dr

    p = _params(np.asarray(x, dtype=np.float64))
    for q in p:
        dr.enable_grad(q)
    v = objective(p)
    dr.backward(v)
    return _scalar(dr.detach(v)), np.array([_scalar(dr.grad(q)) for q in p])


def residuals_and_jacobian(residuals: Objective, x: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """(r(x) (M,), J (M, K)) with J's columns ∂r/∂p_k by drjit forward-mode AD (one pass per parameter)."""
    import drjit as dr

    p = _params(np.asarray(x, dtype=np.float64))
    for q in p:
        dr.enable_grad(q)
    r = residuals(p)
    dr.eval(r)
    cols = []
    for q in p:
        dr.set_grad(q, 1.0)
        dr.forward_to(r, flags=dr.ADFlag.ClearInterior | dr.ADFlag.ClearInput)
        cols.append(dr.grad(r))
        dr.clear_grad(r)
    dr.eval(cols)  # the K tangent columns in one kernel launch
    return dr.detach(r).numpy().copy(), np.stack([c.numpy() for c in cols], axis=1)


@dataclass(frozen=True)
class Fit:
    """A fit's result: parameters, objective value (:func:`minimize`: F; :func:`least_squares`: ½ Σ r²),
    evaluations, and the optimiser's message."""

    x: np.ndarray
    fun: float
    evaluations: int
    message: str


def minimize(objective: Objective, x0: Sequence[float], bounds: Sequence[tuple[float | None, float | None]] | None
             = None, scale: Sequence[float] | None = None, gtol: float = 1e-10, ftol: float = 1e-15,
             maxiter: int = 2000, restarts: int = 4, method: str = "L-BFGS-B") -> Fit:
    """min F(p) by L-BFGS-B [1] on u = p / scale, value and gradient from :func:`value_and_grad`; F is divided by
    |F(x0)| so that ``gtol`` / ``ftol`` are relative to the starting misfit. Up to ``restarts`` restarts from the
    last point while one still lowers F by more than 10⁻¹² relative. ``method="BFGS"``: scipy's unbounded BFGS
    with the same gradient (``bounds`` must be None; ``ftol`` unused), whose Wolfe line search gets past kinks
    of a piecewise-smooth F where L-BFGS-B's line search can stop short."""
    from scipy.optimize import minimize as sp_minimize

    x0 = np.asarray(x0, dtype=np.float64)
    s = np.ones_like(x0) if scale is None else np.asarray(scale, dtype=np.float64)
    b = None if bounds is None else [(None if lo is None else lo / si, None if hi is None else hi / si)
                                     for (lo, hi), si in zip(bounds, s, strict=True)]

    f0 = abs(value_and_grad(objective, x0)[0]) or 1.0

    def fg(u: np.ndarray) -> tuple[float, np.ndarray]:
        v, g = value_and_grad(objective, u * s)
        return v / f0, g * s / f0

    u, evals, message = x0 / s, 1, ""
    best = fg(u)[0]
    for _ in range(restarts + 1):  # a restart drops L-BFGS's curvature memory (stalls in narrow valleys)
        if method == "BFGS":
            if b is not None:
                raise ValueError("BFGS takes no bounds")
            res = sp_minimize(fg, u, jac=True, method="BFGS", options={"gtol": gtol, "maxiter": maxiter})
        else:
            res = sp_minimize(fg, u, jac=True, method="L-BFGS-B", bounds=b,
                              options={"gtol": gtol, "ftol": ftol, "maxiter": maxiter, "maxcor": 20})
        evals, message = evals + int(res.nfev), str(res.message)
        gain = best - float(res.fun)
        if float(res.fun) <= best:
            u, best = res.x, float(res.fun)
        if gain <= 1e-12 * abs(best):
            break
    return Fit(u * s, best * f0, evals, message)


def least_squares(residuals: Objective, x0: Sequence[float], bounds: tuple[Sequence[float], Sequence[float]],
                  x_scale: Sequence[float]) -> Fit:
    """min ½ Σ r(p)² by scipy's trust-region reflective method [2] with the AD Jacobian
    (:func:`residuals_and_jacobian`; r alone, without AD, at the trial points)."""
    from scipy.optimize import least_squares as sp_least_squares

    def fun(p: np.ndarray) -> np.ndarray:
        import drjit as dr

        return dr.detach(residuals(_params(p))).numpy().copy()

    res = sp_least_squares(fun, np.asarray(x0, dtype=np.float64), jac=lambda p: residuals_and_jacobian(residuals, p)[1],
                           bounds=bounds, x_scale=np.asarray(x_scale, dtype=np.float64))
    return Fit(res.x, float(res.cost), int(res.nfev), str(res.message))
