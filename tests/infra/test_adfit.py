"""The drjit-AD fits (:mod:`validate.numerics.adfit`): each objective's AD derivative against a central finite
difference, and each AD fit the experiment uses reaching the scipy fit's residual on a small instance (same data,
same start).

Tolerances: the central difference with step h has truncation error O(h² f''') and rounding error
O(ε f / h); with h = 10⁻⁵ (relative to the parameter) both are ≤ 10⁻⁶ of the derivative for these smooth
objectives, so FD_REL = 10⁻⁵ leaves a margin. A wrong chain-rule factor (a factor 2, a missing 1/m11) is O(1).
RESIDUAL_TOL = 10⁻⁶ as in the bench (validate/bench/fits.py).
"""

from __future__ import annotations

import importlib
import math
from types import SimpleNamespace

import numpy as np
import pytest

from validate.experiments.lights import sweeps as sw
from validate.local_models.specular_arealight import ltc
from validate.numerics import adfit

um = importlib.import_module("validate.experiments.uberlight.compute")

FD_REL = 1e-5
RESIDUAL_TOL = 1e-6

pytestmark = pytest.mark.skipif(not adfit.available(), reason="the active variant has no AD")


def central_difference(f, x: np.ndarray, k: int, rel: float = 1e-5) -> float:
    h = rel * max(abs(x[k]), 1e-2)
    xp, xm = x.copy(), x.copy()
    xp[k] += h
    xm[k] -= h
    return (f(xp) - f(xm)) / (2 * h)


def assert_gradient(objective_ad, objective_np, x: np.ndarray) -> None:
    value, grad = adfit.value_and_grad(objective_ad, x)
    assert value == pytest.approx(objective_np(x), rel=1e-12)
    fd = np.array([central_difference(objective_np, x, k) for k in range(len(x))])
    assert np.allclose(grad, fd, rtol=FD_REL, atol=FD_REL * np.abs(fd).max()), (grad, fd)


def ltc_problem() -> ltc.FitProblem:
    return ltc.fit_problem(0.8, 0.25, (0.5, 0.45, -0.1, 0.05), n=12)  # a small quadrature: 2 × 144 nodes


def test_ltc_gradient_matches_finite_differences():
    prob = ltc_problem()
    assert_gradient(ltc.l3_error_ad(prob), prob.l3_error, np.array([0.52, 0.41, -0.12, 0.07]))


def test_ltc_ad_fit_reaches_nelder_mead():
    prob = ltc_problem()
    ad, nm = ltc.fit_entry_ad(prob), ltc.fit_entry_scipy(prob)
    assert prob.l3_error(np.array(ad.params)) <= prob.l3_error(np.array(nm.params)) * (1 + RESIDUAL_TOL)


def synthetic_barndoor(n: int = 600) -> tuple[SimpleNamespace, dict]:
    """Receivers at random light coordinates inside ±0.5 of the axis, U = 1/z², the reference the beam model of
    known parameters plus 1 % noise (seed 3)."""
    rng = np.random.default_rng(3)
    lc = np.column_stack([rng.uniform(-0.5, 0.5, n), rng.uniform(-0.4, 0.4, n), rng.uniform(0.8, 1.2, n)])
    u = 1.0 / lc[:, 2] ** 2
    truth = np.array([0.25, 0.15, 0.1, 0.08, 0.8, 40.0])
    ref = um.beam_model(lc, u, truth)
    ref = ref + 0.01 * ref.max() * rng.standard_normal(n)
    frame = SimpleNamespace(radiance=ref, peak=float(ref.max()))
    p0 = np.array([0.2, 0.12, 0.06, 0.06, 0.3, 30.0])
    prob = {"lc": lc, "u": u, "p0": p0, "bounds": (np.array([1e-3, 1e-3, 0, 0, 0.05, 3.0]),
                                                    np.array([2.0, 2, 2, 2, 4, 300])),
            "x_scale": np.array([0.1, 0.1, 0.1, 0.1, 0.3, 30.0])}
    return frame, prob


def test_beam_jacobian_matches_finite_differences():
    frame, prob = synthetic_barndoor()
    x = np.array([0.24, 0.16, 0.09, 0.07, 0.7, 38.0])
    r, jac = adfit.residuals_and_jacobian(um.beam_residuals_ad(frame, prob), x)

    def res_np(p: np.ndarray) -> np.ndarray:
        return (um.beam_model(prob["lc"], prob["u"], p) - frame.radiance) / frame.peak
    assert np.allclose(r, res_np(x), rtol=0, atol=1e-12)
    for k in range(6):
        fd = central_difference(lambda p, k=k: res_np(p), x, k)
        assert np.allclose(jac[:, k], fd, rtol=0, atol=FD_REL * np.abs(fd).max()), k


def test_beam_ad_fit_reaches_scipy():
    frame, prob = synthetic_barndoor()
    fit = adfit.least_squares(um.beam_residuals_ad(frame, prob), prob["p0"], prob["bounds"], prob["x_scale"])
    from scipy.optimize import least_squares

    ref = least_squares(lambda p: (um.beam_model(prob["lc"], prob["u"], p) - frame.radiance) / frame.peak,
                        prob["p0"], bounds=prob["bounds"], x_scale=prob["x_scale"])
    assert fit.fun <= float(ref.cost) * (1 + RESIDUAL_TOL)


def test_spot_and_lamp_gradients_match_finite_differences():
    spot = sw.spot_exponent_problem(18.0, 24.0, 400)
    w, t, a = spot["w"], spot["target"], spot["alpha"]
    assert_gradient(sw.spot_exponent_objective_ad(spot),
                    lambda p: float(np.sum(w * (np.cos(np.radians(a)) ** p[0] - t) ** 2) / np.sum(w)), np.array([9.0]))
    lamp = sw.lamp_problem(0.08, 0.3, 0.085, 300)
    cos_f, mitsuba = sw.lamp_objectives_ad(lamp)
    w, t, a, edge = lamp["w"], lamp["target"], lamp["alpha"], lamp["edge"]

    def ms(model: np.ndarray) -> float:
        return float(np.sum(w * (model - t) ** 2) / np.sum(w))
    assert_gradient(cos_f, lambda p: ms(np.where(a < edge, np.cos(np.radians(a)) ** p[0], 0.0)), np.array([20.0]))
    # Mitsuba's profile is piecewise linear in (beam, cutoff): away from a node crossing the difference is exact
    assert_gradient(mitsuba, lambda p: ms(sw.mitsuba_spot_profile(a, p[0], p[1])), np.array([3.01, 25.03]))


def test_spot_and_lamp_ad_fits_reach_brent():
    f_ad, rms_ad = sw.fit_spot_exponent(18.0, 24.0, 400, method="ad")
    f_sc, rms_sc = sw.fit_spot_exponent(18.0, 24.0, 400, method="scipy")
    assert rms_ad <= rms_sc * (1 + RESIDUAL_TOL) and abs(f_ad - f_sc) < 1e-2
    lamp = sw.lamp_problem(0.08, 0.3, 0.085, 300)
    ad, sc = sw.fit_lamp_ad(lamp, (True, False)), sw.fit_lamp_scipy(lamp, (True, False))
    assert ad["cos_f_rms"] <= sc["cos_f_rms"] * (1 + RESIDUAL_TOL)
    assert math.isfinite(ad["cos_f_exponent"])


def test_bench_only_rejects_an_unknown_section(capsys, tmp_path):
    from validate.cli import main

    assert main(["bench", "--only", "fits,nosuch", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("validate: error: --only fits,nosuch: unknown section nosuch")
    assert not (tmp_path / "bench.json").exists()
