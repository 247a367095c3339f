"""(b) Babylon's CDF irradiance (Babylon PR 16247): the scene, the energy ratio, the claims and their power checks.

Default run: synthetic numbers only (no browser, no Mitsuba). ``slow``: Babylon renders the scene at cube size 64
with and without supersampling against Mitsuba (needs Chromium, node_modules and the probes folder).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from validate.experiments.renders.cdf.claims import cdf_claims
from validate.experiments.renders.cdf.compute import CdfResult, CdfScene, energy_ratio
from validate.metrics.pixel_z import judge
from validate.scenes import render_cdf_scenes as rcs


def test_rolled_probe_puts_the_sun_at_its_azimuth_and_keeps_every_texel() -> None:
    t = np.full((8, 16, 3), 0.5)
    t[3, 2] = 100.0
    r = rcs.rolled_probe(t, 180.0)  # φ = 2π(j + ½)/W = π → j = 7.5 → the column 7 (round(7.5) = 8 − ½ rounding)
    j = rcs.sun_column(r)
    assert abs(2 * np.pi * (j + 0.5) / 16 - np.pi) <= 2 * np.pi / 16
    assert np.array_equal(np.sort(r, axis=None), np.sort(t, axis=None))


def test_energy_ratio_and_its_uncertainty() -> None:
    mean = np.full((4, 4, 3), 2.0)
    se = np.full((4, 4, 3), 0.02)
    mask = np.ones((4, 4), bool)
    r, u = energy_ratio(0.9 * mean, mean, se, mask)
    assert r == pytest.approx(0.9)
    # r·√(Σ s²)/Σ m = 0.9 · 0.02·√48 / (2·48)
    assert u == pytest.approx(0.9 * 0.02 * np.sqrt(48) / 96)


def _scene(ratios: dict[tuple[int, str], float]) -> CdfScene:
    mean = np.full((8, 8, 3), 1.0)
    se = np.full((8, 8, 3), 1e-3)
    mask = np.ones((8, 8), bool)
    probe = np.full((8, 16, 3), 0.5)
    probe[3, 2] = 100.0
    sc = CdfScene(rcs.cdf_lambert_scene(probe, 8), mean, se, 7, mask, "synthetic")
    for (n, v), k in ratios.items():
        img = k * mean
        r, u = energy_ratio(img, mean, se, mask)
        sc.results.append(CdfResult(n, v, img, judge(img, mean, se, 7, mask, 0.0, ""), r, u, {}, 0.0, 0.0))
    return sc


def test_claims_pass_on_the_pr_s_defect_and_their_power_checks_fail(tmp_path: Path) -> None:
    # the measured pattern (rooitou_park_1k): pre-PR dark at 64, bright at 128; shipped ≈ 20 % dark everywhere
    sc = _scene({(64, "shipped"): 0.76, (64, "pre16247"): 0.31, (128, "shipped"): 0.81, (128, "pre16247"): 1.08,
                 (256, "shipped"): 0.79, (256, "pre16247"): 0.79})
    cs = {c.id: c for c in cdf_claims([sc])}
    assert set(cs) == {"renders.babylon.cdf_irradiance.pre16247.regression",
                       "renders.babylon.cdf_irradiance.shipped.regression",
                       "renders.babylon.cdf_irradiance.supersample"}
    for c in cs.values():
        assert c.passed and c.power is not None and c.power.fails, c.id
    from validate.experiments.renders.cdf.report import cdf_data, cdf_findings, cdf_sections, cdf_table

    assert len(cdf_table(sc).rows) == 6 and len(cdf_findings([sc])) == 2
    assert cdf_data([sc])["cdf_lambert"]["results"]["64 pre16247"]["ratio"] == pytest.approx(0.31)

    class Ctx:
        def figure_path(self, experiment: str, filename: str) -> tuple[Path, str]:
            return tmp_path / filename, filename

    (section,) = cdf_sections([sc], Ctx())
    assert (tmp_path / section.figures[0].path).is_file()


def test_claims_fail_on_an_engine_that_matches_the_truth() -> None:
    sc = _scene({(n, v): 1.0 for n in (64, 128, 256) for v in rcs.CDF_VARIANTS})
    cs = {c.id: c for c in cdf_claims([sc])}
    assert not cs["renders.babylon.cdf_irradiance.pre16247.regression"].passed
    assert not cs["renders.babylon.cdf_irradiance.shipped.regression"].passed
    assert not cs["renders.babylon.cdf_irradiance.supersample"].passed  # 0 < 0 does not hold


@pytest.mark.slow
def test_babylon_cdf_without_supersampling_is_darker_at_64(probes_dir: Path) -> None:
    from validate.gl.egl import GLUnavailable
    from validate.local_models import render
    from validate.reference.render_reference import render_reference
    from validate.scenes.loaders import load_environment

    path = probes_dir / rcs.CDF_PROBE_FILE
    if not path.is_file():
        pytest.skip(f"{path}: not found")
    scene = rcs.cdf_lambert_scene(load_environment(path, "latlong", False).radiance, 32)
    ref = render_reference(scene, 256, 8, 0)
    out = {}
    for v in rcs.CDF_VARIANTS:
        try:
            er = render.render(rcs.engine_name(64, v), scene)
        except GLUnavailable as exc:
            pytest.skip(f"babylon cannot render here: {exc}")
        assert er.info["cdf"]["irradiance"] and er.info["cdf"]["supersample"] == (v == "shipped")
        from validate.metrics.pixel_z import interior_mask

        out[v] = energy_ratio(er.image[..., :3].astype(np.float64), ref.mean, ref.stderr,
                              interior_mask(ref.hit, er.image[..., 3]))
    # measured 0.31 (pre) and 0.76 (shipped); each ratio's σ ≈ 3e-4: the 0.3 gap is > 100 σ
    assert out["pre16247"][0] + 5 * out["pre16247"][1] < 0.5
    assert out["shipped"][0] - out["pre16247"][0] > 0.3


def test_the_experiment_hooks_carry_the_cdf_scene() -> None:
    from validate.experiments import renders
    from validate.experiments.base import part_measurements, settings_json
    from validate.experiments.renders.compute import Measurements
    from validate.experiments.renders.settings import FULL, QUICK

    sc = _scene({(64, "shipped"): 0.76, (64, "pre16247"): 0.31, (256, "shipped"): 0.79, (256, "pre16247"): 0.79})
    m = Measurements(FULL, [], cdf=[sc])
    (cdf,) = [p for p in renders.PARTS if p.KEY == "cdf"]  # a part of renders: base.run appends its stages
    pm = part_measurements(m, cdf.KEY)
    assert "cdf_lambert" in cdf.data(pm)["cdf_irradiance"]
    assert settings_json(renders.reported_settings(FULL, m, None))["cdf_sizes"] == [64, 128, 256]
    assert {c.id for c in cdf.claims(pm)} >= {"renders.babylon.cdf_irradiance.pre16247.regression"}
    assert any("PR 16247" in f for f in cdf.findings(pm))
    # quick renders no Babylon: no CDF work (no data key), and its settings block is unchanged
    assert QUICK.cdf_sizes == () and cdf.data([]) == {}
    assert "cdf_sizes" not in renders.reported_settings(QUICK, Measurements(QUICK, []), None)
