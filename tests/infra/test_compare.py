"""``python -m validate compare OLD NEW [--strict]`` and ``validate.testing.compare``.

Fast tests on two small synthetic results.json files, on old-shape files (before the measured-value
schema), on the committed ``docs/results.json`` and on sh9's own computation of a plug-in and its 2 %
worse twin (tiny settings, two environments); slow tests on two real runs of ``run hemisphere --quick``
and ``run sh9 --quick``, the second with a plug-in irradiance technique made 2 % brighter.
"""

from __future__ import annotations

import copy
import json
import math
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from validate import cli, testing
from validate.errors import ValidateError
from validate.experiments import Context
from validate.experiments.sh9 import report as sh9_report
from validate.experiments.sh9.compute import compute as sh9_compute
from validate.experiments.sh9.settings import Settings as Sh9Settings
from validate.experiments.techniques import error_stats_measured
from validate.local_models import irradiance
from validate.metrics.pixel_z import PixelJudgement
from validate.report.compare import OLD_NOTE, REGRESSION_STATUSES, ROUNDOFF, compare, is_old
from validate.scenes import procedural
from validate.stats import Measured, measured_json

REPO = Path(__file__).resolve().parents[2]
SCHEMA = {"kind", "key", "old", "new", "old_uncertainty", "new_uncertainty", "change", "exceeds_uncertainty",
          "status", "unit"}
STATUSES = ("regressed", "newly_failing", "improved", "changed", "new", "removed", "unchanged")


def table_keys(stdout: str) -> set[str]:
    """The keys of the changed rows ``compare`` printed (lines that start with a status)."""
    return {ln.split()[2] for ln in stdout.strip().splitlines() if ln.split() and ln.split()[0] in STATUSES}


def _claim(cid: str, measured: float, unc: float, threshold: float = 0.05) -> dict[str, Any]:
    return {"id": cid, "measured": measured, "uncertainty": unc, "threshold": threshold, "comparison": "<",
            "passed": measured + unc < threshold}


def _metric(value: float | None, unc: float | None = 0.001) -> dict[str, Any]:
    return {"value": value, "uncertainty": unc}


def synthetic() -> dict[str, Any]:
    return {"meta": {}, "experiments": {"exp": {
        "claims": [_claim("exp.stays", 0.01, 0.001), _claim("exp.breaks", 0.04, 0.001),
                   _claim("exp.heals", 0.06, 0.001), _claim("exp.gone", 0.01, 0.001), _claim("plain", 0.02, 0.0)],
        "techniques": {
            "a": {"metrics": {"flux.max": _metric(0.10), "flux.mean": _metric(0.05), "relative.max": _metric(1.0),
                              "meter": _metric(2.0, None)}},
            "b": {"metrics": {"flux.max": _metric(0.20), "point": {"bias": _metric(-0.05)},
                              "psnr": _metric(30.0, 0.1)}},
        }}}}


def modified() -> dict[str, Any]:
    d = copy.deepcopy(synthetic())
    e = d["experiments"]["exp"]
    e["claims"] = [_claim("exp.stays", 0.012, 0.001), _claim("exp.breaks", 0.055, 0.001),
                   _claim("exp.heals", 0.03, 0.001), _claim("plain", 0.02, 0.0), _claim("exp.fresh", 0.0, 0.0)]
    m = e["techniques"]["a"]["metrics"]
    m["flux.max"]["value"] = 0.102   # +0.002 > √2 · 0.001: worse beyond the uncertainty
    m["flux.mean"]["value"] = 0.0505  # +0.0005 < 0.0014: within it
    m["relative.max"]["value"] = 0.9  # better beyond it
    m["meter"]["value"] = 2.0 + 1e-6  # no uncertainty: any change beyond round-off counts
    b = e["techniques"]["b"]["metrics"]
    b["point"]["bias"]["value"] = 0.06  # signed: |0.06| > |−0.05|, worse by magnitude
    b["psnr"]["value"] = 28.0  # a score: lower is worse
    del b["flux.max"]
    e["techniques"]["c"] = {"metrics": {"flux.max": _metric(0.3)}}
    return d


def test_synthetic_statuses_and_schema() -> None:
    c = compare(synthetic(), modified())
    status = {r.key: r.status for r in c.rows}
    assert status == {
        "exp.stays": "changed", "exp.breaks": "newly_failing", "exp.heals": "improved", "exp.gone": "removed",
        "exp/plain": "unchanged", "exp.fresh": "new",
        "exp/a/flux.max": "regressed", "exp/a/flux.mean": "changed", "exp/a/relative.max": "improved",
        "exp/a/meter": "regressed", "exp/b/flux.max": "removed", "exp/b/point/bias": "regressed",
        "exp/b/psnr": "regressed", "exp/c/flux.max": "new"}
    rows = {r.key: r for r in c.rows}
    assert rows["exp/a/flux.max"].exceeds_uncertainty and not rows["exp/a/flux.mean"].exceeds_uncertainty
    assert rows["exp/a/flux.max"].change == pytest.approx(0.002, rel=1e-9)
    assert rows["exp/a/meter"].old_uncertainty is None and rows["exp/a/meter"].exceeds_uncertainty
    doc = c.to_json()
    assert doc["regressions"] == 5 == len(c.regressions)  # newly failing claim + 4 worse metrics
    assert all(set(r) == SCHEMA for r in doc["rows"])
    json.dumps(doc)  # JSON-able as it stands


def test_roundoff_is_unchanged() -> None:
    new = copy.deepcopy(synthetic())
    new["experiments"]["exp"]["techniques"]["a"]["metrics"]["meter"]["value"] = 2.0 * (1 + ROUNDOFF / 10)
    c = compare(synthetic(), new)
    assert not c.changed and not c.regressions and c.table() == ""


def _scaled(results: dict[str, Any], technique: str, factor: float) -> dict[str, Any]:
    d = copy.deepcopy(results)
    for e in d["experiments"].values():
        for leaf in e["techniques"].get(technique, {}).get("metrics", {}).values():
            leaf["value"] *= factor
    return d


def test_two_percent_worse_technique_is_named_and_strict_fails(tmp_path: Path,
                                                              capsys: pytest.CaptureFixture[str]) -> None:
    """The fast twin of the slow real-run test: one technique's metrics 2 % larger, the rest equal."""
    old = synthetic()
    old_path, new_path = tmp_path / "old.json", tmp_path / "new.json"
    old_path.write_text(json.dumps(old))
    new_path.write_text(json.dumps(_scaled(old, "a", 1.02)))
    assert cli.main(["compare", str(old_path), str(new_path)]) == 0
    out = capsys.readouterr().out
    lines = out.strip().splitlines()
    assert cli.main(["compare", str(old_path), str(new_path), "--strict"]) == 1
    assert capsys.readouterr().out.strip().splitlines() == lines
    named = table_keys(out)
    assert named == {f"exp/a/{m}" for m in old["experiments"]["exp"]["techniques"]["a"]["metrics"]}
    assert lines[-1].startswith("3 regression(s)")  # flux.max, relative.max, meter beyond σ; flux.mean within
    assert testing.compare(old_path, new_path).to_json()["regressions"] == 3
    assert cli.main(["compare", str(old_path), str(old_path), "--strict"]) == 0


@pytest.mark.parametrize("case", ["missing", "not_json", "not_results"])
def test_bad_input_is_one_line(tmp_path: Path, case: str, capsys: pytest.CaptureFixture[str]) -> None:
    good = tmp_path / "good.json"
    good.write_text(json.dumps(synthetic()))
    bad = tmp_path / "bad.json"
    if case == "not_json":
        bad.write_text("{not json")
    elif case == "not_results":
        bad.write_text("[1, 2]")
    assert cli.main(["compare", str(good), str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"validate: error: {bad}:"), err


PLUGIN = '''
from validate.local_models import irradiance

FACTOR = {factor!r}


@irradiance.register("plugin_scaled_sh9", "SH9 irradiance times a factor (a technique made {factor} x)")
def plugin_scaled_sh9(radiance, normals):
    return irradiance["sh9"].fn(radiance, normals) * FACTOR
'''


def _run(out: Path, plugin: Path, *extra: str, experiment: str = "hemisphere") -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "VALIDATE_PROBES"}
    return subprocess.run([sys.executable, "-m", "validate", "run", experiment, "--quick", "--no-progress",
                           "--plugin", str(plugin), "--out", str(out), *extra],
                          capture_output=True, text=True, cwd=REPO, env=env, timeout=900)


@pytest.mark.slow
def test_real_runs_plugin_two_percent_worse(tmp_path: Path) -> None:
    """Two ``run hemisphere --quick`` (≈ 20 s each): the changed rows are exactly the scaled technique's
    metrics, ``--strict`` exits 1, and ``--baseline`` stores the same rows as ``changes``."""
    plugin = tmp_path / "scaled.py"
    plugin.write_text(PLUGIN.format(factor=1.0))
    r = _run(tmp_path / "old", plugin)
    assert r.returncode == 0, r.stderr
    plugin.write_text(PLUGIN.format(factor=1.02))
    r = _run(tmp_path / "new", plugin, "--baseline", str(tmp_path / "old" / "results.json"))
    assert r.returncode == 0, r.stderr
    c = compare(tmp_path / "old", tmp_path / "new")
    old = json.loads((tmp_path / "old" / "results.json").read_text())
    scaled = {f"hemisphere/plugin_scaled_sh9/{m}"
              for m in old["experiments"]["hemisphere"]["techniques"]["plugin_scaled_sh9"]["metrics"]}
    assert {r.key for r in c.changed if r.kind == "metric"} == scaled
    assert c.regressions and all("plugin_scaled_sh9" in r.key for r in c.regressions)
    strict = subprocess.run([sys.executable, "-m", "validate", "compare", str(tmp_path / "old"),
                             str(tmp_path / "new"), "--strict"], capture_output=True, text=True, cwd=REPO)
    assert strict.returncode == 1, strict.stdout + strict.stderr
    assert table_keys(strict.stdout) == {r.key for r in c.changed}
    changes = json.loads((tmp_path / "new" / "results.json").read_text())["changes"]
    assert changes["regressions"] == len(c.regressions)
    assert {r["key"] for r in changes["rows"] if r["status"] != "unchanged"} == {r.key for r in c.changed}


# ---------------------------------------------------------------------------------------------
# The measured-value schema: every technique metric and judgement, old files, sh9's plug-ins
# ---------------------------------------------------------------------------------------------

def test_measured_json_round_trip() -> None:
    m = Measured(0.0123, 0.0004, 0.0185, "error × 1.5", unit="%", stat="max", better="zero", params={"n": 3})
    assert Measured.from_json(json.loads(json.dumps(m.to_json()))) == m
    assert Measured(2.0).to_json() == {"value": 2.0, "uncertainty": 0.0, "unit": ""}  # none counts as 0
    assert Measured.from_json({"value": 1.0, "unit": "%", "uncertainty": None}).uncertainty == 0.0
    assert Measured(float("nan"), float("nan")).to_json() == {"value": None, "uncertainty": None, "unit": ""}
    assert math.isnan(Measured.from_json({"value": None, "unit": ""}).value)
    with pytest.raises(ValidateError, match="better='up'"):
        Measured(1.0, better="up")


def _judgement(fraction: float) -> PixelJudgement:
    z = np.zeros((2, 2))
    return PixelJudgement(4096, fraction, 3.9, 2.5, 0.01, 0.002, 0.05, 0.004, -0.003, 0.01, "probe budget", z, z)


def _old_and_new() -> tuple[dict[str, Any], dict[str, Any]]:
    """The same numbers in the shapes before the schema (sh9's ErrorStats dicts, worstcase's bare numbers,
    hand-written {value, uncertainty}, a flat renders judgement) and in the schema."""
    stats = {"mean": 0.01, "max": 0.03, "rms": 0.015, "mean_uncertainty": 0.001, "max_uncertainty": 0.002}
    j = _judgement(0.999)
    flat = {k: v for k, v in vars(j).items() if k not in ("z_image", "rel_image")}
    old = {"meta": {}, "experiments": {
        "sh9": {"claims": [], "techniques": {"sh9": {"metrics": {"constant": {"flux_rgb": stats}}}}},
        "worstcase": {"claims": [], "techniques": {"sh9": {"metrics": {"linearity_defect": 1e-7}}}},
        "hemisphere": {"claims": [], "techniques": {"sh9": {"metrics": {"flux_rgb.max": {"value": 0.03,
                                                                                          "uncertainty": 0.002}}}}},
        "renders": {"claims": [], "techniques": {},
                    "scenes": {"furnace": {"engines": {"three": {"judgements": {"mitsuba": flat}}}}}}}}
    new = {"meta": {}, "experiments": {
        "sh9": {"claims": [], "techniques": {"sh9": {"metrics": measured_json(
            {"constant": {"flux_rgb": error_stats_measured(stats)}})}}},
        "worstcase": {"claims": [], "techniques": {"sh9": {"metrics": {
            "linearity_defect": Measured(1e-7, unit="%").to_json()}}}},
        "hemisphere": {"claims": [], "techniques": {"sh9": {"metrics": {
            "flux_rgb.max": Measured(0.03, 0.002, unit="%", stat="max").to_json()}}}},
        "renders": {"claims": [], "techniques": {},
                    "scenes": {"furnace": {"engines": {"three": {"judgements": {"mitsuba": j.to_json()}}}}}}}}
    return old, new


def test_old_shapes_load_unchanged_and_the_old_file_is_named(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    old, new = _old_and_new()
    assert is_old(old) and not is_old(new)
    old_path, new_path = tmp_path / "OLD.json", tmp_path / "NEW.json"
    old_path.write_text(json.dumps(old))
    new_path.write_text(json.dumps(new))
    c = compare(old_path, new_path)
    assert c.notes == [f"{old_path}: {OLD_NOTE}"]
    assert {r.key for r in c.rows} == {
        "sh9/sh9/constant/flux_rgb/mean", "sh9/sh9/constant/flux_rgb/max", "sh9/sh9/constant/flux_rgb/rms",
        "worstcase/sh9/linearity_defect", "hemisphere/sh9/flux_rgb.max",
        *(f"renders/scenes/furnace/engines/three/judgements/mitsuba/{k}"
          for k in ("fraction_accepted", "max_abs_z", "mean_rel", "max_rel", "mean_signed_rel"))}
    assert all(r.status == "unchanged" for r in c.rows), c.table()
    assert c.counts()["renders"]["judgement"] == 5 and c.counts()["sh9"]["metric"] == 3
    assert cli.main(["compare", str(old_path), str(new_path), "--strict"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == f"{old_path}: {OLD_NOTE}" and out[-1].startswith("0 regression(s)")
    assert compare(new_path, new_path).notes == []


def test_a_judgement_accepting_fewer_pixels_is_a_regression() -> None:
    """fraction_accepted: larger is better (the value says so); the mean signed error counts by magnitude."""
    _, new = _old_and_new()
    worse = copy.deepcopy(new)
    leaf = worse["experiments"]["renders"]["scenes"]["furnace"]["engines"]["three"]["judgements"]["mitsuba"]
    leaf.update(_judgement(0.95).to_json())
    leaf["mean_signed_rel"]["value"] = 0.003  # −0.003 → +0.003: the same magnitude, not worse
    status = {r.key.rsplit("/", 1)[-1]: r.status for r in compare(new, worse).rows if r.kind == "judgement"}
    assert status["fraction_accepted"] == "regressed" and status["mean_signed_rel"] == "changed"
    assert status["mean_rel"] == "unchanged"


def test_docs_results_compare_sees_every_experiments_technique_metrics() -> None:
    """The committed subset (``docs/results.json``) keeps every technique metric in the schema: ``compare``
    finds more than none for every experiment that registers techniques (sh9, engines, worstcase among them)."""
    docs = json.loads((REPO / "docs" / "results.json").read_text(encoding="utf-8"))
    assert not is_old(docs)
    counts = compare(docs, docs).counts()
    with_techniques = [e for e, v in docs["experiments"].items() if v.get("techniques")]
    assert {"sh9", "engines", "worstcase"} <= set(with_techniques)
    assert {e: counts[e]["metric"] for e in with_techniques if counts.get(e, {}).get("metric", 0) == 0} == {}


PLUGIN_NAME = "plugin_scaled_sh9"
SH9_TINY = Sh9Settings(400, 16, (4, 8), 8, (), max_order=4)  # no path tracing; seconds, not a minute
SH9_ENVS = ("two_tone", "sunsky_30deg")


def test_sh9_plugin_two_percent_worse_is_named_and_strict_fails(tmp_path: Path,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    """sh9's own computation (tiny settings, two built-in environments) of a plug-in, SH9 × 1.00, and of its
    twin made 2 % worse, SH9 × 1.02: run A reports the first under the plug-in's name, run B the second, every
    other technique as measured. ``compare --strict A B`` exits 1 and names exactly the plug-in's metrics."""
    irradiance.add("scaled_100", lambda r, n: irradiance["sh9"].fn(r, n) * 1.00, "SH9 × 1.00")
    irradiance.add("scaled_102", lambda r, n: irradiance["sh9"].fn(r, n) * 1.02, "SH9 × 1.02")
    try:
        ctx = Context(out_dir=tmp_path, quick=True, show_progress=False, log=lambda _: None)
        ctx._env_cache["envs"] = ([e for e in procedural.builtin_environments(True) if e.name in SH9_ENVS], [])
        entries = sh9_report.techniques(sh9_compute(ctx, SH9_TINY))
    finally:
        irradiance.unregister("scaled_100")
        irradiance.unregister("scaled_102")
    rest = {k: v for k, v in entries.items() if not k.startswith("scaled_")}
    paths = []
    for run, twin in (("A", "scaled_100"), ("B", "scaled_102")):
        doc = {"meta": {}, "experiments": {"sh9": {"claims": [], "techniques": {**rest, PLUGIN_NAME: entries[twin]}}}}
        paths.append(tmp_path / f"{run}.json")
        paths[-1].write_text(json.dumps(doc))
    c = compare(*paths)
    metrics = {r.key for r in c.rows if r.kind == "metric" and r.key.startswith(f"sh9/{PLUGIN_NAME}/")}
    assert len(metrics) == len(SH9_ENVS) * 4 * 3  # environments × metrics × (mean, max, rms)
    assert {r.key for r in c.changed} == metrics  # every other technique: unchanged
    assert c.regressions and {r.key for r in c.regressions} <= metrics
    assert all(r.status in REGRESSION_STATUSES or not r.exceeds_uncertainty for r in c.changed)
    assert cli.main(["compare", str(paths[0]), str(paths[1]), "--strict"]) == 1
    out = capsys.readouterr().out
    assert table_keys(out) == metrics and f"{len(c.regressions)} regression(s)" in out


@pytest.mark.slow
def test_real_sh9_runs_plugin_two_percent_worse(tmp_path: Path) -> None:
    """Two ``run sh9 --quick`` on the built-in environments: a plug-in SH9 × 1.00, then × 1.02; ``compare
    --strict`` exits 1 naming only that plug-in's metrics (and claims on it, none here)."""
    plugin = tmp_path / "scaled.py"
    plugin.write_text(PLUGIN.format(factor=1.0))
    r = _run(tmp_path / "old", plugin, experiment="sh9")
    assert r.returncode == 0, r.stderr
    plugin.write_text(PLUGIN.format(factor=1.02))
    r = _run(tmp_path / "new", plugin, experiment="sh9")
    assert r.returncode == 0, r.stderr
    c = compare(tmp_path / "old", tmp_path / "new")
    assert c.counts()["sh9"]["metric"] > 0
    assert c.regressions and all(f"sh9/{PLUGIN_NAME}/" in r.key for r in c.regressions)
    assert {r.key for r in c.changed if r.kind == "metric"} == {
        r.key for r in c.rows if r.kind == "metric" and r.key.startswith(f"sh9/{PLUGIN_NAME}/")}
    strict = subprocess.run([sys.executable, "-m", "validate", "compare", str(tmp_path / "old"),
                             str(tmp_path / "new"), "--strict"], capture_output=True, text=True, cwd=REPO)
    assert strict.returncode == 1, strict.stdout + strict.stderr
    assert table_keys(strict.stdout) == {r.key for r in c.changed}
