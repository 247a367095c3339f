"""Multiple-scattering GGX compensation (validate.local_models.brdf.brdf_multiscatter) and the multiscatter
experiment."""

from __future__ import annotations

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.experiments import multiscatter as ms
from validate.experiments.base import Context
from validate.experiments.multiscatter.claims import SS_LIMIT, sidak_z
from validate.experiments.multiscatter.compute import e_correlated, metrics
from validate.experiments.multiscatter.settings import Settings
from validate.local_models import family
from validate.local_models.brdf.brdf_multiscatter import tables
from validate.scenes import brdf_scenes as bs

COMPENSATED = ("ggx_kulla_conty", "ggx_fdez_aguera", "ggx_turquin", "ggx_metalness_fdez_aguera")


def furnace(tech: str, params: dict, mu: float, nodes: int = 96) -> float:
    dirs, w = bs.hemisphere_quadrature(nodes, 2 * nodes)
    v = np.tile([np.sqrt(1.0 - mu * mu), 0.0, mu], (len(dirs), 1))
    q = family("brdf").call(tech, params, np.tile([0.0, 0.0, 1.0], (len(dirs), 1)), dirs, v)
    return float(np.sum(w * q[:, 1]))


def test_table_matches_direct_quadrature_of_single_scattering():
    """E(μ) from the half-vector quadrature equals the l-space quadrature of cook_torrance (F = 1) to 10⁻³."""
    for alpha, mu in ((0.5, 0.5), (1.0, 1.0), (0.3, 0.8)):
        t = tables("ggx", alpha)
        direct = furnace("cook_torrance", {"alpha": alpha, "distribution": "ggx", "eta": 0.0, "k": 1.0}, mu)
        assert abs(float(t.lookup(t.e, np.array([mu]))[0]) - direct) < 1e-3
    assert 0.29 < float(tables("ggx", 1.0).lookup(tables("ggx", 1.0).e, np.array([1.0]))[0]) < 0.32  # ~69 % lost


@pytest.mark.parametrize("tech", COMPENSATED)
def test_compensation_closes_the_furnace(tech):
    for alpha, mu in ((0.5, 0.3), (1.0, 1.0), (1.0, 0.5)):
        p = {"alpha": alpha, "distribution": "ggx", "eta": 0.0, "k": 1.0, "metalness": 1.0, "base_color": 1.0}
        assert abs(furnace(tech, p, mu) - 1.0) < 2e-3


def test_blended_f0_bug_loses_energy_at_intermediate_metalness():
    p = {"alpha": 0.6, "distribution": "ggx", "metalness": 0.5, "base_color": 1.0}
    assert abs(furnace("ggx_metalness_fdez_aguera", p, 0.5) - 1.0) < 2e-3
    assert furnace("ggx_metalness_blended_f0_bug", p, 0.5) < 0.9
    pure = {**p, "metalness": 1.0}
    assert abs(furnace("ggx_metalness_blended_f0_bug", pure, 0.5) - 1.0) < 2e-3


def test_bad_alpha_is_one_line_error():
    with pytest.raises(ValidateError, match="ggx_turquin.*alpha"):
        family("brdf").call("ggx_turquin", {"alpha": 0.0}, np.array([[0, 0, 1.0]]), np.array([[0, 0, 1.0]]),
                            np.array([[0, 0, 1.0]]))


def test_experiment_claims_pass_and_power_fails(tmp_path):
    s = Settings(alphas=(0.5, 1.0), mus=(0.3, 1.0), metalness=(0.0, 0.5, 1.0), nodes=64, walkers=50_000,
                 walk_alphas=(0.6, 1.0), chi2_cases=((0.3, 30.0), (1.0, 20.0)), chi2_samples=200_000, chi2_res=31,
                 recip_f0s=(1.0,), recip_lanes=128, furnace_mus=(0.5,), furnace_directions=100_000, render_spp=16)
    ctx = Context(out_dir=tmp_path, quick=True, show_progress=False)
    m = ms.compute(ctx, s)
    claims = {c.id: c for c in ms.claims(m)}
    for tech in COMPENSATED:
        c = claims[f"multiscatter.technique.{tech}.furnace_error.f0_1"]
        assert c.passed and c.power.fails, c
    bug = claims["multiscatter.regression.ggx_metalness_blended_f0_bug.furnace_error.metalness"]
    assert bug.passed and bug.measured > 0.2 and bug.power.fails
    assert metrics(m, "cook_torrance")["furnace_error.f0_1"]["value"] > 0.6
    for cid in ("single_scatter", "furnace", "chi2", "reciprocity", "eval_furnace", "render_furnace",
                "mitsuba_single_scatter"):
        c = claims[f"multiscatter.walk.{cid}"]
        assert c.passed and c.power.fails, c


def test_random_walk_reference():
    """Heitz et al. 2016's walk: energy 1 at F = 1, first bounce = the height-correlated albedo, and more light than
    single scattering at F₀ < 1."""
    from validate.reference import microsurface_walk as mw
    r = mw.walk(0.8, 0.6, (1.0, 0.5), 60_000, 3)
    assert abs(r.albedo[0] - 1.0) < 1e-12 and r.truncated == 0.0
    assert abs(r.single[0] - e_correlated(0.8, 0.6)) < 4 * r.single_se[0]
    assert r.albedo[1] > r.single[1] + 0.02


# ---------------------------------------------------------------- the walk as a Mitsuba BSDF (microsurface_bsdf)

def test_walk_bsdf_chi2_accepts_the_sampler_and_rejects_alpha_times_1_1():
    """χ² (Mitsuba's histogram, pdf() with its Monte Carlo variance): the walk's sampler fits its pdf at the 1 %
    level; the sampler with α × 1.1 (eval/pdf unchanged) is rejected far below it."""
    from validate.reference import microsurface_bsdf as mb

    kw = {"samples": 200_000, "seed": 5, "res": 31, "ires": 6, "walks": 32}
    ok = mb.chi2_walk(0.6, 50.0, **kw)
    assert ok["p_value"] > 0.01 and ok["stray_samples"] == 0 and not ok["harness_sanity_fail"], ok
    assert abs(ok["pdf_mass"] - 1.0) < 5e-3 and ok["histogram_mass"] == 1.0
    bad = mb.chi2_walk(0.6, 50.0, **kw, sample_alpha_scale=1.1)
    assert bad["p_value"] < 1e-6, bad


def test_walk_bsdf_chi2_at_a_sharp_lobe_needs_the_pdf_noise_below_poisson():
    """α = 0.1: with 4 × 32 pdf walks the heavy-tailed next-event estimate's noise dominates the expected counts
    (max Var Ê/Ê > 1) and its 4-seed variance is unreliable; the experiment's rule (walks quadrupled until
    Var Ê ≤ Ê) brings the correct sampler above the 1 % level, and still rejects α × 1.1."""
    from validate.experiments.multiscatter.compute import CHI2_POWER, chi2_case
    from validate.reference import microsurface_bsdf as mb

    kw = {"samples": 400_000, "seed": 3, "res": 51, "ires": 6, "walks": 32}
    first = mb.chi2_walk(0.1, 30.0, **kw)
    assert first["variance_ratio"] > 1.0, first
    row, used = chi2_case(0.1, 30.0, kw)
    assert row["variance_ratio"] <= 1.0 and used["walks"] > 32, row
    assert row["p_value"] > 0.01, row
    assert mb.chi2_walk(0.1, 30.0, **used, **CHI2_POWER)["p_value"] < 1e-6


def test_chi2_histogram_memo_returns_what_a_fresh_tabulation_does():
    """chi2_walk reuses the previous call's histogram when only the pdf walks changed (``sample`` never reads
    them): the row equals the one from a fresh tabulation (memo cleared), and a perturbed sampler is tabulated
    anew."""
    from validate.reference import microsurface_bsdf as mb

    kw = {"samples": 50_000, "seed": 7, "res": 21, "ires": 4}
    mb.chi2_walk(0.6, 50.0, **kw, walks=8)
    memo = mb.chi2_walk(0.6, 50.0, **kw, walks=16)
    mb._HISTOGRAM_MEMO.clear()
    assert memo == mb.chi2_walk(0.6, 50.0, **kw, walks=16)
    bad = mb.chi2_walk(0.6, 50.0, **kw, walks=16, sample_alpha_scale=1.1)
    mb._HISTOGRAM_MEMO.clear()
    assert bad == mb.chi2_walk(0.6, 50.0, **kw, walks=16, sample_alpha_scale=1.1) and bad != memo


def test_resumed_pdf_walks_equal_a_fresh_evaluation_bit_for_bit():
    """pdf_state continued from a state of fewer walks (chi2_walk's quadrupling) returns exactly the harness's own
    pdf functor (BSDFAdapter) of the full walk count."""
    import drjit as dr
    import mitsuba as mi
    from mitsuba import chi2

    from validate.reference import microsurface_bsdf as mb

    d, _, _ = mb._pdf_grid((10, 21), 3, 1)
    dirs = mi.Vector3f(np.ascontiguousarray(d.T, dtype=np.float32))
    wi, state = mb._direction(30.0), None
    for walks in (4, 16):
        _, pdf = chi2.BSDFAdapter(mb.register(), mb._bsdf_dict(0.1, 1.0, walks, 1003), wi=wi)
        bsdf = mi.load_dict(mb._bsdf_dict(0.1, 1.0, walks, 1003))
        si = dr.zeros(mi.SurfaceInteraction3f, dr.width(dirs))
        si.wi = wi
        v, state = bsdf.pdf_state(si, dirs, state)
        assert np.array_equal(np.asarray(v), np.asarray(pdf(dirs)))


def test_bsdf_tasks_cover_the_serial_loop_and_collect_in_its_order():
    """compute's BSDF-check tasks: one per case of each check, the serial loop's seeds, collected back in the
    serial order whatever order they finished in."""
    from validate.experiments.multiscatter.compute import bsdf_collect, bsdf_tasks

    s = ms.FULL
    tasks = bsdf_tasks(s, 1234)
    kinds = [t[0] for t in tasks]
    assert kinds.count("chi2") == len(s.chi2_cases) and kinds.count("render") == len(s.walk_alphas)
    assert kinds.count("reciprocity") == len(s.walk_alphas) * len(s.recip_f0s)
    assert sorted(t[-1] for t in tasks if t[0] == "chi2") == [1234 + k for k in range(len(s.chi2_cases))]
    fake = [(t, {t[0]: t[1]}) for t in tasks]
    out = bsdf_collect(fake[::-1])
    assert out["chi2"] == list(range(len(s.chi2_cases))) and out["render"] == list(range(len(s.walk_alphas)))


def test_walk_bsdf_reciprocity_and_its_power():
    """|z| of forward vs reverse one-sided eval within the Šidák bound (9 pairs, family-wise 1 %); next-event
    shadowing by the distant G₁ breaks reciprocity by many standard errors."""
    from validate.reference import microsurface_bsdf as mb

    bound = sidak_z(9)
    assert mb.reciprocity_walk(0.8, 1.0, 64, 128, 9)["max_abs_z"] < bound
    assert mb.reciprocity_walk(0.8, 1.0, 64, 128, 9, nee_distant_g1=True)["max_abs_z"] > 2 * bound


def test_walk_bsdf_eval_matches_numpy_walk_and_furnace():
    """∫ eval dω_o: 1 at F₀ = 1 (theorem) and, at F₀ = 0.5, the numpy walk's albedo (same model, independent
    float64 code), both within 4 combined standard errors."""
    from validate.reference import microsurface_bsdf as mb
    from validate.reference import microsurface_walk as mw

    one = mb.furnace_eval(0.7, 0.4, 1.0, 100_000, 8, 3)
    assert abs(one["albedo"] - 1.0) < 4 * one["se"], one
    half = mb.furnace_eval(0.7, 0.4, 0.5, 100_000, 8, 4)
    ref = mw.walk(0.7, 0.4, (0.5,), 100_000, 4)
    assert abs(half["albedo"] - ref.albedo[0]) < 4 * np.hypot(half["se"], ref.albedo_se[0]), (half, ref)
    assert half["albedo"] > e_correlated(0.7, 0.4) * 0.5 + 0.02  # more than F₀ × single scattering


def test_walk_bsdf_first_order_is_mitsuba_roughconductor_with_correlated_g2():
    from validate.reference import microsurface_bsdf as mb

    r = mb.single_scatter_vs_mitsuba(0.5, 5000, 1)
    assert r["max_rel_diff"] < SS_LIMIT and r["separable_max_rel_diff"] > 0.1
    assert mb.single_scatter_vs_mitsuba(0.5, 5000, 1, 1.01)["max_rel_diff"] > 10 * SS_LIMIT


def test_walk_bsdf_sample_weight_pdf_and_bad_input():
    """sample(): F₀ = 1 weights are exactly 1, ω_o above the horizon, bs.pdf equals pdf() (the same function of
    (ω_i, ω_o), as MIS needs); bad properties → one-line ValidateError."""
    import drjit as dr
    import mitsuba as mi

    from validate.reference import microsurface_bsdf as mb

    b = mb.load_bsdf(0.6, 1.0, 8, 2)
    n = 4096
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(0.6, 0.0, 0.8)
    rng = mi.PCG32(n)
    ctx = mi.BSDFContext()
    bs, w = b.sample(ctx, si, rng.next_float32(), mi.Point2f(rng.next_float32(), rng.next_float32()))
    assert np.all(np.asarray(w) == 1.0) and np.all(np.asarray(bs.wo.z) > 0.0)
    assert np.allclose(np.asarray(bs.pdf), np.asarray(b.pdf(ctx, si, bs.wo)), rtol=1e-6)
    with pytest.raises(ValidateError, match="microsurface_walk.*alpha"):
        mb.load_bsdf(0.0)


def test_furnace_memo_reuses_only_calls_that_read_the_same_parameters():
    """_furnace's memo: Phong reads no α, so its second α is the first's W (one evaluation); Cook–Torrance reads α,
    so each α is evaluated; every memoised W equals an unmemoised evaluation exactly."""
    import importlib

    from validate.backend import init

    c = importlib.import_module("validate.experiments.multiscatter.compute")
    mus, nodes = (0.3, 0.9), 24
    for name, evaluations in (("phong", 1), ("cook_torrance", 2)):
        tech = family("brdf")[name]
        key = (tech.name, id(tech.fn), mus, nodes, init().variant)
        c._FURNACE_MEMO.pop(key, None)
        for a in (0.3, 0.7):
            got = c._furnace(tech, c._f1(a), mus, nodes)
            assert np.array_equal(got, c._furnace_eval(tech, c._f1(a), mus, nodes))
        assert len(c._FURNACE_MEMO[key]) == evaluations
    rec = c._ReadKeys({"alpha": 0.5, "ks": 1.0})
    assert rec.get("alpha") == 0.5 and "eta" not in rec and rec.read == {"alpha", "eta"}
    assert dict(rec) == {"alpha": 0.5, "ks": 1.0} and rec.read == {"alpha", "eta", "ks"}


def test_furnace_geometry_is_built_once_read_only_and_gives_the_per_call_values():
    """_furnace_eval's arrays are those formed per call before (n = +z, the quadrature tiled per μ, v at azimuth 0),
    shared between calls and read-only; a technique on them returns what it returns on fresh writable copies."""
    import importlib

    c = importlib.import_module("validate.experiments.multiscatter.compute")
    mus, nodes = (0.3, 0.9), 16
    n, l, v, w = c._furnace_geometry(mus, nodes)
    assert c._furnace_geometry(mus, nodes)[1] is l
    assert not any(a.flags.writeable for a in (n, l, v, w))
    dirs, w0 = bs.hemisphere_quadrature(nodes, 2 * nodes)
    k = len(dirs)
    assert np.array_equal(w, w0) and np.array_equal(l, np.tile(dirs, (2, 1)))
    assert np.array_equal(n, np.tile([0.0, 0.0, 1.0], (2 * k, 1)))
    assert np.array_equal(v, np.concatenate([np.tile([np.sqrt(1.0 - mu * mu), 0.0, mu], (k, 1)) for mu in mus]))
    for name in ("cook_torrance", "ggx_metalness_fdez_aguera"):
        tech = family("brdf")[name]
        fresh = family("brdf").call(tech, c._f1(0.5, 0.5), n.copy(), l.copy(), v.copy())
        for _ in range(2):  # the second call on the same read-only arrays reuses their packed drjit input
            assert np.array_equal(family("brdf").call(tech, c._f1(0.5, 0.5), n, l, v), fresh)
