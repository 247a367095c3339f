"""The ``sh9`` experiment end to end: its claims on the built-in environments and on the paper's probes.

Thresholds are the claims' own (R&H 2001: mean < 1 %, max < 5 % of Φ; the directional bound
3/32 and 3.07 %; the published table ±0.01) — the experiment applies them bound-based
(measured + uncertainty), and these tests assert the claims and the figures behind them.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.experiments import Context, run_experiment
from validate.experiments import sh9 as sh9_exp
from validate.experiments.sh9 import report as sh9_report
from validate.experiments.sh9.claims import BANDLIMITED_EXACT, CONVERGENCE, PAPER_MAX, PAPER_MEAN
from validate.experiments.sh9.compute import Measurements, analyse_environment
from validate.local_models import irradiance
from validate.local_models.irradiance import sh_truncated
from validate.metrics.irradiance_error import METRIC_NAMES, WORST_CASE_MAX, WORST_CASE_MEAN
from validate.scenes.environment import Environment
from validate.scenes.probes import read_aliases, read_published_sh9

sh9_claims = importlib.import_module("validate.experiments.sh9.claims")  # the module (`sh9.claims` is the function)

# Independent figures quoted in the issue (a numpy quadrature over the angular maps, luminance,
# flux-normalised): grace 0.86 % / 3.26 %, rnl ≈ 0.4 % / 1.4 %. Our pipeline resamples the angular
# map to a 512×1024 lat-long map and uses 10k Fibonacci normals; measured differences are ≤ 0.04 %
# (max) and ≤ 0.02 % (mean), so ±0.1 % / ±0.05 % absolute is a margin of ~2.5×.
INDEPENDENT = {"grace_probe.hdr": (0.0086, 0.0326), "rnl_probe.hdr": (0.004, 0.014)}
INDEPENDENT_TOL_MEAN = 5e-4
INDEPENDENT_TOL_MAX = 1e-3


# Plug-ins registered for the quick run: SH9 itself declaring the theorem's max bound on every environment,
# and declaring exactness (0.1 %) on the two environments SH9 represents exactly.
PLUGIN_BOUND, PLUGIN_EXACT = "test_sh9_bound", "test_sh9_exact"
EXACT_SCOPE = ("two_tone", "bandlimited")
CLAIM_FAMILIES = ("sh9.bound.", "sh9.worst_case.", "sh9.bandlimited.", "reference.convergence",
                  "reference.closed_form.", "reference.pathtrace.", "sh9.technique.", "sh9.cmgen_auto.")
# built-in techniques with declared thresholds (issue 15): the Hölder bound of their window (all environments)
# or their directional closed form (near_directional)
DECLARED = {"sh9_hanning": 8, "sh9_lanczos": 8, "sh1_geomerics": 1, "zh3_hallucinated": 1, "zh3_stored": 1}


@pytest.fixture(scope="module")
def quick_result(tmp_path_factory: pytest.TempPathFactory):
    irradiance.add(PLUGIN_BOUND, sh_truncated.sh9, "SH9 declaring the directional bound",
                   thresholds={"flux_rgb.max": WORST_CASE_MAX}, source="R&H JOSA 2001: |K̃ − max(x,0)| ≤ 3/32")
    irradiance.add(PLUGIN_EXACT, sh_truncated.sh9, "SH9 declaring exactness on order-≤ 2 lighting",
                   thresholds={"flux_luminance.max": BANDLIMITED_EXACT}, environments=EXACT_SCOPE,
                   source="R&H 2001: order-2 lighting is represented exactly")
    try:
        ctx = Context(out_dir=tmp_path_factory.mktemp("sh9"), quick=True, show_progress=False, log=lambda _: None)
        yield run_experiment("sh9", ctx), ctx
    finally:
        irradiance.unregister(PLUGIN_BOUND)
        irradiance.unregister(PLUGIN_EXACT)


def test_every_claim_on_builtin_environments_passes(quick_result) -> None:
    res, _ = quick_result
    ids = {c.id for c in res.claims}
    for needed in ("sh9.bound.max", "sh9.bound.mean", "sh9.bandlimited.exact", "reference.convergence",
                   "reference.closed_form.constant", "reference.closed_form.two_tone",
                   "reference.closed_form.bandlimited", "reference.closed_form.near_directional",
                   "reference.pathtrace.near_directional", "reference.pathtrace.near_directional.bias",
                   "sh9.worst_case.near_directional.max", "sh9.worst_case.near_directional.mean",
                   f"sh9.technique.{PLUGIN_BOUND}.flux_rgb.max", f"sh9.technique.{PLUGIN_EXACT}.flux_luminance.max"):
        assert needed in ids
    # every claim of the experiment and of this test's plug-ins (other techniques' thresholds are theirs)
    ours = [c for c in res.claims if not c.id.startswith("sh9.technique.") or c.id.split(".")[2] in
            (PLUGIN_BOUND, PLUGIN_EXACT)]
    failed = [(c.id, c.measured, c.uncertainty, c.threshold) for c in ours if not c.passed]
    assert not failed


@pytest.mark.parametrize("family", CLAIM_FAMILIES)
def test_every_claim_family_has_a_failing_power_check(quick_result, family: str) -> None:
    """Issue 10: each claim re-evaluated under a bug-sized perturbation must fail; sources cite, never
    name an issue."""
    res, _ = quick_result
    members = [c for c in res.claims if c.id.startswith(family)]
    assert members, family
    for c in members:
        assert c.power is not None and c.power.perturbation, c.id
        assert c.power.fails, (c.id, c.power)
        assert c.source and "issue" not in c.source.lower(), c.id


@pytest.mark.parametrize("name, n_envs", DECLARED.items())
def test_builtin_declared_thresholds_pass_with_failing_power(quick_result, name: str, n_envs: int) -> None:
    res, _ = quick_result
    (c,) = [c for c in res.claims if c.id == f"sh9.technique.{name}.flux_rgb.max"]
    assert c.passed and c.power.fails and "mirrored" in c.power.perturbation, (c.measured, c.threshold, c.power)
    assert f"worst over {n_envs} environment" in c.description
    assert c.measured > 0.95 * c.threshold  # near_directional nearly attains each bound


def test_cmgen_auto_claims_and_findings(quick_result) -> None:
    """cmgen's window is non-negative everywhere and within its map's kernel bound; near_directional needs the
    strongest window (cut-off near 3), constant lighting none that matters (the bracket's top)."""
    res, _ = quick_result
    by_id = {c.id: c for c in res.claims}
    assert by_id["sh9.cmgen_auto.nonnegative"].measured < 0 < by_id["sh9.cmgen_auto.nonnegative"].power.measured
    envs = res.data["environments"]
    assert 3.0 <= envs["near_directional"]["cmgen_auto"]["cutoff"] < 3.5
    assert envs["constant"]["cmgen_auto"]["rejected"] is None and envs["constant"]["cmgen_auto"]["cutoff"] > 12.5
    assert any(f.startswith("cmgen auto window: cut-off") for f in res.findings)
    assert any(f.startswith("ZH3 vs SH9 on ") for f in res.findings)


def test_technique_entries_cover_every_registered_technique(quick_result) -> None:
    res, _ = quick_result
    envs = set(res.data["environments"])
    assert set(res.techniques) == {t.name for t in irradiance}
    for name, entry in res.techniques.items():
        assert entry["family"] == "irradiance"
        assert set(entry["metrics"]) == envs, name
        for metrics in entry["metrics"].values():
            assert set(metrics) == set(METRIC_NAMES)
            for st in metrics.values():  # one measured value per statistic (validate.stats.Measured)
                assert set(st) == {"mean", "max", "rms"} and all(v["unit"] == "%" for v in st.values())
        assert set(entry["mirrored_normals"]) == envs
    exact = next(c for c in res.claims if c.id == f"sh9.technique.{PLUGIN_EXACT}.flux_luminance.max")
    assert "worst over 2 environments" in exact.description  # the declared scope, not every environment
    table = next(s for s in res.sections if s.title.startswith("Technique comparison")).tables[0]
    assert {row[0] for row in table.rows} >= {"sh9", PLUGIN_BOUND, PLUGIN_EXACT}
    assert len(table.headers) == 1 + len(envs)


def test_a_plugin_named_sh9_is_a_duplicate() -> None:
    with pytest.raises(ValidateError, match="already registered"):
        irradiance.register("sh9")(sh_truncated.sh9)


def test_bandlimited_closed_form_is_independent_of_the_model() -> None:
    """A_l from R&H JOSA 2001 eq. 19 written out in sh9_closed_forms equals the published values
    (reference README: A0 = π, A1 = 2π/3, A2 = π/4, A4 = −π/24, A6 = π/64, A8 = −π/128, odd l > 1: 0)."""
    from validate.experiments.sh9.closed_forms import clamped_cosine_coefficient

    published = {0: np.pi, 1: 2 * np.pi / 3, 2: np.pi / 4, 3: 0.0, 4: -np.pi / 24, 5: 0.0, 6: np.pi / 64,
                 8: -np.pi / 128}
    for l, a in published.items():
        assert clamped_cosine_coefficient(l) == pytest.approx(a, abs=1e-15), l


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


@pytest.fixture(scope="module")
def paper_results(load_probe: Callable[[str], Environment]) -> dict[str, dict]:
    """The paper's probes analysed at full settings (10k normals), once per module."""
    return {f: analyse_environment(load_probe(f), sh9_exp.FULL, read_published_sh9(),
                                           read_aliases()) for f in sorted(INDEPENDENT)}


@pytest.mark.probes
@pytest.mark.parametrize("filename", sorted(INDEPENDENT))
def test_paper_probes_reproduce_rh2001(filename: str, paper_results: dict[str, dict]) -> None:
    r = paper_results[filename]
    st = r["errors"]["flux_luminance"]
    assert st["mean"] + st["mean_uncertainty"] < PAPER_MEAN
    assert st["max"] + st["max_uncertainty"] < PAPER_MAX
    mean_ind, max_ind = INDEPENDENT[filename]
    assert abs(st["mean"] - mean_ind) < INDEPENDENT_TOL_MEAN
    assert abs(st["max"] - max_ind) < INDEPENDENT_TOL_MAX
    # the other normalisations measure the same approximation more harshly (3–10 % relative)
    assert 0.03 <= r["errors"]["relative"]["mean"] <= 0.10
    assert r["convergence"] < CONVERGENCE
    pub = r["published"]
    assert pub["max_deviation"] < 0.01
    assert pub["scale"] == pytest.approx({"grace_probe.hdr": 3.19, "rnl_probe.hdr": 9.97}[filename], rel=0.01)


@pytest.mark.probes
def test_paper_and_published_claims_have_failing_power(paper_results: dict[str, dict]) -> None:
    m = Measurements(sh9_exp.FULL, {f.removesuffix(".hdr"): r for f, r in paper_results.items()})
    claims = sh9_claims.paper_claims(m) + sh9_claims.published_claims(m)
    assert len(claims) == 3 * len(paper_results)
    for c in claims:
        assert c.passed, c
        assert c.power is not None and c.power.fails, c


@pytest.mark.probes
def test_copies_of_paper_probes_get_no_published_row(load_probe: Callable[[str], Environment],
                                                     reference_dir: Path) -> None:
    from validate.scenes.probes import published_row

    assert published_row(load_probe("grace_probe.hdr")) == "grace"
    assert published_row(load_probe("grace_probe_latlong.exr")) is None
    assert published_row(load_probe("ict_grace_256x128.hdr")) is None


@pytest.mark.probes
def test_paper_claims_from_any_folder(load_probe: Callable[[str], Environment], paper_results: dict[str, dict],
                                      tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The published table and aliases ship with the package: from a folder without ../shared/reference the
    paper's probe is still recognised and its sh9.paper.* and sh9.published.* claims are made."""
    from validate.experiments.sh9.compute import published_check

    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("VALIDATE_REFERENCE", raising=False)
    pub = published_check(load_probe("grace_probe.hdr"), read_published_sh9(), read_aliases())
    assert pub["published"]["probe"] == "grace"
    r = dict(paper_results["grace_probe.hdr"], **pub)
    m = Measurements(sh9_exp.FULL, {"grace_probe": r})
    ids = {c.id for c in sh9_claims.paper_claims(m) + sh9_claims.published_claims(m)}
    assert ids == {"sh9.paper.grace_probe.mean", "sh9.paper.grace_probe.max", "sh9.published.grace_probe"}


@pytest.mark.probes
def test_near_matches_of_paper_probes_say_why_not_compared(load_probe: Callable[[str], Environment]) -> None:
    r = analyse_environment(load_probe("ict_grace_256x128.hdr"), sh9_exp.QUICK,
                                    read_published_sh9(), read_aliases())
    assert "published" not in r
    assert "not the Debevec angular map grace_probe.hdr" in r["published_note"]
    m = Measurements(sh9_exp.QUICK, {"ict_grace_256x128": r})
    assert any("ict_grace_256x128.hdr" in f for f in sh9_report.findings(m))


def _stats(v: float) -> dict[str, dict[str, float]]:
    return {metric: {"mean": v, "max": v, "rms": v, "mean_uncertainty": 0.0, "max_uncertainty": 0.0}
            for metric in METRIC_NAMES}


@pytest.mark.parametrize("mirrored, expect", [(0.5, "mirrored"), (0.04, "error × 1.5")])
def test_technique_power_mirror_or_error_growth(mirrored: float, expect: str) -> None:
    """The mirror x → −x is the technique claims' perturbation; where it hides the bug (a technique or
    environments symmetric in x) the error × 1.5 is used instead. Both fail a 5 % claim measured at 4 %."""
    from validate.experiments.techniques import technique_claims
    from validate.local_models.registry import Technique

    tech = Technique("fake", "irradiance", sh_truncated.sh9, "fake", {"flux_luminance.max": 0.05})
    env = {"models": {"fake": _stats(0.04)}, "models_mirrored": {"fake": _stats(mirrored)}}
    m = Measurements(sh9_exp.QUICK, {"two_tone": env})
    (c,) = technique_claims("sh9", tech, sh9_claims.technique_measured(m, "fake", ["two_tone"]))
    assert c.id == "sh9.technique.fake.flux_luminance.max" and c.passed
    assert expect in c.power.perturbation and c.power.fails
    assert c.power.measured == pytest.approx(max(mirrored, 0.06))


def test_technique_findings_say_where_a_technique_beats_sh9() -> None:
    envs = {"a": {"errors": _stats(0.02), "models": {"t": _stats(0.01)}},
            "b": {"errors": _stats(0.01), "models": {"t": _stats(0.03)}}}
    (sentence,) = sh9_report.technique_findings(Measurements(sh9_exp.QUICK, envs))
    assert sentence.startswith("technique t: worst flux-normalised error 3 % mean (b) / 3 % max (b)")
    assert "lower mean error than SH9 on 1 of 2 environments (a)" in sentence


def test_zh3_findings_name_grace_and_the_sunniest_probe() -> None:
    """Per selected environment the numbers of SH9, stored / hallucinated ZH3 and L1 SH, and which is closer."""
    def env(kind: str, share: float, sh9: float, stored: float, hall: float, sh1: float) -> dict:
        models = {"zh3_stored": _stats(stored), "zh3_hallucinated": _stats(hall), "sh1": _stats(sh1)}
        return {"kind": kind, "sun_share": share, "errors": _stats(sh9), "models": models}

    m = Measurements(sh9_exp.QUICK, {"grace_probe": env("probe", 0.05, 0.0086, 0.0080, 0.02, 0.05),
                                                 "sunny": env("probe", 0.7, 0.02, 0.025, 0.03, 0.06),
                                                 "near_directional": env("procedural", 1.0, 0.03, 0.03, 0.03, 0.1)})
    found = sh9_report.zh3_findings(m)
    assert len(found) == 3 and found[0].startswith("ZH3 vs SH9 on grace_probe") and " on sunny " in found[1]
    assert "closer to the truth than SH9 (9) by 0.06 %" in found[0]
    assert "farther from the truth than SH9 (9) by 0.5 %" in found[1]
    assert "closer to the truth than L1 SH (4) by 3 %" in found[1]
    assert found[2].startswith("Stored ZH3 has a lower mean error than SH9 on 1 of 3 environments (grace_probe)")


def test_thresholds_on_other_experiments_metrics_are_findings_not_errors() -> None:
    irradiance.add("test_foreign", sh_truncated.sh9, thresholds={"flux_luminance.max": 0.5, "peak_map.max": 0.01})
    try:
        m = Measurements(sh9_exp.QUICK, {"a": {"errors": _stats(0.01), "models": {"test_foreign": _stats(
            0.01)}, "models_mirrored": {"test_foreign": _stats(0.1)}}})
        ids = [c.id for c in sh9_claims.all_technique_claims(m) if ".test_foreign." in c.id]
        assert ids == ["sh9.technique.test_foreign.flux_luminance.max"]
        assert any("test_foreign: thresholds on peak_map.max" in f for f in sh9_claims.foreign_thresholds())
    finally:
        irradiance.unregister("test_foreign")
