"""IBL convolution (issue 4): irradiance maps, Phong-prefiltered maps, split-sum GGX, the modified-Phong
Mitsuba BSDF, image metrics — against closed forms, the irradiance quadrature and Mitsuba.

Tolerances are named next to the measured value they come from (measured on this machine, llvm_ad_rgb).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from validate import geometry
from validate.errors import ValidateError
from validate.local_models.irradiance import irradiance_map as im
from validate.local_models.irradiance import sh as shm
from validate.local_models.specular import common as specular_common
from validate.local_models.specular import prefiltered_specular as ps
from validate.local_models.specular import split_sum as ss
from validate.metrics import image_error as ie
from validate.metrics.flip import flip_hdr
from validate.metrics.irradiance_error import WORST_CASE_MAX
from validate.reference import ibl_render as rr
from validate.reference.irradiance import reference_irradiance
from validate.scenes import latlong, procedural

Y = latlong.luminance


def smooth(d: np.ndarray) -> np.ndarray:
    """A smooth RGB test function of direction (second derivatives ~1)."""
    return np.stack([1 + 0.5 * d[:, 0], 1 + 0.3 * d[:, 1] + 0.2 * d[:, 2] ** 2, 2 + d[:, 0] * d[:, 1]], -1)


def random_dirs(n: int, seed: int = 1) -> np.ndarray:
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


@pytest.fixture(scope="module")
def disc() -> procedural.Environment:
    return procedural.disc_on_sky(128)


# ------------------------------------------------------------------------------------------------
# Cube-map geometry, lookups, seams
# ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("n", [1, 2, 5, 16])
def test_cube_texel_round_trip_and_solid_angles(n: int) -> None:
    d = geometry.cube_texel_directions(n).reshape(-1, 3)
    face, x, y = geometry.face_coords(d, n)
    i = np.arange(6 * n * n)
    assert np.array_equal(face, i // (n * n))
    assert np.allclose(y, (i // n) % n, atol=1e-9) and np.allclose(x, i % n, atol=1e-9)
    assert 6 * geometry.cube_texel_solid_angles(n).sum() == pytest.approx(4 * math.pi, rel=1e-12)


def test_cube_face_selection_matches_opengl_table() -> None:
    """[3, Table 8.19]: +X centre is +x, +Y's t axis runs along +z, −Z's s axis along −x."""
    d = np.array([[1.0, 0, 0], [0, 1.0, 0.5], [0.2, 0, -1.0]])
    face, x, y = geometry.face_coords(d, 2)
    assert list(face) == [0, 2, 5]
    assert x[0] == pytest.approx(0.5) and y[0] == pytest.approx(0.5)  # face centre of a 2×2 face
    assert y[1] > 0.5  # +Y: t grows with +z
    assert x[2] < 0.5  # −Z: s grows with −x, so +x means smaller s


def test_lookup_drjit_matches_numpy() -> None:
    q = random_dirs(5000)
    for n in (4, 9, 32):
        m = im.CubeMap.build(smooth, n)
        assert np.max(np.abs(m.lookup(q) - m.lookup_numpy(q))) < 1e-5  # float32 vs float64 weights
        ll = im.LatLongMap.build(smooth, n)
        assert np.max(np.abs(ll.lookup(q) - ll.lookup_numpy(q))) < 1e-5


def test_cube_lookup_second_order_across_seams_and_corners() -> None:
    """Bilinear interpolation is second order (error ÷ 4 per doubling) only if the seam padding is: a
    nearest-texel padding or a corner averaging the three corner texels is first order (÷ 2).
    Measured max error of `smooth` near corners: 2.1e-3 (N = 16) → 4.9e-4 (32) → 1.1e-4 (64)."""
    q = random_dirs(200000, seed=2)
    errs = {}
    for n in (16, 32, 64):
        face, x, y = geometry.face_coords(q, n)
        near_corner = (np.minimum(x + 0.5, n - 0.5 - x) < 1) & (np.minimum(y + 0.5, n - 0.5 - y) < 1)
        near_edge = (np.minimum(np.minimum(x + 0.5, n - 0.5 - x), np.minimum(y + 0.5, n - 0.5 - y)) < 1)
        e = np.abs(im.CubeMap.build(smooth, n).lookup_numpy(q) - smooth(q)).max(axis=1)
        errs[n] = (e[near_corner].max(), e[near_edge].max(), e.max())
    for k in range(3):
        assert errs[16][k] / errs[32][k] > 3.0 and errs[32][k] / errs[64][k] > 3.0, errs


def test_latlong_lookup_is_mitsubas_filter() -> None:
    """The lat-long map's drjit lookup equals latlong.bilinear_lookup (measured against emitter.eval)."""
    rad = procedural.bandlimited(16).radiance.astype(np.float64)
    q = random_dirs(3000)
    assert np.max(np.abs(im.LatLongMap(rad).lookup(q) - latlong.bilinear_lookup(rad, q))) < 1e-4


def test_sparse_build_covers_its_lookups() -> None:
    q = random_dirs(300, seed=5)
    for n in (8, 33):
        full, sparse = im.CubeMap.build(smooth, n), im.CubeMap.build(smooth, n, needed=q)
        assert np.isnan(sparse.faces).any()  # really sparse
        assert np.allclose(sparse.lookup(q), full.lookup(q), atol=1e-6)
        ll_full, ll_sparse = im.LatLongMap.build(smooth, n), im.LatLongMap.build(smooth, n, needed=q)
        assert np.allclose(ll_sparse.lookup(q), ll_full.lookup(q), atol=1e-6)


@pytest.mark.parametrize("bad", [0, -3, 2.5, 5000])
def test_bad_face_size_raises(bad: object) -> None:
    with pytest.raises(ValidateError, match="face size"):
        im.CubeMap.build(smooth, bad)  # type: ignore[arg-type]


def test_bad_radiance_raises() -> None:
    with pytest.raises(ValidateError, match="lat-long"):
        im.environment_nodes(np.ones((8, 8, 3)))


# ------------------------------------------------------------------------------------------------
# Irradiance maps
# ------------------------------------------------------------------------------------------------

def test_constant_environment_is_exact() -> None:
    """E = πL for uniform L; the ratio estimator makes every map exact (float32 storage)."""
    env = procedural.constant(32)
    m = im.compute_irradiance_cube(env.radiance, 8)
    assert np.allclose(m.lookup(random_dirs(500)), np.pi * procedural.CONSTANT, rtol=1e-5)


def test_two_tone_closed_form() -> None:
    """E = π(L_s(1 + cos β)/2 + L_g(1 − cos β)/2). The horizon falls between the point-sampled rows of a
    256-row map, a ±0.35° band: measured max error 0.12 % of the peak at faces 32 (bilinear + horizon)."""
    env = procedural.two_tone(256)
    n = random_dirs(2000, seed=3)
    c = n[:, 1:2]
    exact = np.pi * (procedural.SKY * (1 + c) / 2 + procedural.GROUND * (1 - c) / 2)
    m = im.compute_irradiance_cube(env.radiance, 32, needed=n)
    assert np.max(np.abs(Y(m.lookup(n)) - Y(exact))) / Y(exact).max() < 3e-3


def test_convolution_matches_reference_quadrature(disc) -> None:
    """Brute-force node convolution vs the foundation's quadrature of Mitsuba's radiance: node merging
    (4° blocks) errs ≈ β²/12 ≈ 4e-4 at most; measured 1.6e-4 of the peak (disc_on_sky)."""
    normals = latlong.fibonacci_sphere(1024)
    ref = reference_irradiance(disc, normals)
    e = im.convolve_cosine(im.environment_nodes(disc.radiance), normals)
    assert np.max(np.abs(Y(e) - Y(ref.irradiance))) / Y(ref.irradiance).max() < 1e-3


def test_sh_map_equals_convolution_for_bandlimited_light() -> None:
    """Order-2 lighting: SH9 irradiance is exact, so the two maps agree to quadrature error (< 0.1 % Φ;
    measured 2e-5)."""
    env = procedural.bandlimited(64)
    coeffs = shm.project_environment(env.radiance, 2)
    phi = Y(env.total_flux())
    conv = im.compute_irradiance_cube(env.radiance, 8).faces
    sh_map = im.irradiance_cube_from_sh(coeffs, 8).faces
    assert np.max(np.abs(Y(conv) - Y(sh_map))) / phi < 1e-3
    conv_ll = im.compute_irradiance_latlong(env.radiance, 8).data
    sh_ll = im.irradiance_latlong_from_sh(coeffs, 8).data
    assert np.max(np.abs(Y(conv_ll) - Y(sh_ll))) / phi < 1e-3


def test_claim_diffuse_map_within_1pct(disc) -> None:
    """Claim ibl.diffuse_map.within_1pct on the 4° disc: cube faces 32² within 1 % of the peak reference
    irradiance (measured 0.34 % at 256 rows; the experiment's full sweep needs 32² for the 0.5° disc)."""
    normals = latlong.fibonacci_sphere(2048) @ np.linalg.qr(np.random.default_rng(0).normal(size=(3, 3)))[0].T
    ref = reference_irradiance(disc, normals)
    m = im.compute_irradiance_cube(disc.radiance, 32, needed=normals)
    err = np.max(np.abs(Y(m.lookup(normals)) - Y(ref.irradiance))) / Y(ref.irradiance).max()
    unc = np.max(Y(ref.uncertainty)) / Y(ref.irradiance).max()
    assert err + unc < 0.01


def test_claim_sh_and_convolution_maps_within_sh9_bound() -> None:
    """Claim ibl.sh_vs_convolution.bound on the near-directional light, where R&H's 3/32 Φ bound is nearly
    attained: measured 9.19 % (bound 9.375 %) at faces 32."""
    env = procedural.near_directional(256)
    conv = im.compute_irradiance_cube(env.radiance, 16).faces.reshape(-1, 3)
    sh_map = im.irradiance_cube_from_sh(shm.project_environment(env.radiance, 2), 16).faces.reshape(-1, 3)
    phi = Y(env.total_flux())
    diff = np.max(np.abs(Y(sh_map) - Y(conv))) / phi
    assert 0.8 * WORST_CASE_MAX < diff < WORST_CASE_MAX  # close to, but within, the bound


# ------------------------------------------------------------------------------------------------
# Phong-prefiltered maps and the modified-Phong BSDF
# ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("s", [1.0, 10.0, 100.0, 1000.0])
def test_phong_lobe_is_normalised(s: float) -> None:
    """∫ (s+1)/2π cos^s α dω = 1: Gauss–Legendre in α over [0, min(π/2, 10/√s)] (2π sin α dα)."""
    x, w = np.polynomial.legendre.leggauss(400)
    amax = min(np.pi / 2, 10 / math.sqrt(s))
    a = (x + 1) * amax / 2
    integral = np.sum(ps.phong_kernel(s)(np.cos(a)) * 2 * np.pi * np.sin(a) * w * amax / 2)
    assert integral == pytest.approx(1.0, abs=1e-6)


def test_phong_face_rule() -> None:
    assert [ps.phong_face_size(s) for s in (1, 10, 100, 1000)] == [8, 32, 128, 256]


def test_phong_map_vs_exact_convolution(disc) -> None:
    """The map's own discretisation (bilinear on faces N with 2/N ≤ σ/4, 1.4° blocks) against the exact
    convolution at the looked-up directions: documented ≤ 1/128 + 1/384 of the lobe-filtered peak; measured
    0.2 % (s = 100, disc_on_sky)."""
    s = 101.0
    q = random_dirs(3000, seed=4)
    q = np.concatenate([q, q[:200] * 0.02 + procedural.direction_from_elevation(35.0, 30.0)])
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    m = ps.prefilter_phong_cube(disc.radiance, s, needed=q)
    exact = im.convolve_zonal(im.environment_nodes(disc.radiance, 0.5), q, ps.phong_kernel(s), 1.0,
                              ps.phong_support_cos(s))
    assert np.max(np.abs(Y(m.lookup(q)) - Y(exact))) / Y(exact).max() < 1 / 128 + 1 / 384


def test_phong_map_of_constant_light_is_exact() -> None:
    env = procedural.constant(32)
    m = ps.prefilter_phong_cube(env.radiance, 50.0)
    assert np.allclose(m.lookup(random_dirs(300)), procedural.CONSTANT, rtol=1e-5)


@pytest.mark.parametrize("bad", [0.0, -1.0, 1e6])
def test_bad_exponent_raises(bad: float) -> None:
    with pytest.raises(ValidateError, match="Phong exponent"):
        ps.phong_kernel(bad)


def test_mix_shader_algebra() -> None:
    base, diff, spec = np.array([0.5, 0.4, 0.3]), np.array([2.0, 2.0, 2.0]), np.array([1.0, 0.0, 3.0])
    assert np.allclose(ps.mix_shader(base, 1.0, 0.25, diff, spec), base * diff + 0.25 * spec)
    assert np.allclose(ps.mix_shader(base, 0.5, 0.0, diff, spec), 0.5 * base + 0.5 * base * diff)
    with pytest.raises(ValidateError, match="DiffusePercent"):
        ps.mix_shader(base, 1.5, 0.0, diff, spec)


@pytest.mark.parametrize("s", [1.0, 10.0, 100.0, 1000.0])
def test_phong_bsdf_white_furnace(s: float) -> None:
    """White furnace: albedo 1 at normal incidence (exact), and the horizon-cut albedo elsewhere equal to an
    independent quadrature — within 4 standard errors of Mitsuba's own importance sampling."""
    for mu in (1.0, 0.6, 0.15):
        a, se = rr.bsdf_albedo({"type": rr.PHONG_PLUGIN, "exponent": s}, mu, samples=1 << 17)
        expect = rr.phong_albedo(s, mu)
        assert abs(a - expect) < 4 * se + 1e-6, (mu, a, expect, se)
    assert rr.phong_albedo(s, 1.0) == pytest.approx(1.0, abs=1e-9)
    assert rr.phong_albedo(s, 0.5) < 1.0


def test_phong_bsdf_sample_eval_pdf_consistent() -> None:
    """eval/pdf equals the sample weight for sampled directions (MIS needs all three to agree)."""
    import drjit as dr
    import mitsuba as mi

    rr.register_phong_bsdf()
    b = mi.load_dict({"type": rr.PHONG_PLUGIN, "exponent": 20.0})
    n = 4096
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(0.6, 0.0, 0.8)
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(0, n)
    ctx = mi.BSDFContext()
    bs, w = b.sample(ctx, si, sampler.next_1d(), sampler.next_2d())
    value, pdf = b.eval_pdf(ctx, si, bs.wo)
    w, value, pdf = np.array(w)[0], np.array(value)[0], np.array(pdf)
    ok = pdf > 0
    assert ok.sum() > n // 2
    assert np.allclose(value[ok] / pdf[ok], w[ok], rtol=1e-4, atol=1e-6)
    assert np.allclose(np.array(bs.pdf)[ok], pdf[ok], rtol=1e-4)


def test_phong_sphere_white_furnace_render() -> None:
    """End to end: a modified-Phong sphere under a uniform white-ish environment L shows L · a(θ_v) in every
    pixel. Per-pixel z = (render − L a)/σ: |mean z| < 4/√N and at most 1 % of |z| > 4 (t with 7 dof has
    heavier tails than a normal: P(|t| > 4) = 0.5 %)."""
    env = procedural.constant(16)
    cam = rr.Camera((0.3, 0.5, 0.81), 24)
    r = rr.render(env, rr.RenderSpec("sphere", {"type": rr.PHONG_PLUGIN, "exponent": 10.0}, cam, spp=8 * 64,
                                     passes=8))
    cv = r.cos_view[r.mask]
    grid = np.linspace(0.0, 1.0, 101)  # a(μ) is smooth: linear interpolation on 101 points errs < 1e-4
    expect = np.interp(cv, grid, [rr.phong_albedo(10.0, m, nodes=96) for m in grid]) * Y(procedural.CONSTANT)
    z = (Y(r.mean[r.mask]) - expect) / r.stderr_y[r.mask]
    assert abs(z.mean()) < 4 / math.sqrt(z.size)
    assert np.mean(np.abs(z) > 4) < 0.01


def test_claim_phong_map_at_normal_incidence(disc) -> None:
    """Claim ibl.phong.normal_incidence (s = 100): over the θ_v ≤ 5° crop, Σ|ΔY| of the s + 1 map stays
    within the independent per-pixel bound Σ Y(U) of ibl_checks.phong_bound (measured 0.21 ± 0.07 of it at
    48², 8k spp), and the bound is not vacuous: U is below 5 % of the rendered luminance on average."""
    from validate.experiments.ibl import reference_checks as chk

    key = procedural.direction_from_elevation(35.0, 30.0)
    cam = rr.camera_towards(key, 6.0, 48)
    spec = rr.RenderSpec("sphere", {"type": rr.PHONG_PLUGIN, "exponent": 100.0}, cam, spp=8 * 1024, passes=8,
                         crop_deg=ps.NORMAL_INCIDENCE_DEG)
    r = rr.render(disc, spec)
    n, v = r.normal[r.mask], r.view[r.mask]
    assert r.mask.sum() >= 8
    m = ps.prefilter_phong_cube(disc.radiance, ps.map_exponent_for_brdf(100.0), needed=specular_common.reflect(n, v))
    y_app, y_ref = Y(ps.shade_phong_map(m, n, v)), Y(r.mean[r.mask])
    u = Y(chk.phong_bound(disc.radiance, 100.0, n, v))
    assert (np.sum(np.abs(y_app - y_ref)) + np.sum(r.stderr_y[r.mask])) / np.sum(u) < 1.0
    assert np.sum(u) / np.sum(y_ref) < 0.05


# ------------------------------------------------------------------------------------------------
# Split sum
# ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("alpha", [0.1, 0.5])
def test_dfg_albedo_matches_mitsuba_roughconductor(alpha: float) -> None:
    """A + B (F = 1) is the GGX albedo with Mitsuba's separable Smith G: vs Mitsuba's own sampling, within
    4σ + 1e-3 (QMC, 2048 visible-normal samples; measured ≤ 3e-4)."""
    for mu in (0.15, 0.6, 1.0):
        a, b = ss.dfg_terms(np.array([mu]), alpha)
        m, se = rr.bsdf_albedo({"type": "roughconductor", "distribution": "ggx", "alpha": alpha}, mu,
                               samples=1 << 18)
        assert abs((a + b)[0] - m) < 4 * se + 1e-3, (mu, (a + b)[0], m)


def test_plastic_terms_match_mitsuba_roughplastic() -> None:
    """The rough-plastic BRDF assembled from our coat terms equals Mitsuba's ``roughplastic`` eval
    pointwise (measured max 0.07 %, α = 0.1…0.6): the split-sum plastic's error is the split's, not a
    different BRDF's."""
    import drjit as dr
    import mitsuba as mi

    rng = np.random.default_rng(0)

    def hemi(k: int) -> np.ndarray:
        v = rng.normal(size=(k, 3))
        v[:, 2] = np.abs(v[:, 2]) + 0.05
        return v / np.linalg.norm(v, axis=1, keepdims=True)

    wi, wo = hemi(1000), hemi(1000)
    for alpha in (0.1, 0.6):
        b = mi.load_dict({"type": "roughplastic", "distribution": "ggx", "alpha": alpha, "int_ior": 1.49,
                          "ext_ior": 1.0})
        si = dr.zeros(mi.SurfaceInteraction3f, wi.shape[0])
        si.wi = mi.Vector3f(wi.T.astype(np.float32))
        ref = np.array(b.eval(mi.BSDFContext(), si, mi.Vector3f(wo.T.astype(np.float32))))[0]
        mine = ss.plastic_brdf_cos(ss.plastic_terms(alpha, 1.49), 0.5, wi, wo)
        assert np.max(np.abs(mine - ref) / ref) < 3e-3


def test_split_sum_is_exact_for_uniform_light() -> None:
    """P_α = L for uniform L, so the split sum is L (F0 A + B) = L × albedo (up to the table's bilinear
    interpolation: measured ≤ 0.3 % of A + B)."""
    env = procedural.constant(32)
    n = random_dirs(400, seed=9)
    v = n * 0.6 + random_dirs(400, seed=10) * 0.5
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    mu = np.sum(n * v, axis=1)
    keep = mu > 0.2
    n, v, mu = n[keep], v[keep], mu[keep]
    table = ss.compute_dfg_table()
    pre = ss.prefilter_ggx_cube(env.radiance, 0.3, face_size=8)
    got = ss.shade_split_sum(pre, table, n, v, 0.3)
    a, b = ss.dfg_terms(mu, 0.3)
    assert np.max(np.abs(got / procedural.CONSTANT - (a + b)[:, None]) / (a + b)[:, None]) < 5e-3


def test_centre_weight_ratio_by_sampling() -> None:
    """∫K_α = E[max(0, cos 2θ_h)] for h ∝ D cos θ_h (tan²θ_h = α² u/(1 − u)): the quadrature and a 10⁶-point
    stratified estimate agree to 1e-4."""
    for alpha in (0.1, 0.3, 0.6):
        u = (np.arange(1_000_000) + 0.5) / 1_000_000
        c2 = 2.0 / (1.0 + alpha * alpha * u / (1 - u)) - 1.0
        assert ss.prefilter_kernel_integral(alpha) == pytest.approx(np.mean(np.maximum(c2, 0.0)), abs=1e-4)
    assert ss.centre_weight_ratio(0.3) > 1.2  # the split sum over-weights a light at the lobe centre


@pytest.mark.parametrize("bad", [0.0, 1.5, -0.2])
def test_bad_alpha_raises(bad: float) -> None:
    with pytest.raises(ValidateError, match="alpha"):
        ss.ggx_prefilter_kernel(bad)


# ------------------------------------------------------------------------------------------------
# Renders, G-buffer, dented sphere
# ------------------------------------------------------------------------------------------------

def test_diffuse_sphere_render_matches_quadrature(disc) -> None:
    """Mitsuba's Lambertian sphere = ρ/π E(n) at the G-buffer normals (no occlusion on a sphere): the
    luminance-weighted bias within 4σ + 0.2 % (measured −0.01 % ± 0.02 %)."""
    cam = rr.camera_towards(procedural.direction_from_elevation(35.0, 30.0), 40.0, 32)
    r = rr.render(disc, rr.RenderSpec("sphere", {"type": "diffuse"}, cam, spp=8 * 64, passes=8))
    n = r.normal[r.mask]
    assert np.allclose(np.linalg.norm(r.position[r.mask], axis=1), 1.0, atol=1e-5)
    assert np.allclose(n, r.position[r.mask], atol=1e-5)
    approx = np.full(r.mean.shape, np.nan)
    approx[r.mask] = 0.5 / np.pi * reference_irradiance(disc, n).irradiance
    st = ie.relative_error(r.mean, r.stderr_y, approx, r.mask).stats
    assert abs(st.bias) < 4 * st.bias_uncertainty + 2e-3


def test_dented_sphere_geometry_and_occlusion(disc) -> None:
    spec = rr.DentSpec(depth=0.7, width_deg=50.0, axis=(0.0, 0.0, 1.0), resolution=24)
    pos, tri = rr.dented_sphere_vertices(spec)
    r = np.linalg.norm(pos, axis=1)
    assert r.max() == pytest.approx(1.0) and r.min() == pytest.approx(0.3, abs=0.02)
    assert tri.max() < pos.shape[0]
    # a closed surface: every edge is shared by exactly two triangles
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert np.all(counts == 2)
    cam = rr.Camera((0.0, 0.0, 1.0), 24)
    ao, _ = rr.ambient_occlusion(disc, rr.RenderSpec("dented", {"type": "diffuse"}, cam, dent=spec), 256)
    centre = ao[10:14, 10:14]
    assert np.nanmax(centre) < 0.8 and np.nanmedian(ao) > 0.95  # occluded crater, open rim


def test_render_rejects_bad_settings(disc) -> None:
    cam = rr.Camera((0.0, 0.0, 1.0), 8)
    with pytest.raises(ValidateError, match="passes"):
        rr.render(disc, rr.RenderSpec("sphere", {"type": "diffuse"}, cam, spp=10, passes=3))
    with pytest.raises(ValidateError, match="power of 4"):
        rr.render(disc, rr.RenderSpec("sphere", {"type": "diffuse"}, cam, spp=8 * 32, passes=8))
    with pytest.raises(ValidateError, match="shape"):
        rr.render(disc, rr.RenderSpec("cube", {"type": "diffuse"}, cam, spp=8 * 16, passes=8))


# ------------------------------------------------------------------------------------------------
# Image metrics
# ------------------------------------------------------------------------------------------------

def test_relative_error_and_bias() -> None:
    ref = np.ones((8, 8, 3))
    approx = ref * 1.1
    mask = np.zeros((8, 8), bool)
    mask[2:6, 2:6] = True
    approx[~mask] = 50.0  # outside the mask: ignored
    r = ie.relative_error(ref, np.full((8, 8), 0.01), approx, mask)
    assert r.stats.mean == pytest.approx(0.1) and r.stats.bias == pytest.approx(0.1)
    assert r.stats.pixels == 16 and r.stats.mean_uncertainty == pytest.approx(0.01)
    assert r.stats.bias_uncertainty == pytest.approx(0.01 / 4)  # √(16·0.01²)/16
    assert np.isnan(r.error[0, 0])
    with pytest.raises(ValidateError, match="image error"):
        ie.relative_error(ref, np.zeros((8, 8)), approx[:4], mask)


def test_flip_zero_for_identical_and_masked() -> None:
    rng = np.random.default_rng(0)
    ref = rng.random((32, 32, 3)) * 2
    mask = np.ones((32, 32), bool)
    assert flip_hdr(ref, ref.copy(), mask, negatives="clamp").mean == pytest.approx(0.0, abs=1e-7)
    worse = ref * 1.3
    f = flip_hdr(ref, worse, mask, negatives="clamp")
    assert f.mean > 0.01 and f.parameters["tonemapper"].lower() == "aces"
    mask[:16] = False  # errors outside the mask do not count
    worse2 = ref.copy()
    worse2[:16] *= 3.0
    assert flip_hdr(ref, worse2, mask, negatives="clamp").mean == pytest.approx(0.0, abs=1e-7)


# ---------------------------------------------------------------------------------------------
# Speed rewrites keep the bits (issue 22 item 5)
# ---------------------------------------------------------------------------------------------

def _plain_ggx(c: np.ndarray, alpha: float) -> np.ndarray:
    a2 = alpha * alpha
    pos = np.maximum(c, 0)
    return (a2 / np.pi) * pos * 0.25 / np.square((a2 - 1) * ((1 + pos) * 0.5) + 1)


def _plain_phong(c: np.ndarray, s: float) -> np.ndarray:
    return (s + 1.0) / (2.0 * math.pi) * np.power(np.maximum(c, 0), c.dtype.type(s))


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_in_place_kernels_equal_the_plain_formulas_bit_for_bit(dtype: type) -> None:
    """The GGX and Phong prefilter kernels, evaluated in place, give the plain expressions' values bit for bit
    (the same IEEE operations in the same order) and leave their input alone. Power check: the GGX formula with
    the division first, pos / den · (a2/π) · 0.25, is not bit-equal — the check sees an operation order."""
    c = np.random.default_rng(11).uniform(-1.0, 1.0, 200_000).astype(dtype)
    c0 = c.copy()
    for alpha in (0.1, 0.3, 0.6):
        assert np.array_equal(ss.ggx_prefilter_kernel(alpha)(c), _plain_ggx(c, alpha)), alpha
    for s in (1.0, 10.0, 100.0, 1000.0):
        assert np.array_equal(ps.phong_kernel(s)(c), _plain_phong(c, s)), s
    assert np.array_equal(c, c0)
    a2 = 0.3 ** 2
    pos = np.maximum(c, 0)
    swapped = pos / np.square((a2 - 1) * ((1 + pos) * 0.5) + 1) * (a2 / np.pi) * 0.25
    assert not np.array_equal(swapped, _plain_ggx(c, 0.3))


def test_dense_convolution_does_not_depend_on_the_kernel_slices(monkeypatch: pytest.MonkeyPatch) -> None:
    """convolve_zonal's dense path applies the kernel to row slices of KERNEL_PAIRS products: slices of one row,
    of 37 rows and the whole block give the same bits (the kernel is elementwise; the BLAS blocks are unchanged)."""
    nodes = im.environment_nodes(procedural.disc_on_sky(64).radiance)
    dirs = geometry.cube_texel_directions(8).reshape(-1, 3)
    kernel = ss.ggx_prefilter_kernel(0.3)
    outs = []
    for pairs in (1, 37 * nodes.count, 1 << 30):
        monkeypatch.setattr(im, "KERNEL_PAIRS", pairs)
        outs.append(im.convolve_zonal(nodes, dirs, kernel))
    assert np.isfinite(outs[0]).all()
    assert np.array_equal(outs[0], outs[1]) and np.array_equal(outs[0], outs[2])


def test_cube_lookup_compiles_one_kernel_for_every_face_size() -> None:
    """CubeMap.lookup takes the face size as opaque values (precision.constants_dr): lookups on faces 8 and 16
    after one on face 4 find every JIT kernel in drjit's cache (a literal 0.5·N or N + 2 is a new kernel per N)."""
    import drjit as dr

    from validate.local_models import precision

    d = np.random.default_rng(5).normal(size=(300, 3))
    maps = [im.CubeMap.build(lambda x: x * 1.0, n) for n in (4, 8, 16)]
    flag = dr.flag(dr.JitFlag.KernelHistory)
    dr.set_flag(dr.JitFlag.KernelHistory, True)
    try:
        with precision.computing_in(backend="llvm"):
            maps[0].lookup(d)
            dr.kernel_history()
            misses = []
            for m in maps[1:]:
                m.lookup(d)
                jit = [k for k in dr.kernel_history() if str(k["type"]).endswith("JIT")]
                assert jit
                misses.append(sum(1 for k in jit if not k["cache_hit"] or k["cache_disk"]))
    finally:
        dr.set_flag(dr.JitFlag.KernelHistory, flag)
    assert misses == [0, 0], misses
