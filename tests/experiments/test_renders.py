"""Issue 21, first slice: engines' pixels against Mitsuba (scenes, reference, per-pixel z, check_render).

Default run: the judgement on synthetic images, the RGBE writer, the probe conventions (Mitsuba node lattice, the
engines' quarter turn), the contrast ratio, the rectangle's form factor, check_render on an analytic Lambert shader
(Mitsuba only, 16² pixels), and three.js's Lambertian sphere under a directional light (64², one scene,
skipped with the reason without Chromium / node_modules). The furnace and Babylon are ``slow``.
"""

from __future__ import annotations

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.metrics.pixel_z import MIN_ACCEPTED, interior_mask, judge
from validate.scenes import render_scenes as rs

SMALL = 32


def _engine_or_skip(engine: str, scene: rs.RenderScene):
    from validate.gl.egl import GLUnavailable
    from validate.local_models import render

    try:
        return render.render(engine, scene)
    except GLUnavailable as exc:
        pytest.skip(f"{engine} cannot render here: {exc}")


def test_judge_accepts_the_truth_and_rejects_a_two_percent_bias() -> None:
    rng = np.random.default_rng(7)
    mean = np.full((16, 16, 3), 0.5)
    stderr = np.full((16, 16, 3), 1e-3)
    mask = np.ones((16, 16), bool)
    engine = mean + rng.normal(0.0, 1e-3, mean.shape)  # the truth plus noise of the reference's size
    ok = judge(engine, mean, stderr, 31, mask, 0.0, "none")
    assert ok.fraction_accepted >= MIN_ACCEPTED
    # 10 σ per pixel with 31 dof: z ≈ 6.5 > z* = 4.36 (with 7 dof the same t maps to z ≈ 4.2: too few passes)
    bad = judge(mean * 1.02, mean, stderr, 31, mask, 0.0, "none")
    assert bad.fraction_accepted < MIN_ACCEPTED
    assert bad.mean_signed_rel == pytest.approx(0.02, rel=1e-9)


def test_budget_is_the_largest_difference_accepted_alone() -> None:
    mean = np.full((8, 8, 3), 1.0)
    zero = np.zeros_like(mean)
    mask = np.ones((8, 8), bool)
    b = 1e-3
    assert judge(mean + 0.9 * b, mean, zero, 7, mask, b, "b").fraction_accepted == 1.0
    assert judge(mean + 1.1 * b, mean, zero, 7, mask, b, "b").fraction_accepted == 0.0


def test_interior_mask_drops_the_outline() -> None:
    scene = rs.lambert_sun_scene(SMALL)
    x, y = scene.pixel_centres()
    hit = x**2 + y**2 < 1.0
    m = interior_mask(hit, np.ones_like(x))
    assert m.sum() < hit.sum() and not (m & ~hit).any()


def test_rgbe_round_trips_radiance_one() -> None:
    data = rs.rgbe_bytes(np.ones((4, 8, 3)))
    assert data.endswith(bytes([128, 128, 128, 129]) * 32)


def test_material_outside_the_mapping_is_an_error() -> None:
    with pytest.raises(ValidateError, match="metallic"):
        rs.Material(metallic=0.5)


def test_check_render_on_an_analytic_lambert_shader() -> None:
    from examples.check_my_renderer import my_renderer
    from validate.testing import check_render

    scene = rs.lambert_sun_scene(16)
    [good] = check_render(my_renderer, scenes=[(scene, "directional")], spp=4, passes=4)
    assert good.passed and good.judgement.max_rel < 1e-5
    [bad] = check_render(lambda s: my_renderer(s) * 1.02, scenes=[(scene, "directional")], spp=4, passes=4)
    assert not bad.passed
    with pytest.raises(ValidateError, match="lambert_directional: render_fn returned shape"):
        check_render(lambda s: np.zeros((3, 3)), scenes=[(scene, "directional")], spp=4, passes=4)


def _directional(engine: str, resolution: int) -> tuple:
    from validate.experiments.renders.compute import budget
    from validate.reference.render_reference import render_reference

    scene = rs.lambert_sun_scene(resolution)
    er = _engine_or_skip(engine, scene)
    ref = render_reference(scene, spp=4, passes=4)
    mask = interior_mask(ref.hit, er.image[..., 3])
    b, text = budget("directional", ref.mean)
    img = er.image[..., :3].astype(np.float64)
    return (judge(img, ref.mean, ref.stderr, ref.dof, mask, b, text),
            judge(img * 1.02, ref.mean, ref.stderr, ref.dof, mask, b, text))


# The directional budget is a margin measured at 64² (compute.DIRECT_BUDGET_OF_PEAK); at 32² the 2-pixel edge
# mask is twice as wide in the image but leaves limb pixels whose tessellation error is larger (measured: 5 of
# 500 pixels rejected), so the engines are judged at the 64² of the experiment.
DIRECT_RES = 64


def test_three_lambert_sphere_equals_mitsuba_per_pixel() -> None:
    j, j102 = _directional("three", DIRECT_RES)
    assert j.fraction_accepted >= MIN_ACCEPTED, j
    assert j102.fraction_accepted < MIN_ACCEPTED  # power: the light intensity × 1.02


@pytest.mark.slow
def test_babylon_lambert_sphere_equals_mitsuba_per_pixel() -> None:
    j, j102 = _directional("babylon", DIRECT_RES)
    assert j.fraction_accepted >= MIN_ACCEPTED, j
    assert j102.fraction_accepted < MIN_ACCEPTED


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["three", "babylon"])
def test_furnace_energy(engine: str) -> None:
    """Metal spheres return 1 in every engine; the dielectric does in three.js and, as the regression the
    renders experiment states, not in Babylon (measured +1.7 % at roughness 0.5)."""
    from validate.experiments.renders.claims import FURNACE_ENERGY_TOL, defect

    for scene in rs.furnace_scenes(SMALL, (0.5,)):
        er = _engine_or_skip(engine, scene)
        x, y = scene.pixel_centres()
        mask = interior_mask(x**2 + y**2 < 1.0, er.image[..., 3])
        deviation = abs(er.image[..., :3][mask].mean() - 1.0)
        if defect(engine, "furnace") is not None and "dielectric" in scene.name:
            assert deviation > FURNACE_ENERGY_TOL, scene.name
        else:
            assert deviation < FURNACE_ENERGY_TOL, scene.name


# --- (c) punctual lights and (f) hemisphere light (issue 21, second slice) ---------------------------------------


def _lambert_analytic(scene: rs.RenderScene) -> np.ndarray:
    """L = ρ/π · I f(θ) cos θ_n / d² at each pixel's surface point (KHR point/spot, inverse square) [PBR4 §12.1]."""
    p = scene.surface_points()
    n = p if scene.geometry == "sphere" else np.broadcast_to([0.0, 0.0, 1.0], p.shape)
    [li] = scene.lights
    v = np.asarray(li.position) - p
    d = np.linalg.norm(v, axis=-1)
    f = li.falloff((-v / d[..., None]) @ li.unit_direction()) if isinstance(li, rs.SpotLight) else 1.0
    return li.intensity * f * np.clip((n * v).sum(-1) / d, 0.0, None) / d**2 / np.pi


@pytest.mark.parametrize("profile", rs.SPOT_PROFILES)
def test_mitsuba_spot_reference_follows_the_profile_exactly(profile: str) -> None:
    """Mitsuba's spot ramps linearly in angle; with the projected KHR texture it follows the profile to float32."""
    from validate.reference.render_reference import render_reference

    scene = rs.spot_scene(16, profile)
    ref = render_reference(scene, spp=1, passes=4)
    want = _lambert_analytic(scene)
    assert np.nanmax(np.abs(ref.mean[..., 0] - want)) < 1e-5 * np.nanmax(want)
    # power: the other profile differs by far more inside the penumbra (t = ½: 0.25 vs 0.5)
    other = _lambert_analytic(rs.spot_scene(16, "smoothstep" if profile == "gltf" else "gltf"))
    pen = rs.spot_penumbra(scene)
    assert pen.sum() > 20 and np.max(np.abs(other - want)[pen]) > 0.1 * np.nanmax(want)


def test_mitsuba_point_reference_on_the_plane_is_inverse_square() -> None:
    from validate.reference.render_reference import render_reference

    scene = rs.punctual_scenes(16)[0]
    assert scene.geometry == "plane" and scene.hit_mask().all()
    ref = render_reference(scene, spp=1, passes=4)
    want = _lambert_analytic(scene)
    assert np.max(np.abs(ref.mean[..., 0] - want)) < 1e-5 * want.max()
    assert np.all(ref.stderr == 0)  # a delta light with next-event estimation: noise free


def test_spot_flux_is_the_integral_of_its_profile() -> None:
    for profile in rs.SPOT_PROFILES:
        li = rs.SpotLight((0, 0, 1), (0, 0, 0), 4.0, 20.0, 30.0, profile=profile)
        c = np.linspace(np.cos(np.radians(30.0)), 1.0, 200001)
        numeric = 2 * np.pi * li.intensity * np.trapezoid(li.falloff(c), c)
        assert li.flux() == pytest.approx(numeric, rel=1e-8)


def test_bad_lights_and_geometry_are_errors() -> None:
    with pytest.raises(ValidateError, match="inner_deg < outer_deg"):
        rs.SpotLight((0, 0, 1), (0, 0, 0), 1.0, 30.0, 20.0)
    with pytest.raises(ValidateError, match="profile"):
        rs.SpotLight((0, 0, 1), (0, 0, 0), 1.0, 10.0, 20.0, profile="linear")
    with pytest.raises(ValidateError, match="geometry"):
        rs.RenderScene("x", rs.LAMBERT, geometry="cube")


def test_hemisphere_texels_split_at_the_horizon() -> None:
    t = rs.HEMISPHERE.texels(8)
    assert t.shape == (8, 16, 3)
    assert np.all(t[:4] == np.asarray(rs.HEMISPHERE.sky)) and np.all(t[4:] == np.asarray(rs.HEMISPHERE.ground))


def _judged(engine: str, scene: rs.RenderScene, kind: str):
    from validate.experiments.renders.compute import budget, references, truth

    er = _engine_or_skip(engine, scene)
    refs, hit = references(scene, kind, _QuickRefs())
    mask = interior_mask(hit, er.image[..., 3])
    img = er.image[..., :3].astype(np.float64)
    out = {}
    for k, r in refs.items():
        m, se, dof = truth(r, hit, 4)
        b, text = budget(kind, m)
        out[k] = (judge(img, m, se, dof, mask, b, text), judge(img * 4 * np.pi, m, se, dof, mask, b, text))
    return out


class _QuickRefs:
    spp, passes, seed, env_spp = 1, 4, 0, 64


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["three", "babylon"])
def test_point_and_spot_lights_equal_mitsuba(engine: str) -> None:
    """Point lights in candela match in both engines; the spot matches the profile each engine implements
    (three: smoothstep, Babylon FALLOFF_GLTF: KHR's formula) and three's misses KHR's in the penumbra."""
    from validate.experiments.renders.claims import fact

    for scene in rs.punctual_scenes(DIRECT_RES):
        kind = "spot" if scene.name.startswith("spot") else "point"
        js = _judged(engine, scene, kind)
        own = js[fact(engine, "spot_reference", "mitsuba")] if kind == "spot" else js["mitsuba"]
        assert own[0].fraction_accepted >= MIN_ACCEPTED, (scene.name, own[0])
        assert own[1].fraction_accepted < MIN_ACCEPTED  # power: lumens taken for candela (× 4π)
        if kind == "spot" and engine == "three":
            assert js["mitsuba"][0].fraction_accepted < MIN_ACCEPTED


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["three", "three_probe", "babylon"])
def test_hemisphere_light_equals_mitsuba(engine: str) -> None:
    j, j4pi = _judged(engine, rs.hemisphere_scene(DIRECT_RES), "hemisphere")["mitsuba"]
    assert j.fraction_accepted >= MIN_ACCEPTED, j
    assert j4pi.fraction_accepted < MIN_ACCEPTED


def test_check_render_on_analytic_point_and_spot_lights() -> None:
    from examples.check_my_renderer import my_renderer
    from validate.testing import check_render

    point, _, spot = rs.punctual_scenes(16)
    checks = check_render(my_renderer, scenes=[(point, "point"), (spot, "spot")], spp=1, passes=4)
    assert [c.reference for c in checks] == ["mitsuba", "mitsuba"] and all(c.passed for c in checks)
    [bad] = check_render(lambda s: my_renderer(s) * 4 * np.pi, scenes=[(point, "point")], spp=1, passes=4)
    assert not bad.passed  # power: lumens taken for candela


# (b) the probe: conventions (Mitsuba's node lattice, the engines' quarter turn), the contrast ratio, resampling.
def _gpu_bilinear(texels: np.ndarray, d: np.ndarray) -> np.ndarray:
    """What a GPU's bilinear lookup returns for direction d in the probes' convention (texel centres, u wraps,
    θ clamped to the first and last row centres) — written from the convention, not from the code under test."""
    h, w = texels.shape[:2]
    theta, phi = np.arccos(np.clip(d[:, 1], -1, 1)), np.arctan2(d[:, 0], -d[:, 2]) % (2 * np.pi)
    y, x = np.clip(theta / np.pi * h - 0.5, 0, h - 1), phi / (2 * np.pi) * w - 0.5
    y0, x0 = np.minimum(np.floor(y).astype(int), h - 2), np.floor(x).astype(int)
    fy, fx = (y - y0)[:, None], (x - x0)[:, None]
    t = lambda i, j: texels[i, j % w]  # noqa: E731
    return ((1 - fy) * ((1 - fx) * t(y0, x0) + fx * t(y0, x0 + 1))
            + fy * ((1 - fx) * t(y0 + 1, x0) + fx * t(y0 + 1, x0 + 1)))


def test_mitsuba_envmap_on_the_node_lattice_is_the_gpu_bilinear_texture() -> None:
    import mitsuba as mi

    from validate.backend import init

    init()
    rng = np.random.default_rng(3)
    tex = rng.uniform(0.1, 2.0, (8, 16, 3))
    emitter = mi.load_dict(rs.mitsuba_environment(rs.Environment("t", texels=tex)))  # no filter_type: it loads
    d = rng.normal(size=(200, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(*(mi.Float(-d[:, k]) for k in range(3)))
    got = np.stack([np.array(c) for c in emitter.eval(si)], axis=-1)
    np.testing.assert_allclose(got, _gpu_bilinear(tex, d), rtol=2e-5)
    # power: Mitsuba on the texels themselves (its rows at θ = πi/(H − 1)) is off by up to tens of percent
    raw = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(np.ascontiguousarray(tex, np.float32))})
    off = np.stack([np.array(c) for c in raw.eval(si)], axis=-1)
    assert np.abs(off / _gpu_bilinear(tex, d) - 1).max() > 0.05


def test_engine_texels_turn_the_probe_a_quarter_for_three() -> None:
    """three's equirectUv: u = atan2(d_z, d_x)/2π + ½, v = asin(d_y)/π + ½ (row 0 of the scene's texels = top).
    The texel three reads at a texel-centre direction must be the probes' texel of that direction."""
    h, w = 8, 16
    tex = np.arange(h * w, dtype=float).reshape(h, w, 1) * np.ones(3)
    eng = rs.engine_texels(tex)
    i, j = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    theta, phi = np.pi * (i + 0.5) / h, 2 * np.pi * (j + 0.5) / w
    dx, dz = np.sin(phi) * np.sin(theta), -np.cos(phi) * np.sin(theta)
    ju = np.floor((np.arctan2(dz, dx) / (2 * np.pi) + 0.5) * w).astype(int) % w
    assert np.array_equal(eng[i, ju], tex[i, j])
    assert not np.array_equal(tex[i, ju], tex[i, j])  # power: without the turn three reads another texel
    with pytest.raises(ValidateError):
        rs.engine_texels(np.ones((4, 6, 3)))


def test_contrast_ratio_sees_blur_and_not_the_truth() -> None:
    from validate.experiments.renders.compute import contrast_ratio

    rng = np.random.default_rng(5)
    truth = np.repeat(rng.uniform(0.5, 1.5, (32, 32, 1)), 3, axis=-1)
    se, mask = np.full(truth.shape, 0.01), np.ones((32, 32), bool)
    noisy = truth + se * rng.standard_normal(truth.shape) * 3 ** -0.5  # channel mean noise = se/√3 as assumed
    c, u = contrast_ratio(truth, noisy, se, mask)
    assert abs(c - 1) < 4 * u + 0.02
    blurred = 0.5 * (truth + truth.mean())  # the pixel spread halved
    cb, ub = contrast_ratio(blurred, noisy, se, mask)
    assert cb + ub < 0.6


def test_resample_probe_keeps_the_mean_and_rejects_odd_sizes() -> None:
    rng = np.random.default_rng(2)
    r = rng.uniform(0, 3, (16, 32, 3))
    out = rs.resample_probe(r, (8, 16))
    assert out.shape == (8, 16, 3)
    np.testing.assert_allclose(out.mean(), r.mean())
    with pytest.raises(ValidateError):
        rs.resample_probe(r, (6, 16))


@pytest.mark.slow
def test_three_lambert_sphere_under_the_probe_equals_mitsuba() -> None:
    from pathlib import Path

    from validate.reference.render_reference import render_reference
    from validate.scenes.loaders import load_environment

    path = Path("../shared/probes") / rs.PROBE_FILE
    if not path.is_file():
        pytest.skip(f"{path}: not here")
    tex = rs.resample_probe(load_environment(path, "latlong", False).radiance)
    scene = rs.probe_lambert_scene(tex, "uffizi", SMALL)
    ref = render_reference(scene, 256, 8, 0)
    er = _engine_or_skip("three", scene)
    mask = interior_mask(ref.hit, er.image[..., 3])
    ratio = float(er.image[..., :3][mask].mean() / ref.mean[mask].mean())
    assert abs(ratio - 1) < 0.01  # the experiment's bound (R&H 2001's 1 % average error of order-2 SH irradiance)
    assert abs(1.02 * ratio - 1) > 0.01  # power: the probe 2 % brighter


# (d) the rectangular area light: Lambert's polygon formula against a quadrature of the form factor
def test_rect_form_factor_is_the_integral_over_the_rectangle() -> None:
    """F·n = (1/π) ∫_A cos θ cos θ' / d² dA, by a 200² midpoint rule over the rectangle, at three sphere points."""
    scene = rs.rect_scenes(16)[1]
    li = scene.lights[0]
    exact, sphere = rs.rect_form_factors(scene)
    above = rs.rect_above_horizon(scene)
    corners = rs.rect_corners(li)
    ex, ey = corners[1] - corners[0], corners[3] - corners[0]
    nl = np.cross(ex, ey) / np.linalg.norm(np.cross(ex, ey))
    t = (np.arange(200) + 0.5) / 200
    q = corners[0] + t[:, None, None] * ex + t[None, :, None] * ey
    da = np.linalg.norm(ex) * np.linalg.norm(ey) / 200**2
    p = scene.surface_points()
    for i, j in np.argwhere(above)[[0, len(np.argwhere(above)) // 2, -1]]:
        v = q - p[i, j]
        d2 = (v**2).sum(-1)
        cos_r = (v @ p[i, j]) / np.sqrt(d2)
        cos_l = np.abs(v @ nl) / np.sqrt(d2)
        np.testing.assert_allclose(exact[i, j], (cos_r * cos_l / d2).sum() * da / np.pi, rtol=1e-4)
        assert sphere[i, j] > exact[i, j]  # power: three's clipped-sphere form factor is not the integral here


@pytest.mark.slow
def test_three_rect_area_light_in_nits_with_its_form_factor_divided_out() -> None:
    from validate.reference.render_reference import render_reference

    scene = rs.rect_scenes(SMALL)[1]
    ref = render_reference(scene, 256, 8, 0)
    er = _engine_or_skip("three", scene)
    mask = interior_mask(ref.hit, er.image[..., 3]) & rs.rect_above_horizon(scene)
    exact, sphere = rs.rect_form_factors(scene)
    fixed = er.image[..., :3] * np.where(sphere > 0, exact / np.where(sphere > 0, sphere, 1.0), 1.0)[..., None]
    b = 2.5e-3 * np.nanmax(ref.mean)
    assert judge(fixed, ref.mean, ref.stderr, 7, mask, b, "").fraction_accepted >= MIN_ACCEPTED
    area = scene.lights[0].area()
    assert judge(fixed / (np.pi * area), ref.mean, ref.stderr, 7, mask, b, "").fraction_accepted < MIN_ACCEPTED
    assert judge(er.image[..., :3], ref.mean, ref.stderr, 7, mask, b, "").fraction_accepted < MIN_ACCEPTED
