"""(d) Babylon.js's RectAreaLight, rendered through Babylon's own shader with Heitz et al. 2016's GGX LTC tables
(three.js's RectAreaLightTexturesLib LTC_MAT_1 / LTC_MAT_2) because Babylon's own areaLightsLTC.bin comes from
assets.babylonjs.com (its engine's notes["rect"], validate/local_models/render/babylon.py).

Default run: the label is one string in the page and the experiment, and Babylon is rendered, not skipped. ``slow``
(Babylon's page load costs tens of seconds on the shared cores): the rectangle the shader builds is the scene's;
the Lambertian pixels do not depend on the table (its diffuse is the LTC with the identity matrix — the form factor
— and its specular 0), while a dielectric's do (the tables reach the shader); and the units (nits) on the sphere,
with Babylon's clipped-sphere form factor divided out, against Mitsuba.
"""

from __future__ import annotations

import importlib
import re

import numpy as np
import pytest

from validate.local_models.render.babylon import RECT_LTC_LABEL
from validate.metrics.pixel_z import MIN_ACCEPTED, interior_mask, judge
from validate.scenes import render_scenes as rs

SMALL = 32
compute = importlib.import_module("validate.experiments.renders.compute")


def test_babylon_rect_is_rendered_with_the_labelled_substitution() -> None:
    from validate.experiments.renders.kinds import RECT
    from validate.gl import browser_page

    assert compute.skip_reason("babylon", RECT) is None
    assert compute.substitution("babylon", RECT) == RECT_LTC_LABEL
    src = (browser_page.PAGES / "babylon_render.mjs").read_text()
    m = re.search(r"export const LTC_LABEL = ((?:'[^']*'|\"[^\"]*\")(?:\s*\+\s*(?:'[^']*'|\"[^\"]*\"))*);", src)
    assert m is not None
    page_label = "".join(s[1:-1] for s in re.findall(r"'[^']*'|\"[^\"]*\"", m.group(1)))
    assert page_label == RECT_LTC_LABEL
    assert "Heitz" in page_label and "not obtainable offline" in page_label


def _babylon(scene: rs.RenderScene, table: str = "heitz", specular: float | None = None) -> tuple[np.ndarray, dict]:
    from validate.gl import browser_page
    from validate.gl.egl import GLUnavailable

    d = scene.engine_json()
    d["options"] = {"ltcTable": table}
    if specular is not None:  # a dielectric (F0 = 0.04 · specular) at roughness 0.5: the LTC tables matter
        d["material"] = dict(d["material"], specular=specular, roughness=0.5)
    try:
        r = browser_page.call("babylon.html", "renderBabylon", d)
    except GLUnavailable as exc:
        pytest.skip(f"babylon cannot render here: {exc}")
    n = scene.resolution
    return browser_page.decode_f32(r["data"], (n, n, 4))[::-1].copy(), dict(r.get("info") or {})


@pytest.mark.slow
def test_babylon_rect_geometry_and_table_independence() -> None:
    for scene in rs.rect_scenes(SMALL):
        img, info = _babylon(scene)
        [light] = info["lights"]
        assert light["ltc_tables"] == RECT_LTC_LABEL
        assert light["intensity"] == scene.lights[0].intensity  # photometric scale 1: the nits go in unchanged
        corners = np.array(light["rect_corners"])
        want = rs.rect_corners(scene.lights[0])
        # the same four corners (the shader's start at the other end of the width), to float32 rounding
        assert np.abs(corners[:, None, :] - want[None]).max(-1).min(-1).max() < 1e-6
        assert not np.isnan(img).any()
        const, _ = _babylon(scene, "constant")
        np.testing.assert_array_equal(img, const)  # Lambertian: form factor only, no table
        spec, _ = _babylon(scene, "heitz", specular=1.0)
        spec_const, _ = _babylon(scene, "constant", specular=1.0)
        lit = spec[..., 3] > 0
        # power: with a specular layer the table reaches the pixels (measured max |Δ| 0.75 plane, 1.2 sphere)
        assert np.abs(spec[lit, :3] - spec_const[lit, :3]).max() > 0.1


@pytest.mark.slow
def test_babylon_rect_area_light_in_nits_with_its_form_factor_divided_out() -> None:
    from validate.reference.render_reference import render_reference

    scene = rs.rect_scenes(SMALL)[1]
    ref = render_reference(scene, 256, 8, 0)
    img, _ = _babylon(scene)
    mask = interior_mask(ref.hit, img[..., 3]) & rs.rect_above_horizon(scene)
    exact, sphere = rs.rect_form_factors(scene)
    fixed = img[..., :3] * np.where(sphere > 0, exact / np.where(sphere > 0, sphere, 1.0), 1.0)[..., None]
    b = compute.DIRECT_BUDGET_OF_PEAK * np.nanmax(ref.mean)
    assert judge(fixed, ref.mean, ref.stderr, 7, mask, b, "").fraction_accepted >= MIN_ACCEPTED
    assert judge(fixed * 1.02, ref.mean, ref.stderr, 7, mask, b, "").fraction_accepted < MIN_ACCEPTED  # power
    area = scene.lights[0].area()
    assert judge(fixed / (np.pi * area), ref.mean, ref.stderr, 7, mask, b, "").fraction_accepted < MIN_ACCEPTED
    # the regression it keeps: the clipped-sphere form factor itself is not the integral
    assert judge(img[..., :3], ref.mean, ref.stderr, 7, mask, b, "").fraction_accepted < MIN_ACCEPTED
