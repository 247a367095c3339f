"""The ``renders`` diagnoses (docs/experiments/renders.md, "three.js VSM columns"): the cause, switched off.

three.js 0.187's VSM darkens columns of the fully lit plane because it draws the receiver into its shadow map and
stores the moments as half floats; keeping the receiver out of the map, or the moments in RG32F
(three_shadows.mjs's diagnostic ``sh.diag``), leaves no dark lit pixel. ``slow``: it renders in Chromium.
"""

from __future__ import annotations

import numpy as np
import pytest

from validate.scenes import render_shadow_scenes as rss

DARK = 0.995  # shadow factor below which a lit pixel counts as darkened (the artefact's s ≤ 0.86 at 32², measured)


def _lit_shadow_factor(scene: rss.ShadowScene, diag: dict) -> np.ndarray:
    from validate.gl import browser_page
    from validate.gl.egl import GLUnavailable

    d = scene.with_shadow_type("vsm").engine_json()
    d["shadow"]["diag"] = diag
    d["options"] = {}
    try:
        r = browser_page.call("three.html", "renderThree", d)
    except GLUnavailable as exc:
        pytest.skip(f"three cannot render here: {exc}")
    n = scene.resolution
    img = browser_page.decode_f32(r["data"], (n, n, 4))[::-1, :, :3].astype(float)
    return (img.mean(-1) / rss.unshadowed_radiance(scene))[rss.regions(scene)["lit"]]


@pytest.mark.slow
def test_three_vsm_lit_columns_are_the_receiver_in_its_half_float_map() -> None:
    scene = rss.spot_shadow_scene(32)  # 32²: the directional scene's columns fall between the pixels (none dark)
    as_run = _lit_shadow_factor(scene, {})
    assert (as_run < DARK).sum() >= 16  # measured 38 of 672 (2 columns), s ≥ 0.860
    for off in ({"excludeReceiver": 1}, {"floatMoments": 1}, {"bias": -2e-4}):
        assert (_lit_shadow_factor(scene, off) < DARK).sum() == 0, off
