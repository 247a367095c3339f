"""Issue 21: Filament (npm 1.53.4, WebAssembly) as the third engine of ``renders`` — punctual lights only.

Default run: the 8-bit readback's decoding and its quantisation uncertainty (no browser), and which kinds Filament
is skipped for. ``slow``: Filament renders the directional, point and spot scenes (32²) through gltfio and its
LightManager, and each claim of the experiment passes while its power check fails (skipped with the reason without
Chromium / node_modules/filament).
"""

from __future__ import annotations

import base64
import importlib

import numpy as np
import pytest

from validate.local_models.render import decode_unorm8

compute = importlib.import_module("validate.experiments.renders.compute")  # the package re-exports compute()
cl = importlib.import_module("validate.experiments.renders.claims")


def test_unorm8_decode_divides_by_the_exposure_and_carries_half_an_lsb() -> None:
    q = np.array([[[0, 51, 255, 255]]], np.uint8)  # one pixel: 0, 0.2, 1 of full scale, alpha 1
    img, sigma = decode_unorm8(base64.b64encode(q.tobytes()).decode(), (1, 1, 4), 0.5)
    np.testing.assert_allclose(img[0, 0], [0.0, 0.4, 2.0, 1.0], rtol=1e-6)
    # uniform on ±½ LSB: variance 1/12 LSB²; in radiance one LSB is 1/(255 e)
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 255, 200_000)
    err = (np.round(x) - x) / (255 * 0.5)
    assert sigma == pytest.approx(err.std(), rel=0.01)


def test_filament_is_skipped_where_it_has_no_pipeline() -> None:
    for kind in ("furnace", "hemisphere", "probe", "probe_lambert", "rect"):
        assert "filament" in compute.KIND_SKIP[kind]
    for kind in ("directional", "point", "spot"):
        assert "filament" not in compute.KIND_SKIP.get(kind, {})


def test_readback_uncertainty_adds_in_quadrature() -> None:
    er = compute.EngineResult(np.zeros((1, 1, 3)), np.ones((1, 1)), 0.0, 0.0, "", stderr=4.0)
    np.testing.assert_allclose(compute.with_readback(np.full((1, 1, 3), 3.0), er), 5.0)


@pytest.mark.slow
def test_filament_punctual_claims_pass_and_their_power_checks_fail() -> None:
    from validate.experiments.renders.settings import Settings
    from validate.gl.egl import GLUnavailable
    from validate.scenes import render_scenes as rs

    s = Settings(resolution=32, spp=4, passes=4, engines=("filament",))
    scenes = [(rs.lambert_sun_scene(32, s.sun_lux), "directional")]
    scenes += [(sc, "spot" if sc.name.startswith("spot") else "point") for sc in rs.punctual_scenes(32)]
    results = [compute.measure_scene(sc, kind, s) for sc, kind in scenes]
    if any("filament" not in r.engines for r in results):
        reason = next(r.skipped["filament"] for r in results if "filament" in r.skipped)
        if "GLUnavailable" in reason:
            pytest.skip(f"filament cannot render here: {reason}")
        raise GLUnavailable(reason)
    m = compute.Measurements(s, results)
    out = cl.directional_claims(m) + cl.point_claims(m) + cl.spot_claims(m)
    assert len(out) == 4
    for c in out:
        assert c.passed, c
        assert c.power is not None and c.power.fails, c
