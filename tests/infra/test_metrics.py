"""Irradiance error metrics (validate.metrics.irradiance_error) on hand-computed examples.

Grey triples (v, v, v) have luminance v because the Rec. 709 weights sum to 1, which keeps the
hand computations readable. All expected numbers below are exact decimal arithmetic, so the
tolerance is float64 round-off.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from validate.metrics.irradiance_error import METRIC_NAMES, RELATIVE_FLOOR, ErrorStats, irradiance_errors
from validate.metrics.published import PUBLISHED_TOLERANCE, fit_exposure

FLOAT64_TOL = 1e-12


def grey(*values: float) -> np.ndarray:
    return np.repeat(np.array(values, dtype=np.float64)[:, None], 3, axis=1)


def close(stats: ErrorStats, mean: float, max_: float, rms: float) -> bool:
    return (abs(stats.mean - mean) < FLOAT64_TOL and abs(stats.max - max_) < FLOAT64_TOL
            and abs(stats.rms - rms) < FLOAT64_TOL)


@pytest.fixture
def example() -> dict[str, np.ndarray]:
    """E = (1, 2, 4), E′ = (1.1, 1.8, 4), Φ = 10 (grey): |ΔY| = (0.1, 0.2, 0)."""
    return {"reference": grey(1, 2, 4), "approx": grey(1.1, 1.8, 4), "flux": np.full(3, 10.0),
            "uncertainty": grey(0.01, 0.02, 0.03)}


def test_all_metrics_present(example) -> None:
    out = irradiance_errors(example["reference"], example["approx"], example["flux"])
    assert tuple(out) == METRIC_NAMES
    assert set(out["peak"].to_json()) == {"mean", "max", "rms", "mean_uncertainty", "max_uncertainty"}


def test_flux_luminance(example) -> None:
    """e = |ΔY|/Φ_Y = (0.01, 0.02, 0): mean 0.01, max 0.02, rms √((1e-4 + 4e-4)/3)."""
    s = irradiance_errors(example["reference"], example["approx"], example["flux"])["flux_luminance"]
    assert close(s, 0.01, 0.02, math.sqrt(5e-4 / 3))


def test_peak(example) -> None:
    """e = |ΔY| / max Y(E) = (0.1, 0.2, 0)/4."""
    s = irradiance_errors(example["reference"], example["approx"], example["flux"])["peak"]
    assert close(s, 0.025, 0.05, math.sqrt((0.025**2 + 0.05**2) / 3))


def test_relative(example) -> None:
    """e = |ΔY| / Y(E) = (0.1, 0.1, 0)."""
    s = irradiance_errors(example["reference"], example["approx"], example["flux"])["relative"]
    assert close(s, 0.2 / 3, 0.1, math.sqrt(0.02 / 3))


def test_flux_rgb_takes_worst_channel_and_skips_dark_channels() -> None:
    """Per channel e_c = |ΔE_c|/Φ_c; a channel with Φ_c = 0 has no defined error and is skipped.
    R: |Δ| = (0.1, 0.3), Φ = 1 → mean 0.2, max 0.3, rms √0.05.
    G: |Δ| = (0.4, 0.0), Φ = 2 → mean 0.1, max 0.2, rms √0.02.  B: Φ = 0, skipped (|Δ| = 5)."""
    ref = np.array([[1.0, 1.0, 0.0], [2.0, 2.0, 0.0]])
    approx = np.array([[1.1, 1.4, 5.0], [1.7, 2.0, 5.0]])
    s = irradiance_errors(ref, approx, np.array([1.0, 2.0, 0.0]))["flux_rgb"]
    assert close(s, 0.2, 0.3, math.sqrt(0.05))


def test_relative_floor_excludes_dark_normals() -> None:
    """Relative error is reported only where Y(E) ≥ RELATIVE_FLOOR·max Y(E) = 1e-3·1000 = 1.
    The normal at Y = 0.5 (error 200 %) is excluded; the one at exactly 1 is included (error 10 %)."""
    assert RELATIVE_FLOOR == 1e-3
    ref = grey(1000.0, 0.5, 1.0)
    approx = grey(1000.0, 1.5, 1.1)
    s = irradiance_errors(ref, approx, np.full(3, 10.0))["relative"]
    assert close(s, 0.05, 0.1, math.sqrt(0.01 / 2))
    # the other metrics still see every normal: peak max = 1.0/1000
    assert abs(irradiance_errors(ref, approx, np.full(3, 10.0))["peak"].max - 1e-3) < FLOAT64_TOL


def test_uncertainty_is_propagated(example) -> None:
    """δ = (0.01, 0.02, 0.03): flux metrics δ/Φ → mean 0.002, max 0.003; peak δ/4 → 0.005, 0.0075;
    relative δ/Y(E) = (0.01, 0.01, 0.0075) → mean 0.0275/3, max 0.01."""
    out = irradiance_errors(example["reference"], example["approx"], example["flux"], example["uncertainty"])
    expected = {"flux_luminance": (0.002, 0.003), "flux_rgb": (0.002, 0.003), "peak": (0.005, 0.0075),
                "relative": (0.0275 / 3, 0.01)}
    for name, (mean_u, max_u) in expected.items():
        assert abs(out[name].mean_uncertainty - mean_u) < FLOAT64_TOL, name
        assert abs(out[name].max_uncertainty - max_u) < FLOAT64_TOL, name
    no_unc = irradiance_errors(example["reference"], example["approx"], example["flux"])
    assert all(s.mean_uncertainty == 0 and s.max_uncertainty == 0 for s in no_unc.values())


def test_uncertainty_bounds_the_true_error() -> None:
    """The propagation's promise: if the true reference is within δ of the measured one, the true
    mean and max error are within the reported uncertainties of the measured ones."""
    rng = np.random.default_rng(0)
    true = rng.uniform(1.0, 3.0, size=(500, 3))
    approx = true * rng.uniform(0.9, 1.1, size=(500, 3))
    delta = rng.uniform(0.0, 0.05, size=(500, 3))
    measured = true + delta * rng.uniform(-1.0, 1.0, size=(500, 3))
    flux = np.array([6.0, 7.0, 8.0])
    got = irradiance_errors(measured, approx, flux, delta)
    exact = irradiance_errors(true, approx, flux)
    for name in ("flux_luminance", "flux_rgb", "peak"):  # relative also moves with its denominator
        assert abs(got[name].mean - exact[name].mean) <= got[name].mean_uncertainty, name
        assert abs(got[name].max - exact[name].max) <= got[name].max_uncertainty, name


def test_fit_exposure_recovers_scale() -> None:
    """s = Σ c t / Σ t² (least squares); with c = 3.2·t exactly the deviation is 0. Perturbing a
    coefficient whose table value is 0 by 0.064 leaves Σ c t, hence s = 3.2, unchanged and deviates
    by 0.064/3.2 = 0.02."""
    t = np.linspace(-1.0, 1.0, 27).reshape(9, 3)  # t[4, 1] = 0
    fit = fit_exposure(3.2 * t, t, "p")
    assert abs(fit.scale - 3.2) < FLOAT64_TOL and fit.max_deviation < FLOAT64_TOL
    assert fit.to_json() == {"probe": "p", "scale": fit.scale, "max_deviation": fit.max_deviation}
    c = 3.2 * t
    c[4, 1] += 0.064
    fit = fit_exposure(c, t)
    assert abs(fit.scale - 3.2) < FLOAT64_TOL
    assert abs(fit.max_deviation - 0.02) < FLOAT64_TOL
    assert PUBLISHED_TOLERANCE == 0.01  # the threshold
