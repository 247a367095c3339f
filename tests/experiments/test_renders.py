"""Issue 21, first slice: engines' pixels against Mitsuba (scenes, reference, per-pixel z, check_render).

Default run: the judgement on synthetic images, the RGBE writer, check_render on an analytic Lambert shader
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
    from validate.testing_render import check_render

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
    from validate.experiments.renders.claims import FURNACE_ENERGY_TOL, FURNACE_REGRESSIONS

    for scene in rs.furnace_scenes(SMALL, (0.5,)):
        er = _engine_or_skip(engine, scene)
        x, y = scene.pixel_centres()
        mask = interior_mask(x**2 + y**2 < 1.0, er.image[..., 3])
        deviation = abs(er.image[..., :3][mask].mean() - 1.0)
        if engine in FURNACE_REGRESSIONS and "dielectric" in scene.name:
            assert deviation > FURNACE_ENERGY_TOL, scene.name
        else:
            assert deviation < FURNACE_ENERGY_TOL, scene.name
