"""``python -m validate compare OLD NEW [--strict]`` and ``validate.testing.compare``.

Fast tests on two small synthetic results.json files; one slow test on two real runs of
``run hemisphere --quick``, the second with a plug-in irradiance technique made 2 % brighter.
"""

from __future__ import annotations

import copy
import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from validate import cli, testing
from validate.report.compare import ROUNDOFF, compare

REPO = Path(__file__).resolve().parents[2]
SCHEMA = {"kind", "key", "old", "new", "old_uncertainty", "new_uncertainty", "change", "exceeds_uncertainty",
          "status"}


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
    lines = capsys.readouterr().out.strip().splitlines()
    assert cli.main(["compare", str(old_path), str(new_path), "--strict"]) == 1
    assert capsys.readouterr().out.strip().splitlines() == lines
    named = {ln.split()[2] for ln in lines[1:-1]}
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


def _run(out: Path, plugin: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "VALIDATE_PROBES"}
    return subprocess.run([sys.executable, "-m", "validate", "run", "hemisphere", "--quick", "--no-progress",
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
    assert {ln.split()[2] for ln in strict.stdout.strip().splitlines()[1:-1]} == {r.key for r in c.changed}
    changes = json.loads((tmp_path / "new" / "results.json").read_text())["changes"]
    assert changes["regressions"] == len(c.regressions)
    assert {r["key"] for r in changes["rows"] if r["status"] != "unchanged"} == {r.key for r in c.changed}
