"""Techniques as plug-ins: the registry, the output contract, and a plug-in with one technique of every
family run through every experiment (``all --quick``), which is also the end-to-end test of each experiment."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.experiments import discover
from validate.local_models import FAMILIES, irradiance, shadow
from validate.local_models.registry import define_family

ROOT = Path(__file__).resolve().parents[2]
PLUGINS = Path(__file__).resolve().parents[1] / "plugins"
PROBES = Path(os.environ.get("VALIDATE_PROBES") or ROOT.parent / "shared" / "probes").resolve()


# -- the registry ---------------------------------------------------------------------------------------

def test_builtins_register_like_plugins_and_duplicates_are_errors():
    assert "sh9" in irradiance and irradiance["sh9"].builtin
    with pytest.raises(ValidateError, match=r"technique 'sh9' \(irradiance\): already registered"):
        irradiance.register("sh9")(lambda radiance, normals: normals)
    with pytest.raises(ValidateError, match="already defined"):
        define_family("irradiance", "again", lambda *a: (0,))
    with pytest.raises(ValidateError, match="unknown irradiance technique 'nope'"):
        irradiance["nope"]


@pytest.mark.parametrize("out, problem", [
    (lambda n: np.full((len(n), 3), np.nan), r"returned 30 non-finite value\(s\) \(NaN\)"),
    (lambda n: np.full((len(n), 3), np.inf), r"returned 30 non-finite value\(s\) \(Inf\)"),
    (lambda n: np.ones(len(n)), r"returned shape \(10,\), expected \(10, 3\)"),
    (lambda n: "text", "returned str, not an array of numbers"),
    (lambda n: 1 / 0, "raised ZeroDivisionError"),
])
def test_output_contract_is_one_line_naming_the_technique(out, problem):
    irradiance.register("contract_probe")(lambda radiance, normals: out(normals))
    try:
        with pytest.raises(ValidateError, match=r"^technique 'contract_probe' \(irradiance\): " + problem) as err:
            irradiance.call("contract_probe", np.ones((8, 16, 3)), np.tile([0.0, 1.0, 0.0], (10, 1)))
        assert "\n" not in str(err.value)
    finally:
        irradiance.unregister("contract_probe")


def test_physical_bounds_where_the_family_declares_them():
    shadow.register("contract_probe")(lambda sm, light, points, normals: np.full(len(points), 1.5))
    try:
        with pytest.raises(ValidateError, match=r"'contract_probe' \(shadow\): returned 4 value\(s\) above 1"):
            shadow.call("contract_probe", None, None, np.zeros((4, 3)), np.zeros((4, 3)))
    finally:
        shadow.unregister("contract_probe")
    # irradiance approximations may go negative (SH ringing): measured, not refused
    irradiance.register("contract_probe")(lambda radiance, normals: -np.ones((len(normals), 3)))
    try:
        assert irradiance.call("contract_probe", np.ones((4, 8, 3)), np.zeros((2, 3))).min() == -1
    finally:
        irradiance.unregister("contract_probe")


# -- bad plug-ins through the CLI: one line, exit 2, nothing written -----------------------------------------

def _cli(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    env = dict(os.environ, VALIDATE_PROBES="")
    return subprocess.run([sys.executable, "-m", "validate", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=900)


@pytest.mark.parametrize("plugin, message", [
    ("nan_irradiance.py", r"technique 'broken_nan' \(irradiance\): returned \d+ non-finite value\(s\) \(NaN\)"),
    ("wrong_shape_irradiance.py", r"technique 'broken_shape' \(irradiance\): returned shape \(\d+,\), expected"),
    ("duplicate_sh9.py", r"technique 'sh9' \(irradiance\): already registered"),
])
def test_bad_plugin_is_one_line_exit_2_nothing_written(tmp_path, plugin, message):
    out = tmp_path / "reports"
    proc = _cli("run", "hemisphere", "--quick", "--no-progress", "--out", str(out), "--plugin", str(PLUGINS / plugin))
    assert proc.returncode == 2, proc.stderr[-2000:]
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("validate: error: "), proc.stderr[-2000:]
    assert re.search(message, lines[0]), lines[0]
    assert not (out / "results.json").exists() and not (out / "index.html").exists()


# -- a plug-in of every family through the experiments ------------------------------------------------------
# The default run sends the plug-in through one experiment per family — the cheapest reader of each (about 75 s
# on the 2-core machine, against ~230 s for `all --quick`); `make test-slow` runs it through every experiment.
# Every experiment's own claims and power checks are exercised by its tests in tests/experiments/, and every
# claim of the recorded quick run (docs/results.json, regenerated at each release) by the static check below.

CHEAP_READERS = ("hemisphere", "ibl", "arealights", "shadows", "lights", "brdfs", "uberlight", "listings")
EXPERIMENTS = list(discover())


def _plugin_run(factory: pytest.TempPathFactory, names: tuple[str, ...] | None) -> dict:
    out = factory.mktemp("plugin_run") / "reports"
    command = ["all"] if names is None else ["run", *names]
    args = [*command, "--quick", "--no-progress", "--out", str(out), "--plugin", str(PLUGINS / "every_family.py")]
    if PROBES.is_dir():
        args += ["--probes", str(PROBES)]
    proc = _cli(*args, cwd=out.parent)  # from another folder: published facts ship with the package
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return {"results": json.loads((out / "results.json").read_text()), "out": out, "stdout": proc.stdout}


@pytest.fixture(scope="module")
def plugin_run(tmp_path_factory: pytest.TempPathFactory) -> dict:
    return _plugin_run(tmp_path_factory, CHEAP_READERS)


@pytest.fixture(scope="module")
def plugin_run_all(tmp_path_factory: pytest.TempPathFactory) -> dict:
    return _plugin_run(tmp_path_factory, None)


def _claims_have_power_and_sources(exp: dict, name: str) -> None:
    assert exp["claims"], f"{name} makes no claim"
    for c in exp["claims"]:
        assert c["power"] is not None, f"{c['id']}: no power check"
        assert c["power"]["fails"], f"{c['id']}: the power check ({c['power']['perturbation']}) does not fail"
        assert c["source"] and "issue" not in c["source"].lower(), f"{c['id']}: source {c['source']!r}"


@pytest.mark.parametrize("name", CHEAP_READERS)
def test_cheap_readers_run_quick_with_power_on_every_claim(plugin_run, name):
    _claims_have_power_and_sources(plugin_run["results"]["experiments"][name], name)
    assert (plugin_run["out"] / f"exp-{name}.html").is_file()


@pytest.mark.slow
@pytest.mark.parametrize("name", EXPERIMENTS)
def test_every_experiment_runs_quick_with_power_on_every_claim(plugin_run_all, name):
    _claims_have_power_and_sources(plugin_run_all["results"]["experiments"][name], name)
    assert (plugin_run_all["out"] / f"exp-{name}.html").is_file()


def test_recorded_quick_run_has_power_and_sources_on_every_claim():
    """docs/results.json is the whole `all --quick` run the docs quote: every claim in it has a failing power check
    and a source that is not an issue number."""
    recorded = json.loads((ROOT / "docs" / "results.json").read_text())["experiments"]
    assert set(recorded) == set(EXPERIMENTS), "docs/results.json lacks experiments: regenerate it"
    for name, exp in recorded.items():
        _claims_have_power_and_sources(exp, name)


def _plugin_reaches_every_reader_of_its_family(run: dict) -> dict:
    # the names only: importing the plug-in file would register its techniques in this test process too, where every
    # later in-process run (another test file on this pytest worker) would then meet them
    import ast

    tree = ast.parse((PLUGINS / "every_family.py").read_text(encoding="utf-8"))
    PLUGIN_TECHNIQUES = next(ast.literal_eval(node.value) for node in tree.body if isinstance(node, ast.Assign)  # noqa: N806
                             and any(getattr(t, "id", None) == "PLUGIN_TECHNIQUES" for t in node.targets))
    exps = run["results"]["experiments"]
    for family, technique in PLUGIN_TECHNIQUES.items():
        builtins = {t.name for t in FAMILIES[family] if t.builtin}
        readers = [n for n, e in exps.items() if builtins & set(e.get("techniques") or {})]
        assert readers, f"no experiment run reads the {family} family"
        for n in readers:
            entry = exps[n]["techniques"].get(technique)
            assert entry is not None, f"{n}: plug-in {technique} ({family}) has no results.json entry"
            assert entry["family"] == family and not entry["builtin"] and entry["metrics"]
    return exps


def test_plugin_techniques_reach_every_experiment_of_their_family(plugin_run):
    _plugin_reaches_every_reader_of_its_family(plugin_run)


@pytest.mark.slow
def test_plugin_techniques_reach_every_experiment_and_sh9_draws_them(plugin_run_all):
    exps = _plugin_reaches_every_reader_of_its_family(plugin_run_all)
    # images: sh9 draws every irradiance technique (plug-ins included) on every environment's sphere
    assert list((plugin_run_all["out"] / "figures" / "sh9").glob("*_technique_errors.png"))
    assert "plugin_sh2_numpy" in (plugin_run_all["out"] / "exp-sh9.html").read_text(encoding="utf-8")
    claim_ids = {c["id"] for e in exps.values() for c in e["claims"]}
    assert "sh9.technique.plugin_sh2_numpy.flux_luminance.max" in claim_ids
