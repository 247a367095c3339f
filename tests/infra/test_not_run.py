"""A run says what it could not run (``NotRun``): the hook of an experiment and of its parts reaches
``results.json``, the command line prints one line per piece, the pages show it, and ``--strict`` exits 1 —
nothing judged is not a pass. The renders experiment names its engines when their runtime is missing."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import pytest

from validate import cli
from validate.experiments import base
from validate.experiments.base import EXPERIMENTS, NotRun, Section

PLUGIN = Path(__file__).with_name("plugin_tiny.py")


def _stage_module(**extra: object) -> SimpleNamespace:
    return SimpleNamespace(NAME="fake", TITLE="Fake", DESCRIPTION="d", ORDER=1, QUICK={"q": 1}, FULL={"q": 2},
                           compute=lambda ctx, s: {"part": 2}, claims=lambda m: [], findings=lambda m: [],
                           sections=lambda m, ctx: [Section("s")], **extra)


def test_the_hooks_of_an_experiment_and_its_parts_reach_the_result() -> None:
    part = SimpleNamespace(KEY="part", compute=None, claims=lambda pm: [], findings=lambda pm: [],
                           sections=lambda pm, ctx: [], not_run=lambda pm: [NotRun(f"part {pm}", "why")])
    mod = _stage_module(not_run=lambda m: [NotRun("engine x", "no runtime", "install x")], PARTS=(part,))
    res = base.run(mod, SimpleNamespace(quick=True))
    assert [n.what for n in res.not_run] == ["engine x", "part 2"]
    assert res.to_json()["not_run"][0] == {"what": "engine x", "why": "no runtime", "fix": "install x"}
    assert base.run(_stage_module(), SimpleNamespace(quick=True)).to_json()["not_run"] == []


@pytest.fixture
def tiny(monkeypatch: pytest.MonkeyPatch):
    from validate.scenes import procedural

    monkeypatch.setattr(procedural, "builtin_environments", lambda quick=False: [procedural.constant(16)])
    monkeypatch.delenv("VALIDATE_PROBES", raising=False)
    for var in ("TINY_PHASE", "TINY_VALUE"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.setenv("TINY_FIGURES", "1")
    yield monkeypatch
    EXPERIMENTS.pop("tiny_io", None)


def _run(out: Path, *extra: str) -> int:
    return cli.main(["run", "tiny_io", "--quick", "--no-progress", "--plugin", str(PLUGIN), "--out", str(out),
                     *extra])


def test_strict_fails_when_something_was_not_run(tiny: pytest.MonkeyPatch, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    assert _run(out, "--strict") == 0  # everything judged: the claim passes
    assert "not run" not in capsys.readouterr().out
    tiny.setenv("TINY_NOT_RUN", "1")
    assert _run(out) == 0  # without --strict: said, not fatal
    text = capsys.readouterr().out
    line = "the tiny engine not run: TINY_NOT_RUN is set — `unset TINY_NOT_RUN`"
    assert f"tiny_io: {line}" in text and "1 piece(s) not run (use --strict" in text
    assert _run(out, "--strict") == 1
    results = json.loads((out / "results.json").read_text())
    assert results["experiments"]["tiny_io"]["not_run"] == [
        {"what": "the tiny engine", "why": "TINY_NOT_RUN is set", "fix": "unset TINY_NOT_RUN"}]
    from validate.report.html import page_name

    page = (out / page_name("tiny_io")).read_text()
    assert "Not run here" in page and "the tiny engine not run" in page
    assert "Not run here" in (out / "index.html").read_text()


def test_renders_names_its_engines_when_the_runtime_is_missing() -> None:
    from validate.experiments.renders import report
    from validate.experiments.renders.compute import Measurements
    from validate.experiments.renders.settings import FULL, QUICK
    from validate.local_models.render import Missing

    gone = Missing("npm engines", "three not installed in /x", "python -m validate setup --engines")
    [quick] = report.not_run(Measurements(QUICK, [], missing=gone))
    assert quick.what == "three.js, Filament" and "npm engines" in quick.why
    assert quick.fix == "python -m validate setup --engines"
    assert report.not_run(Measurements(FULL, [], missing=gone))[0].what == "three.js, Babylon.js, Filament"
    assert report.not_run(Measurements(QUICK, [], missing=None)) == []
    assert report.summary(Measurements(QUICK, [], missing=gone)).startswith("No engine judged")


def test_missing_runtime_names_the_npm_engines(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from validate.local_models import render

    monkeypatch.setenv("VALIDATE_HOME", str(tmp_path))
    miss = render.missing_runtime()
    assert miss is not None and miss.piece == "npm engines" and "three" in miss.why
    assert miss.fix == "python -m validate setup --engines"


def test_compare_counts_a_piece_newly_not_run_as_a_regression() -> None:
    from validate.report.compare import compare

    def run(*not_run: str) -> dict:
        return {"meta": {}, "experiments": {"renders": {"claims": [], "techniques": {}, "not_run": [
            {"what": w, "why": "npm engines missing", "fix": "python -m validate setup --engines"} for w in not_run]}}}

    c = compare(run(), run("three.js, Filament"))
    assert [(r.kind, r.key, r.status) for r in c.rows] == [("not_run", "renders/not_run/three.js, Filament",
                                                            "regressed")]
    assert c.regressions and "1 regression(s)" in c.summary() and "three.js, Filament" in c.table()
    assert not compare(run("x"), run()).regressions and not compare(run("x"), run("x")).regressions
