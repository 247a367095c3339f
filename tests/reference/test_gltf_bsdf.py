"""The glTF 2.0 metallic-roughness Mitsuba BSDF (validate.reference.gltf_bsdf): closed forms, χ², albedo, Mitsuba."""

from __future__ import annotations

import math

import numpy as np
import pytest

from validate.errors import ValidateError

g = pytest.importorskip("validate.reference.gltf_bsdf")


def _eval(base: tuple[float, float, float], metallic: float, roughness: float, wi: list[float], wo: list[float],
          **extra: float) -> np.ndarray:
    import drjit as dr
    import mitsuba as mi

    b = mi.load_dict(g.bsdf_dict(base, metallic, roughness, **extra))
    si = dr.zeros(mi.SurfaceInteraction3f, 1)
    si.wi = mi.Vector3f(*wi)
    f = b.eval(mi.BSDFContext(), si, mi.Vector3f(*wo))
    return np.array([float(f[k][0]) for k in range(3)])


@pytest.mark.parametrize("metallic", [0.0, 0.5, 1.0])
@pytest.mark.parametrize("roughness", [0.3, 1.0])
def test_eval_at_normal_incidence_is_the_closed_form(metallic: float, roughness: float) -> None:
    # ω_i = ω_o = n: H = n, D = 1/(π α²), V = ½/(1 + 1) = ¼, F(f₀) = f₀ (|V·H| = 1), μ_o = 1:
    # f = (1 − m)((1 − 0.04) ρ/π + 0.04/(4π α²)) + m ρ/(4π α²)   [glTF 2.0 B.2.1, B.3]
    rho = np.array([0.2, 0.5, 1.0])
    a2 = roughness**4
    spec = 1.0 / (4 * math.pi * a2)
    want = (1 - metallic) * ((1 - 0.04) * rho / math.pi + 0.04 * spec) + metallic * rho * spec
    got = _eval(tuple(rho), metallic, roughness, [0.0, 0.0, 1.0], [0.0, 0.0, 1.0])
    np.testing.assert_allclose(got, want, rtol=1e-5)  # float32 evaluation
    bad = _eval(tuple(rho), metallic, roughness, [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], dielectric_f0=0.05)
    if metallic < 1.0:  # power: the dielectric's F₀ 0.04 → 0.05 moves the value by far more than float32
        assert np.max(np.abs(bad / want - 1)) > 1e-3


def test_eval_below_the_horizon_is_zero() -> None:
    assert np.all(_eval((1, 1, 1), 0.5, 0.5, [0.0, 0.0, 1.0], [0.0, 0.6, -0.8]) == 0.0)


def test_chi2_accepts_the_sampler_and_rejects_alpha_times_1_1() -> None:
    ok = g.chi2_gltf(0.5, 0.5, 0.6, 100_000, 3)
    assert ok["accepts"] and not ok["sanity_fail"], ok
    bad = g.chi2_gltf(0.5, 0.5, 0.6, 100_000, 3, sample_alpha_scale=1.1)
    assert not bad["accepts"] and bad["p_value"] < 1e-6, bad


@pytest.mark.parametrize("metallic,roughness", [(0.0, 0.25), (0.5, 0.5), (1.0, 1.0)])
def test_albedo_through_sample_equals_the_quadrature(metallic: float, roughness: float) -> None:
    base = (0.0, 0.5, 1.0)
    mean, se = g.albedo_sampled(base, metallic, roughness, 0.6, 200_000, 5)
    q = g.albedo_quadrature(base, metallic, roughness, 0.6)
    z = [(a - b) / s for a, b, s in zip(mean, q, se, strict=True)]
    assert max(abs(x) for x in z) < 4.0, (mean, q, se)  # 3 channels, α ≈ 2e-4 two-sided
    if metallic < 1.0:  # power: F₀ 0.05 in the quadrature is rejected (the R channel is the specular layer alone)
        qp = g.albedo_quadrature(base, metallic, roughness, 0.6, dielectric_f0=0.05)
        assert max(abs((a - b) / s) for a, b, s in zip(mean, qp, se, strict=True)) > 10.0


def test_quadrature_converges() -> None:
    a = g.albedo_quadrature((1, 1, 1), 0.5, 0.25, 0.6, nodes=192)
    b = g.albedo_quadrature((1, 1, 1), 0.5, 0.25, 0.6, nodes=256)
    assert max(abs(x - y) for x, y in zip(a, b, strict=True)) < 1e-4


def test_metal_equals_roughconductor_with_height_correlated_masking() -> None:
    r = g.metal_vs_roughconductor(0.5, 20_000, 1)
    assert r["max_rel_diff"] < 16 * 2.0**-24 / 0.5**4, r  # float32 at the lobe's peak (claims.F32_EPS rule)
    assert r["separable_max_rel_diff"] > 0.01, r  # power: Mitsuba's separable G₁G₁ is not glTF's V


@pytest.mark.parametrize("bad", [{"metallic": 1.5}, {"roughness": -0.1}, {"base_g": 2.0}, {"sample_alpha_scale": 0.0}])
def test_bad_properties_raise_with_the_ranges(bad: dict) -> None:
    d = dict(g.bsdf_dict((1, 1, 1), 0.5, 0.5))
    d.update(bad)
    with pytest.raises(ValidateError, match="expected"):
        g._props(d)


def test_white_metal_furnace_of_the_walk_reference_is_one() -> None:
    """reference (ii) traced by BSDF sampling (render_reference.trace_pass_bsdf_sampled): a white metal walk
    absorbs nothing, so in the radiance-1 furnace every pixel is exactly 1 [Heitz et al. 2016]; glTF's (i) is not."""
    from validate.reference.render_reference import render_reference
    from validate.scenes import render_scenes as rs

    for model, want_one in (("multiscatter", True), ("gltf", False)):
        sc = rs.RenderScene(f"t_{model}", rs.Material(metallic=1.0, roughness=1.0, model=model),
                            environment=rs.FURNACE, resolution=8)
        ref = render_reference(sc, 4, 4, 0)
        m = ref.mean[ref.hit]
        if want_one:
            np.testing.assert_allclose(m, 1.0, rtol=1e-6)
        else:
            assert m.mean() < 0.6  # glTF's single scattering at roughness 1 loses ≈ 60 % (measured 0.40 at 32²)
