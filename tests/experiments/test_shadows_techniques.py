"""Shadow techniques as plug-ins: one registration gives a technique its table rows, JSON entry and claims;
the output contract; ``check_shadow`` for :mod:`validate.testing`; the convergence-rate fit and its power."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.experiments import Context
from validate.experiments import shadows as exp
from validate.experiments.shadows import report as rep
from validate.experiments.shadows.check import check_shadow
from validate.experiments.shadows.claims import RATE_SLOPE_MAX
from validate.experiments.shadows.compute import fit_rate
from validate.experiments.shadows.settings import QUICK
from validate.local_models import shadow
from validate.local_models.shadow import percentage_closer
from validate.local_models.shadow import shadow_map as smod
from validate.metrics import shadow_error as se
from validate.scenes.latlong import luminance

# A small run: the quick scene at half the pixels, two radii, two resolutions (the wiring, not the numbers).
TINY = replace(QUICK, width=48, height=36, spp=16, passes=4, visibility_side=8, radii=(0.02, 1.0),
               resolutions=(256, 512), default_resolution=512, bias_resolution=512, kernel_resolution=256,
               kernel_radii=(1.0,), bias_scales=(0.0, 1.0), kernels=(1, 5), rate_grid=64)
HALF_THRESHOLD = 0.5  # declared umbra threshold of the half-shadow plug-in: its umbra error, ½ Y(ρ/π E)/L_norm over
#                       the umbra, is 0.39 here (umbra pixels are darker than the mean lit pixel), and × 1.5 = 0.58
#                       (the power check) exceeds it


UMBRA_SLIVER = 0.01
PCSS_UMBRA_MAX = 0.1  # PCSS's umbra error at 512², r = 1 m: measured 5.7 % (its filter leaks 7 % of the light)


def _half(shadow_map, light, points, normals) -> np.ndarray:  # noqa: ANN001 (the family's contract)
    """A deliberately poor plug-in: V′ = ½ everywhere."""
    return np.full(len(points), 0.5)


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory: pytest.TempPathFactory):
    shadow.register("test_half", "V′ = ½ everywhere", thresholds={"umbra.r1": HALF_THRESHOLD},
                    source="test: half of the light everywhere")(_half)
    try:
        ctx = Context(out_dir=tmp_path_factory.mktemp("shadows_tiny"), quick=True, show_progress=False,
                      log=lambda _: None)
        m = exp.compute(ctx, TINY)
        yield m, exp.claims(m), rep.techniques(m), exp.sections(m, ctx), ctx
    finally:
        shadow.unregister("test_half")


def test_a_registered_technique_gets_rows_entries_and_claims(tiny_run) -> None:
    m, claims, entries, sections, ctx = tiny_run
    assert [t.name for t in m.techniques][:3] == ["hard", "pcf", "pcss"] and "test_half" in entries
    e = entries["test_half"]
    assert e["family"] == "shadow" and not e["builtin"]
    umbra = e["metrics"]["umbra.r1"]
    f = m.frame
    in_umbra = se.region_masks(f.ref(1.0)[2])["umbra"]
    half = luminance(smod.shade(f.albedo, f.irradiance[1.0], np.full(in_umbra.size, 0.5)))[in_umbra]
    # the reference umbra is black up to slivers of disc the 8×8 visibility rays miss (≤ 1/64 of it): 1 %
    assert umbra["value"] == pytest.approx(half.mean() / f.norm[1.0], rel=UMBRA_SLIVER)
    table = sections[2].tables[0]
    assert sum(row[1] == "test_half" for row in table.rows) == 2  # one row per radius
    assert any(h.startswith("test_half") for h in sections[2].tables[1].headers)  # resolution table column
    assert any("test_half" in f.path for row in sections[0].gallery for f in row)  # its error map
    for row in sections[0].gallery:
        for f in row:
            assert (Path(ctx.out_dir) / f.path).is_file()
    c = next(c for c in claims if c.id == "shadows.technique.test_half.umbra.r1")
    assert c.passed and c.power is not None and c.power.fails  # 0.39 < 0.5 passes; 1.5 × 0.39 = 0.58 fails
    assert c.power.measured == pytest.approx(1.5 * c.measured)


def test_a_bad_technique_gives_the_one_line_error(tiny_run) -> None:
    m = tiny_run[0]
    shadow.register("test_nan")(lambda sm, light, p, n: np.full(len(p), np.nan))
    try:
        sm = smod.build_shadow_map(*_map_inputs(m))
        with pytest.raises(ValidateError, match=r"technique 'test_nan' \(shadow\): returned \d+ non-finite"):
            shadow.call("test_nan", sm, m.frame.scenes[1.0].light, m.frame.position, m.frame.normal)
    finally:
        shadow.unregister("test_nan")


def _map_inputs(m) -> tuple:  # noqa: ANN001
    from validate.reference import shadow_render as sr

    scene = m.frame.scenes[m.r_pt]
    return sr.load_scene(scene, with_light=False), scene.light, m.frame.position, 64


def test_check_shadow_tells_a_good_technique_from_a_wrong_one() -> None:
    good = check_shadow(percentage_closer.shadow_pcss, radius=1.0, resolution=512)
    wrong = check_shadow(lambda sm, light, p, n: np.ones(len(p)), radius=1.0, resolution=512, name="off")
    assert good.technique == "shadow_pcss" and wrong.technique == "off"
    assert good.umbra.mean < PCSS_UMBRA_MAX < 0.5 < wrong.umbra.mean  # shadows off: the umbra is fully lit
    assert good.penumbra.mean + good.penumbra.mean_uncertainty < wrong.penumbra.mean
    assert good["r=1"].false_light.mean < 0.01 and wrong.false_light.mean == 1.0
    assert set(good.metrics) >= {"total", "lit", "penumbra", "umbra", "false_shadow", "false_light", "leak", "flip"}


def test_rate_fit_recovers_the_slope_and_its_power() -> None:
    """Counts k ∝ R⁻¹ give slope −1 (claim passes); capping the top resolution at the one below (the
    power check's perturbation) gives −0.5 over three resolutions 4× apart (claim fails)."""
    ress = [256, 1024, 4096]
    k = [4000, 1000, 250]
    b, se = fit_rate(ress, k)
    assert b == pytest.approx(-1.0, abs=1e-9) and b + se < RATE_SLOPE_MAX
    bc, sec = fit_rate(ress, k[:-1] + [k[-2]])
    assert bc + sec > RATE_SLOPE_MAX
