"""The ``ibl`` experiment end to end at quick settings (default test run), its claims' power checks, the
``specular`` family inside it, and ``check_specular`` for validate.testing.

The experiment runs once per module (cold cache: ≈ 30 s on an idle 2-core machine); a deliberately wrong
specular plug-in is registered for that run, so the test also shows a plug-in getting its row, its
results.json entry and its declared-threshold claim.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.experiments import Context, run_experiment
from validate.experiments.base import ExperimentResult
from validate.local_models import irradiance, specular
from validate.local_models.irradiance import sh_truncated
from validate.local_models.specular import prefiltered_specular as ps
from validate.reference import ibl_render as rr
from validate.stats import t_to_z

PLUGIN = "test_phong_too_bright"
PLUGIN_LIMIT = 0.01  # declared: mean relative error < 1 %; the plug-in is 30 % too bright, so its claim fails

CLAIMS = ["ibl.diffuse_map.within_1pct", "ibl.sh_vs_convolution.bound", "ibl.reference.diffuse_consistency",
          "ibl.phong.chi2", "ibl.phong.furnace", "ibl.split_sum.constant_environment", "ibl.phong.normal_incidence",
          "ibl.mix.physical_blend"]


IRR_PLUGIN = "test_sh9_brighter"


def sh9_brighter(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:

    return 1.02 * sh_truncated.sh9(radiance, normals)


def too_bright(radiance: np.ndarray, brdf: dict, normals: np.ndarray, views: np.ndarray) -> np.ndarray:
    return 1.3 * ps.phong_prefiltered(radiance, brdf, normals, views)


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[ExperimentResult, Path]]:
    out = tmp_path_factory.mktemp("ibl_quick")
    specular.register(PLUGIN, "30 % too bright Phong map (test plug-in)", thresholds={"relative.mean": PLUGIN_LIMIT},
                      source="test: a threshold the plug-in cannot meet", brdf=("phong",))(too_bright)
    irradiance.register(IRR_PLUGIN, "SH9 2 % too bright (test plug-in)",
                        thresholds={"flux_luminance.mean": 0.01, "relative.mean": 0.5},
                        source="test: one sh9 metric, one ibl metric")(sh9_brighter)
    try:
        yield run_experiment("ibl", Context(out_dir=out, quick=True, show_progress=False)), out
    finally:
        specular.unregister(PLUGIN)
        irradiance.unregister(IRR_PLUGIN)


def test_quick_run_end_to_end(run: tuple[ExperimentResult, Path]) -> None:
    """Every built-in claim present and passing, figures written, JSON-able, every technique entered."""
    res, out = run
    ids = {c.id for c in res.claims}
    assert set(CLAIMS) <= ids
    failed = [c.id for c in res.claims if not c.passed and ".technique.test_" not in c.id]
    assert not failed, failed
    for sec in res.sections:
        for fig in sec.figures:
            assert (out / fig.path).is_file(), fig.path
    json.dumps(res.to_json(), allow_nan=True)
    assert res.data["reported_face"] is not None
    for tech in list(irradiance) + list(specular):
        entry = res.techniques[tech.name]
        assert entry["family"] == tech.family
        for metric in entry["metrics"].values():
            assert math.isfinite(metric["value"]) and math.isfinite(metric["uncertainty"])


def test_plugin_gets_row_entry_and_claim(run: tuple[ExperimentResult, Path]) -> None:
    res, _ = run
    table_rows = [r for sec in res.sections for t in sec.tables for r in t.rows]
    assert any(PLUGIN in [str(x) for x in row] for row in table_rows)
    entry = res.techniques[PLUGIN]
    assert set(entry["cases"]) == {"phong_10", "phong_100"}  # Phong only, as declared
    claim = next(c for c in res.claims if c.id == f"ibl.technique.{PLUGIN}.relative.mean")
    assert not claim.passed and claim.measured > 0.2


def test_irradiance_plugin_thresholds_on_other_metrics_are_left_to_sh9(run: tuple[ExperimentResult, Path]) -> None:
    """An irradiance plug-in's threshold on sh9's flux_luminance does not stop ibl (judged by sh9); its
    threshold on relative.mean becomes an ibl claim."""
    res, _ = run
    ids = {c.id for c in res.claims}
    assert f"ibl.technique.{IRR_PLUGIN}.relative.mean" in ids
    assert f"ibl.technique.{IRR_PLUGIN}.flux_luminance.mean" not in ids
    assert IRR_PLUGIN in res.techniques


@pytest.mark.parametrize("claim_id", CLAIMS)
def test_power_check_fails(run: tuple[ExperimentResult, Path], claim_id: str) -> None:
    """Each claim family, re-evaluated under its perturbation (a bug-sized change), fails."""
    claim = next(c for c in run[0].claims if c.id == claim_id)
    assert claim.power is not None and claim.power.fails, (claim.power, claim.measured, claim.threshold)
    assert "issue" not in claim.source.lower()


# ------------------------------------------------------------------------------------------------
# The BSDF checks on their own (the power checks in isolation)
# ------------------------------------------------------------------------------------------------

def test_chi2_accepts_modphong_and_rejects_off_by_one_pdf() -> None:
    """Measured: p = 0.27 (s = 10, normal incidence, 10⁶ samples) vs p < 10⁻¹⁰ against the pdf of s + 1."""
    good = rr.chi2_bsdf({"type": rr.PHONG_PLUGIN, "exponent": 10.0}, 1.0, samples=1_000_000)
    bad = rr.chi2_bsdf({"type": rr.PHONG_PLUGIN, "exponent": 10.0}, 1.0, {"type": rr.PHONG_PLUGIN, "exponent": 11.0},
                       samples=1_000_000)
    assert good.statistic_ok and good.p_value > 0.01
    assert bad.p_value < 1e-6


def test_furnace_sees_an_eval_bug() -> None:
    """Path-traced furnace of s = 1 at normal incidence: albedo 1 within 4σ; with eval() normalised by
    (s+1)/2π (⅔ of the right value) the MIS estimate is off by > 6σ (measured z = −6.7 at 262k paths)."""
    ok = rr.furnace({"type": rr.PHONG_PLUGIN, "exponent": 1.0}, [1.0], spp=1 << 12)
    bad = rr.furnace({"type": rr.PHONG_PLUGIN, "exponent": 1.0, "eval_scale": 2.0 / 3.0}, [1.0], spp=1 << 12)
    assert abs(t_to_z((ok.mean[0] - 1.0) / ok.stderr[0], ok.passes - 1)) < 4
    assert abs(t_to_z((bad.mean[0] - 1.0) / bad.stderr[0], bad.passes - 1)) > 6


# ------------------------------------------------------------------------------------------------
# The specular family and check_specular
# ------------------------------------------------------------------------------------------------

def test_specular_contract_errors_name_the_technique() -> None:
    def nan_model(radiance: np.ndarray, brdf: dict, normals: np.ndarray, views: np.ndarray) -> np.ndarray:
        return np.full((len(normals), 3), np.nan)

    specular.register("test_nan_specular", brdf=("phong",))(nan_model)
    try:
        n = np.array([[0.0, 0.0, 1.0]])
        with pytest.raises(ValidateError, match="technique 'test_nan_specular' \\(specular\\).*non-finite"):
            specular.call("test_nan_specular", np.ones((8, 16, 3)), {"model": "phong", "exponent": 10.0}, n, n)
    finally:
        specular.unregister("test_nan_specular")
    with pytest.raises(ValidateError, match="Phong-prefiltered map"):
        specular.call("phong_prefiltered", np.ones((8, 16, 3)), {"model": "ggx", "alpha": 0.3}, n, n)


def test_builtin_specular_techniques_under_constant_light() -> None:
    """Uniform unit light: the Phong maps return k_s exactly (normalised lobes, ratio estimator) and the
    split sum returns F0·A + B of its table."""
    ones = np.ones((16, 32, 3))
    n = np.tile([0.0, 1.0, 0.0], (3, 1))
    v = np.array([[0.0, 1.0, 0.0], [0.6, 0.8, 0.0], [0.0, 0.6, 0.8]])
    for name in ("phong_prefiltered", "phong_prefiltered_s"):
        out = specular.call(name, ones, {"model": "phong", "exponent": 20.0, "reflectance": 0.5}, n, v)
        assert np.allclose(out, 0.5, rtol=1e-5)
    from validate.local_models.specular import split_sum as ss

    a, b = ss.default_dfg_table().lookup(np.sum(n * v, axis=1), 0.3)
    out = specular.call("split_sum_ggx", ones, {"model": "ggx", "alpha": 0.3}, n, v)
    assert np.allclose(out[:, 0], a + b, rtol=1e-5)


def test_check_specular_separates_right_from_wrong() -> None:
    """validate.testing entry point: the built-in s + 1 map and the same map 30 % too bright, on one
    environment: the wrong one's bias is larger by ≈ 0.3 (1 + bias)."""
    from validate.experiments.ibl.check import check_specular

    brdf = {"model": "phong", "exponent": 10.0}
    good = check_specular("phong_prefiltered", brdf=brdf, environments=("disc_on_sky",))
    bad = check_specular(too_bright, brdf=brdf, environments=("disc_on_sky",))
    assert good.family == "specular" and set(good.metrics) == {"relative", "bias"}
    assert good["disc_on_sky"].bias.mean_uncertainty > 0
    assert bad.bias.mean - good.bias.mean > 0.25
    with pytest.raises(ValidateError, match="check_specular: BRDF"):
        check_specular("phong_prefiltered", brdf={"model": "lambert"})


def test_bias_is_signed_model_minus_reference_in_json_and_table(run: tuple[ExperimentResult, Path]) -> None:
    """results.json and the report agree on the bias, Σ(Y_model − Y_ref)/ΣY_ref, signed: the plug-in is 1.3 ×
    phong_prefiltered on the same pixels, so (linearity) its bias is 1.3 (1 + b) − 1 with b phong_prefiltered's —
    in its JSON entry (per case and worst) and in its table rows, under the header that says so."""
    from validate.experiments.ibl.report import BIAS_HEADER

    res, _ = run
    entry = res.techniques[PLUGIN]
    cases = {k: v["bias"]["value"] for k, v in entry["cases"].items()}
    base = res.techniques["phong_prefiltered"]["cases"]
    for k, b in cases.items():
        assert b == pytest.approx(1.3 * (1.0 + base[k]["bias"]["value"]) - 1.0, rel=1e-9), (k, b)
    assert entry["metrics"]["bias"]["value"] in cases.values()
    tables = [t for sec in res.sections for t in sec.tables if BIAS_HEADER in t.headers]
    col = tables[0].headers.index(BIAS_HEADER)
    cells = [str(r[col]) for t in tables for r in t.rows if PLUGIN in [str(x) for x in r]]
    assert len(cells) == len(cases)
    shown = sorted(float(c.split("%")[0]) / 100 for c in cells)
    assert np.allclose(shown, sorted(cases.values()), rtol=5e-3), (shown, cases)


def test_khronos_sampler_rows_or_not_run_with_the_reason(run: tuple[ExperimentResult, Path]) -> None:
    """The glTF-IBL-Sampler techniques get their rendered-sphere rows, the part its furnace and orientation (units
    E/π, the measured rotation); without the tool or a Vulkan device both are ``not_run`` with the reason."""
    from validate.local_models import khronos_ibl

    res, _ = run
    why = khronos_ibl.unavailable()
    names = ("khronos_ibl_lambertian", "khronos_ibl_ggx")
    if why is not None:
        assert any(why in n.why for n in res.not_run) and not set(names) & set(res.techniques)
        return
    assert set(names) <= set(res.techniques) and res.techniques["khronos_ibl_ggx"]["cases"]
    k = res.data["khronos_ibl_sampler"]
    assert k["furnace"]["lambertian_max_deviation"] < 1e-5 and k["furnace"]["ggx_max_deviation"] < 1e-5
    assert k["orientation"]["rotation_u_texels"] < 1.0 < 10.0 < k["orientation"]["mirrored_u_texels"]
