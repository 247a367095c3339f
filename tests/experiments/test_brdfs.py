"""The ``brdf`` family: closed forms of the textbook models, agreement with Mitsuba's BSDFs, the V-groove
reference, and the experiment's claims with their power checks (tiny settings)."""

from __future__ import annotations

import dataclasses
import importlib

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.experiments import Context
from validate.experiments import brdfs as exp
from validate.experiments.brdfs import check as chk
from validate.experiments.brdfs import report as rep
from validate.local_models import family, precision
from validate.local_models.brdf import classic_brdfs as cb
from validate.local_models.brdf import common as brdf_common
from validate.reference import brdf_render as br
from validate.scenes import brdf_scenes as bs

bc = importlib.import_module("validate.experiments.brdfs.claims")  # the module (`pkg.claims` is the function)
bm = importlib.import_module("validate.experiments.brdfs.compute")  # the module (`pkg.compute` is the function)

BUILTINS = ("lambert", "phong", "blinn_phong", "phong_normalized", "blinn_phong_normalized", "cook_torrance_printed",
            "cook_torrance", "oren_nayar", "oren_nayar_full", "minnaert")
FURNACE_NODES = (96, 192)  # Gauss–Legendre in cos θ × φ: lobes up to s = 50 integrate to < 1e-4
QUADRATURE_TOL = 1e-3  # furnace quadrature at FURNACE_NODES, measured < 2e-4 for s ≤ 50
BECKMANN_G1_TOL = 0.0071  # Walter et al. 2007 eq. 27: Mitsuba's rational G1 within 0.35 % per direction, ×2
FLOAT32_TOL = 1e-4  # Mitsuba evaluates in float32 (≈ 50 operations × 6e-8)


def _grid(n: int = 16) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    lights, views, w = bs.brdf_grid(n, n)
    return np.tile([0.0, 0.0, 1.0], (len(lights), 1)), lights, views, w


def _albedo(tech: str, params: dict, theta_v_deg: float = 0.0) -> float:
    return float(bm.furnace_albedo(lambda lt, vw: bm.call(tech, params, lt, vw), (theta_v_deg,), FURNACE_NODES)[0])


def test_family_has_the_builtins() -> None:
    fam = family("brdf")
    for name in BUILTINS:
        assert name in fam


def test_lambert_and_rough_models_at_zero_roughness_are_lambert() -> None:
    n, lights, views, _ = _grid(8)
    p = {"albedo": 0.7, "sigma": 0.0, "minnaert_k": 1.0}
    expected = 0.7 / np.pi * np.maximum(lights[:, 2], 0.0)
    for name in ("lambert", "oren_nayar", "oren_nayar_full", "minnaert"):
        with precision.computing_in("float64"):  # an algebraic identity: checked to float64 rounding (family: float32)
            got = family("brdf").call(name, p, n, lights, views)
        np.testing.assert_allclose(got[:, 1], expected, rtol=1e-12, atol=1e-15, err_msg=name)


@pytest.mark.parametrize("s", [1.0, 10.0, 50.0])
def test_furnace_closed_forms_of_phong(s: float) -> None:
    """At normal view: textbook Phong (k_s = 1, π-folded light) has W = (1/π)∫cos^s θ dω = 2/(s + 1);
    the modified Phong has W = 1 exactly (Lafortune & Willems 1994)."""
    p = {"albedo": 0.0, "ks": 1.0, "phong_exponent": s}
    assert abs(_albedo("phong", p) - 2.0 / (s + 1.0)) < QUADRATURE_TOL
    assert abs(_albedo("phong_normalized", p) - 1.0) < QUADRATURE_TOL


def test_beckmann_d_is_normalised_and_smith_matches_mitsubas_rational_fit() -> None:
    """∫ D cos θ_h dω_h = 1 (Walter 2007 eq. 4); exact Smith G1 within 0.35 % of the rational fit (eq. 27)."""
    dirs, w = bs.hemisphere_quadrature(256, 8)
    for a in (0.1, 0.3, 0.7):
        assert abs(np.sum(w * brdf_common.beckmann_d(dirs[:, 2], a) * dirs[:, 2]) - 1.0) < 1e-3
    c = np.linspace(0.05, 0.999, 200)
    for a in (0.1, 0.5, 1.0):
        t = np.sqrt(1 - c * c) / c
        x = 1.0 / (a * t)
        rational = np.where(x >= 1.6, 1.0, (3.535 * x + 2.181 * x * x) / (1 + 2.276 * x + 2.577 * x * x))
        assert np.max(np.abs(brdf_common.smith_g1(c, a, "beckmann") / rational - 1.0)) < 0.0035


def test_fresnel_exact_matches_cook_torrance_dielectric_formula_and_mirror() -> None:
    """Cook & Torrance 1982's unpolarised dielectric F with g² = η² + c² − 1; η = 0 + 1i reflects everything."""
    c = np.linspace(0.01, 1.0, 50)
    eta = 1.5
    g = np.sqrt(eta * eta + c * c - 1.0)
    ct = 0.5 * (g - c) ** 2 / (g + c) ** 2 * (1 + (c * (g + c) - 1) ** 2 / (c * (g - c) + 1) ** 2)
    np.testing.assert_allclose(brdf_common.fresnel_exact(c, eta, 0.0)[:, 0], ct, rtol=1e-10)
    np.testing.assert_allclose(brdf_common.fresnel_exact(c, 0.0, 1.0), 1.0, rtol=1e-10)


@pytest.mark.parametrize("material, tol", [(bs.conductor(0.3, "ggx"), FLOAT32_TOL),
                                           (bs.conductor(0.2), BECKMANN_G1_TOL),
                                           (bs.conductor(0.5, coloured=False), BECKMANN_G1_TOL)])
def test_cook_torrance_equals_mitsuba_roughconductor(material: bs.Material, tol: float) -> None:
    _, lights, views, _ = _grid(12)
    ref = br.eval_bsdf(material.bsdf, lights, views)
    assert bm.max_rel(bm.call("cook_torrance", material.params, lights, views), ref) < tol
    # power: the neighbouring roughness (α × 1.01) is caught
    p = {**material.params, "alpha": 1.01 * material.params["alpha"]}
    assert bm.max_rel(bm.call("cook_torrance", p, lights, views), ref) > tol


def test_phong_normalized_equals_the_suites_modphong_bsdf() -> None:
    _, lights, views, _ = _grid(12)
    mat = bs.modified_phong(20.0, br.register_phong_bsdf())
    ref = br.eval_bsdf(mat.bsdf, lights, views)
    assert bm.max_rel(bm.call("phong_normalized", mat.params, lights, views), ref) < FLOAT32_TOL
    p = {**mat.params, "phong_exponent": 21.0}  # the s + 1 off-by-one is caught
    assert bm.max_rel(bm.call("phong_normalized", p, lights, views), ref) > FLOAT32_TOL


def test_printed_cook_torrance_is_four_times_the_mirror_microfacet_energy() -> None:
    """With F = 1 the printed form differs from Walter's only by the missing 4 and the V-cavity G."""
    _, lights, views, w = _grid(16)
    mat = bs.conductor(0.2, coloured=False)
    ref = br.eval_bsdf(mat.bsdf, lights, views)
    q = bm.call("cook_torrance_printed", mat.params, lights, views)
    ratio = np.sum(w * q[:, 0]) / np.sum(w * ref[:, 0])
    assert 3.9 < ratio < 4.1


def test_bad_parameter_is_one_line_error() -> None:
    n, lights, views, _ = _grid(4)
    with pytest.raises(ValidateError, match="technique 'oren_nayar' .*sigma"):
        family("brdf").call("oren_nayar", {"albedo": 0.5, "sigma": [1.0, 2.0]}, n, lights, views)
    with pytest.raises(ValidateError, match="distribution"):
        family("brdf").call("cook_torrance", {"distribution": "phong"}, n, lights, views)


def test_vgroove_reference_is_lambert_at_small_slope() -> None:
    lights, views = bs.vgroove_configurations([0.0, 45.0, 70.0], [0.0, 180.0])
    r = br.vgroove_brdf(np.radians(2.0), lights, views, 0.8, 3, 3, 64, 6, 5)
    lam = 0.8 / np.pi * lights[:, 2]
    err = np.sum(np.abs(r["value"] - lam)) / np.sum(lam)
    assert err + np.sum(r["stderr"]) / np.sum(lam) < bc.LAMBERT_LIMIT


TINY = dataclasses.replace(exp.QUICK, grid=10, furnace=(24, 48), furnace_views_deg=(0.0, 60.0), sweep_alphas=(0.2, 0.5),
                           sigmas_deg=(2.0, 30.0), thetas_deg=(0.0, 45.0, 70.0), dphis_deg=(0.0, 180.0), n_slope=3,
                           n_orient=4, paths=64, depth=6, image=16, gouraud_image=32, gouraud_exponents=(20.0,),
                           env_image=12, env_nodes=8, env_spp=16)


def test_experiment_claims_pass_and_every_power_check_fails(tmp_path) -> None:
    ctx = Context(out_dir=tmp_path, quick=True, show_progress=False)
    m = exp.compute(ctx, TINY)
    cl = bc.claims(m)
    assert cl, "no claims"
    for c in cl:
        assert c.power is not None and c.power.fails, c.id
        assert c.passed, (c.id, c.measured, c.uncertainty, c.threshold)
    entries = rep.techniques(m)
    for name in BUILTINS:
        assert entries[name]["metrics"], name
        for v in entries[name]["metrics"].values():
            assert np.isfinite(v["value"]) and np.isfinite(v["uncertainty"])
    assert rep.findings(m)
    el = m.plane["elongation"]  # Phong's r·v highlight stays round, the microfacet one stretches (Mitsuba: 3.76)
    assert abs(el["cook_torrance"] / el["mitsuba"] - 1.0) < 0.02 and el["phong"] < 0.6 * el["mitsuba"]


def test_icosphere_counts_and_radius() -> None:
    for level in (0, 2):
        v, f = bs.icosphere(level)
        assert len(f) == 20 * 4 ** level and len(v) == 10 * 4 ** level + 2  # Euler: V = F/2 + 2
        np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1.0, rtol=1e-12)


def test_per_fragment_beats_gouraud_and_converges_at_second_order() -> None:
    """Linear interpolation of the normal errs O(h²) = O(1/T): ×4 triangles → error ÷ ~4 (asymptotically)."""
    light = np.array([0.5, 0.6, 0.62]) / np.linalg.norm([0.5, 0.6, 0.62])
    p = {"albedo": 0.0, "ks": 1.0, "phong_exponent": 20.0}
    errs = []
    for level in (2, 3):
        r = bm._shade(lambda n, lt, vw: bm.call_world("phong_normalized", p, n, lt, vw), light, level, 64)
        errs.append((bm._err(r["gouraud"], r["exact"]), bm._err(r["fragment"], r["exact"])))
        assert errs[-1][1] < errs[-1][0]
    assert 3.0 < errs[0][1] / errs[1][1] < 5.5


def test_check_brdf_accepts_a_correct_model_and_rejects_a_wrong_one() -> None:
    def my_ggx(params, normals, lights, views):  # noqa: ANN001, ANN202 (a user's plug-in)
        return cb.cook_torrance(params, normals, lights, views)

    def missing_four(params, normals, lights, views):  # noqa: ANN001, ANN202
        return 4.0 * cb.cook_torrance(params, normals, lights, views)

    ok = chk.check_brdf(my_ggx, ["conductor_ggx_a0.3"])
    assert ok.max_rel.max + ok.max_rel.max_uncertainty < FLOAT32_TOL
    bad = chk.check_brdf(missing_four, ["conductor_ggx_a0.3"])
    assert bad.rel_l1.max > 1.0
    with pytest.raises(ValidateError, match="unknown material"):
        chk.check_brdf(my_ggx, ["no_such_material"])


def test_shared_work_gives_each_call_its_own_numbers() -> None:
    """The speed-ups that share work between calls change no number: the environment lookups shared by the
    techniques (env_radiance_many) equal one technique at a time, the furnace over several views in one call
    equals a call per view, and the cached quadrature hands out copies (writing into one leaves the next intact)."""
    from validate.scenes import procedural

    env = procedural.two_tone()
    n = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 1.0, 0.0]])
    v = np.array([[0.0, 0.0, 1.0], [0.0, 0.6, 0.8], [0.0, 0.0, 1.0]])
    mat = bs.conductor(0.3)
    fns = {t: (lambda nn, ll, vv, t=t: family("brdf").call(t, mat.params, nn, ll, vv))
           for t in ("lambert", "cook_torrance")}
    many = bm.env_radiance_many(fns, env.radiance, n, v, 6)
    for t, fn in fns.items():
        assert np.array_equal(bm.env_radiance_local(fn, env.radiance, n, v, 6), many[t])
    fn2 = lambda lt, vw: bm.call("cook_torrance", mat.params, lt, vw)  # noqa: E731
    both = bm.furnace_albedo(fn2, (0.0, 60.0), (16, 32))
    assert both.tolist() == [bm.furnace_albedo(fn2, (t,), (16, 32))[0] for t in (0.0, 60.0)]
    d, w = bs.hemisphere_quadrature(8, 16)
    d[:] = 0.0
    assert np.abs(bs.hemisphere_quadrature(8, 16)[0]).sum() > 0


def test_environment_quadrature_matches_per_pixel_sums() -> None:
    """env_radiance_many (direction-major chunks, the techniques' evaluated geometry shared on frozen inputs)
    equals, bit for bit, each pixel on its own: the technique on fresh writable (l, v) rows of that pixel and
    L_o = Σ_j w_j (q_j L_j) added in direction order; several chunks (ENV_CHUNK lowered) and one technique after
    another on the same chunk."""
    from validate.scenes import latlong, procedural

    env = procedural.two_tone()
    rng = np.random.default_rng(3)
    n = rng.normal(size=(5, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    v = n + 0.5 * rng.normal(size=(5, 3))
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    mat = bs.conductor(0.3)
    techs = ("cook_torrance", "oren_nayar_full", "lambert")
    fns = {t: (lambda nn, ll, vv, t=t: family("brdf").call(t, {**mat.params, "sigma": 0.3}, nn, ll, vv))
           for t in techs}
    local, w = bs.hemisphere_quadrature(4, 8)
    frozen: list[bool] = []

    def record(nn: np.ndarray, ll: np.ndarray, vv: np.ndarray) -> np.ndarray:
        frozen.append(all(brdf_common._frozen(a) for a in (nn, ll, vv)))  # what the shared conversions key on
        return fns["lambert"](nn, ll, vv)

    old = bm.ENV_CHUNK
    bm.ENV_CHUNK = 2 * len(local)  # 2 pixels per chunk: 3 chunks, the last one short
    try:
        many = bm.env_radiance_many({**fns, "record": record}, env.radiance, n, v, 4)
    finally:
        bm.ENV_CHUNK = old
    t_, b_ = bm._frames(n)
    for i in range(len(n)):
        d = local[:, :1] * t_[i] + local[:, 1:2] * b_[i] + local[:, 2:3] * n[i]
        lrad = latlong.bilinear_lookup(env.radiance, d)
        for t, fn in fns.items():
            q = fn(np.tile(n[i], (len(d), 1)), d.copy(), np.tile(v[i], (len(d), 1)))
            terms = w[:, None] * (q * lrad)
            acc = terms[0].copy()
            for row in terms[1:]:
                acc += row
            assert np.array_equal(many[t][i], acc), (t, i)
    assert frozen == [True] * 3 and np.array_equal(many["record"], many["lambert"])


def test_frozen_geometry_is_shared_with_the_same_numbers() -> None:
    """GeometryDr on read-only inputs reuses the evaluated fields of the last such inputs; every field equals the
    one formed from writable copies, and new arrays (even with equal values) are not mistaken for the old."""
    import drjit as dr

    rng = np.random.default_rng(4)
    arrays = [rng.normal(size=(64, 3)) for _ in range(3)]
    for a in arrays:
        a.setflags(write=False)
    with precision.family_precision("float32"):
        first = brdf_common.GeometryDr(*arrays)
        again = brdf_common.GeometryDr(*arrays)
        fresh = brdf_common.GeometryDr(*(a.copy() for a in arrays))
        for name in brdf_common._GEOMETRY_FIELDS:
            assert getattr(again, name) is getattr(first, name)
            assert np.array_equal(np.array(getattr(again, name)), np.array(getattr(fresh, name))), name
        other = [a.copy() for a in arrays]
        other[1][0] = -other[1][0]
        for a in other:
            a.setflags(write=False)
        changed = brdf_common.GeometryDr(*other)
        assert not dr.all(changed.cl == first.cl)


def test_drjit_threads_restores_the_pool_and_keeps_the_numbers() -> None:
    """drjit_threads(1) runs the techniques on one thread with the same numbers, and restores the count after
    (also on an error); None leaves it as it is."""
    import drjit as dr

    before = dr.thread_count()
    lights, views, _ = bs.brdf_grid(6, 6)
    ref = bm.call("cook_torrance", bs.conductor(0.3).params, lights, views)
    with bm.drjit_threads(1):
        assert dr.thread_count() == 1
        one = bm.call("cook_torrance", bs.conductor(0.3).params, lights, views)
    assert dr.thread_count() == before and np.array_equal(ref, one)
    with pytest.raises(RuntimeError), bm.drjit_threads(1):
        raise RuntimeError("x")
    assert dr.thread_count() == before
    with bm.drjit_threads(None):
        assert dr.thread_count() == before
