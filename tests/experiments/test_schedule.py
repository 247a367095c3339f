"""The run order (validate.experiments.schedule): ``renders`` beside the others on a Dask run, in order otherwise;
results in the order asked; an error beside is the run's error."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest

from validate.errors import ValidateError
from validate.experiments import Context, Experiment, ExperimentResult
from validate.experiments.schedule import BESIDE, beside, run_experiments
from validate.local_models.registry import FAMILIES, Technique


def _exp(name: str, log: list[tuple[str, str]], fail: bool = False, wait: threading.Event | None = None) -> Experiment:
    def run(ctx: Context) -> ExperimentResult:
        log.append((name, threading.current_thread().name))
        if wait is not None:
            assert wait.wait(10), "the main lane never ran while this experiment waited"
        if fail:
            raise ValidateError(f"{name}: broken")
        return ExperimentResult(name, name, "", [], [], [])
    return Experiment(name, name, "", run)


def test_beside_only_on_a_distributed_run_with_other_experiments(tmp_path: Path) -> None:
    serial, dask = Context(out_dir=tmp_path), Context(out_dir=tmp_path, workers=2)
    assert BESIDE == ("renders",)
    assert beside(serial, ["sh9", "renders"]) == []
    assert beside(dask, ["renders"]) == []
    assert beside(dask, ["sh9", "renders", "ibl"]) == ["renders"]
    assert beside(dask, ["sh9", "ibl"]) == []


def test_a_webgl2_technique_keeps_everything_in_order(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A GLSL plug-in on the webgl2 runtime shares the browser, whose playwright API is bound to one thread."""
    from validate.local_models import registry

    fam = next(iter(FAMILIES.values()))
    plugin = Technique("my_shader", fam.name, lambda *a: None, "", meta={"glsl": "my.glsl", "runtime": "webgl2"})
    assert beside(Context(out_dir=tmp_path, workers=2), ["sh9", "renders"]) == ["renders"]
    monkeypatch.setattr(registry, "FAMILIES", {**FAMILIES, "plugins": [plugin]})
    assert beside(Context(out_dir=tmp_path, workers=2), ["sh9", "renders"]) == []


def test_renders_runs_beside_and_results_keep_the_order(tmp_path: Path) -> None:
    log: list[tuple[str, str]] = []
    main_ran = threading.Event()
    exps = {"sh9": _exp("sh9", log), "renders": _exp("renders", log, wait=main_ran), "ibl": _exp("ibl", log)}
    seen: list[str] = []

    def finished(n: str, res: ExperimentResult) -> None:
        seen.append(n)
        if n == "ibl":
            main_ran.set()  # renders finishes only after the main lane is done: they overlapped

    out = run_experiments(Context(out_dir=tmp_path, workers=2), exps, ["sh9", "renders", "ibl"],
                          lambda n, b: None, finished)
    assert list(out) == ["sh9", "renders", "ibl"] and [r.name for r in out.values()] == list(out)
    assert seen == ["sh9", "ibl", "renders"]
    threads = dict(log)
    assert threads["renders"] == "validate-renders" and threads["sh9"] == threads["ibl"] != "validate-renders"


def test_serial_run_keeps_the_order(tmp_path: Path) -> None:
    log: list[tuple[str, str]] = []
    exps = {n: _exp(n, log) for n in ("sh9", "renders", "ibl")}
    run_experiments(Context(out_dir=tmp_path), exps, ["renders", "sh9", "ibl"], lambda n, b: None,
                    lambda n, r: None)
    assert [n for n, _ in log] == ["renders", "sh9", "ibl"]
    assert len({th for _, th in log}) == 1


def test_an_error_beside_is_the_runs_error(tmp_path: Path) -> None:
    log: list[tuple[str, str]] = []
    exps = {"renders": _exp("renders", log, fail=True), "sh9": _exp("sh9", log), "ibl": _exp("ibl", log)}
    with pytest.raises(ValidateError, match="renders: broken"):
        run_experiments(Context(out_dir=tmp_path, workers=2), exps, ["sh9", "renders", "ibl"],
                        lambda n, b: time.sleep(0.05), lambda n, r: None)
