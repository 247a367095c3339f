"""The ``sh9`` experiment end to end: its claims on the built-in environments and on the paper's probes.

Thresholds are the claims' own (R&H 2001: mean < 1 %, max < 5 % of Φ; the directional bound
3/32 and 3.07 %; the published table ±0.01) — the experiment applies them bound-based
(measured + uncertainty), and these tests assert the claims and the figures behind them.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from validate.experiments import Context, run_experiment
from validate.experiments import sh9 as sh9_exp
from validate.metrics.irradiance_error import WORST_CASE_MAX, WORST_CASE_MEAN
from validate.scenes.environment import Environment
from validate.scenes.probes import read_published_sh9

# Independent figures quoted in the issue (a numpy quadrature over the angular maps, luminance,
# flux-normalised): grace 0.86 % / 3.26 %, rnl ≈ 0.4 % / 1.4 %. Our pipeline resamples the angular
# map to a 512×1024 lat-long map and uses 10k Fibonacci normals; measured differences are ≤ 0.04 %
# (max) and ≤ 0.02 % (mean), so ±0.1 % / ±0.05 % absolute is a margin of ~2.5×.
INDEPENDENT = {"grace_probe.hdr": (0.0086, 0.0326), "rnl_probe.hdr": (0.004, 0.014)}
INDEPENDENT_TOL_MEAN = 5e-4
INDEPENDENT_TOL_MAX = 1e-3


@pytest.fixture(scope="module")
def quick_result(tmp_path_factory: pytest.TempPathFactory):
    ctx = Context(out_dir=tmp_path_factory.mktemp("sh9"), quick=True, show_progress=False, log=lambda _: None)
    return run_experiment("sh9", ctx), ctx


def test_every_claim_on_builtin_environments_passes(quick_result) -> None:
    res, _ = quick_result
    ids = {c.id for c in res.claims}
    for needed in ("sh9.bound.max", "sh9.bound.mean", "sh9.bandlimited.exact", "reference.convergence",
                   "reference.closed_form.constant", "reference.closed_form.two_tone",
                   "reference.closed_form.bandlimited", "sh9.worst_case.near_directional.max",
                   "sh9.worst_case.near_directional.mean"):
        assert needed in ids
    failed = [(c.id, c.measured, c.uncertainty, c.threshold) for c in res.claims if not c.passed]
    assert not failed


def test_bound_holds_per_environment_and_strong_sun_is_a_finding(quick_result) -> None:
    res, _ = quick_result
    envs = res.data["environments"]
    for name, e in envs.items():
        st = e["errors"]["flux_rgb"]
        assert st["max"] <= WORST_CASE_MAX + st["max_uncertainty"], name
        assert st["mean"] <= WORST_CASE_MEAN + st["mean_uncertainty"] + 1e-4, name  # 3.0703 % exact bound
    # sunsky exceeds the paper's 1 %/5 %: reported as a finding, not a failed claim
    sun = envs["sunsky_30deg"]["errors"]["flux_luminance"]
    assert sun["max"] > 0.05
    assert any("sunsky_30deg" in f for f in res.findings)


def test_error_falls_with_sh_order_on_smooth_lighting(quick_result) -> None:
    res, _ = quick_result
    sweep = res.data["environments"]["disc_on_sky"]["order_sweep"]
    assert sweep["max"][8] < sweep["max"][2] < sweep["max"][0]
    band = res.data["environments"]["bandlimited"]["order_sweep"]
    assert band["max"][2] < 1e-3 < band["max"][1]  # exact from order 2 on, not before


def test_figures_exist_and_json_keys_are_stable(quick_result) -> None:
    res, ctx = quick_result
    js = res.to_json()
    env = js["environments"]["two_tone"]
    assert np.array(env["coefficients"]).shape == (9, 3)
    assert set(env["errors"]) == {"flux_luminance", "flux_rgb", "relative", "peak"}
    assert {"mean", "max"} <= set(env["errors"]["flux_luminance"])
    for c in js["claims"]:
        assert {"id", "description", "metric", "threshold", "measured", "uncertainty", "passed"} <= set(c)
    for section in res.sections:
        for row in section.gallery:
            for fig in row:
                assert (Path(ctx.out_dir) / fig.path).is_file(), fig.path


@pytest.mark.probes
@pytest.mark.parametrize("filename", sorted(INDEPENDENT))
def test_paper_probes_reproduce_rh2001(filename: str, load_probe: Callable[[str], Environment],
                                       reference_dir: Path, tmp_path: Path) -> None:
    env = load_probe(filename)
    ctx = Context(out_dir=tmp_path, show_progress=False)
    r = sh9_exp.analyse_environment(env, ctx, sh9_exp._settings(quick=False), read_published_sh9())
    st = r["errors"]["flux_luminance"]
    assert st["mean"] + st["mean_uncertainty"] < sh9_exp.PAPER_MEAN
    assert st["max"] + st["max_uncertainty"] < sh9_exp.PAPER_MAX
    mean_ind, max_ind = INDEPENDENT[filename]
    assert abs(st["mean"] - mean_ind) < INDEPENDENT_TOL_MEAN
    assert abs(st["max"] - max_ind) < INDEPENDENT_TOL_MAX
    # the other normalisations measure the same approximation more harshly (issue: 3–10 % relative)
    assert 0.03 <= r["errors"]["relative"]["mean"] <= 0.10
    assert r["convergence"] < sh9_exp.CONVERGENCE
    pub = r["published"]
    assert pub["max_deviation"] < 0.01
    assert pub["scale"] == pytest.approx({"grace_probe.hdr": 3.19, "rnl_probe.hdr": 9.97}[filename], rel=0.01)


@pytest.mark.probes
def test_copies_of_paper_probes_get_no_published_row(load_probe: Callable[[str], Environment],
                                                     reference_dir: Path) -> None:
    from validate.scenes.probes import published_row

    assert published_row(load_probe("grace_probe.hdr")) == "grace"
    assert published_row(load_probe("grace_probe_latlong.exr")) is None
    assert published_row(load_probe("ict_grace_256x128.hdr")) is None
