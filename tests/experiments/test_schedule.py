"""The run order (validate.run.schedule): two lanes on a Dask run (``renders`` first on the second, each
lane taking the next experiment when it is free), one lane in order otherwise; results in the order asked; an
error in either lane is the run's error. The second lane's child interpreter (validate.run.lane) returns
the numbers of this process's run."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from validate.errors import ValidateError
from validate.experiments import Context, Experiment, ExperimentResult
from validate.local_models.registry import FAMILIES, Technique
from validate.run.schedule import BESIDE, beside, lanes, run_experiments

Log = list[tuple[str, str]]


def _exp(name: str, log: Log, fail: bool = False, wait: threading.Event | None = None) -> Experiment:
    def run(ctx: Context) -> ExperimentResult:
        log.append((name, threading.current_thread().name))
        if wait is not None:
            assert wait.wait(10), "the other lane never ran while this experiment waited"
        if fail:
            raise ValidateError(f"{name}: broken")
        return ExperimentResult(name, name, "", [], [], [])
    return Experiment(name, name, "", run)


def _thread_lane(exps: dict[str, Experiment], ctx: Context, closed: list[bool]
                 ) -> Callable[[], tuple[Callable[[str], ExperimentResult], Callable[[bool], None]]]:
    """A second lane on this process's thread (the lane logic without a child interpreter)."""
    def second() -> tuple[Callable[[str], ExperimentResult], Callable[[bool], None]]:
        return (lambda n: exps[n].run(ctx)), closed.append
    return second


def test_two_lanes_only_on_a_distributed_run_with_other_experiments(tmp_path: Path) -> None:
    serial, dask = Context(out_dir=tmp_path), Context(out_dir=tmp_path, workers=2)
    assert BESIDE == ("renders",)
    assert lanes(serial, ["sh9", "renders"]) == 1 and beside(serial, ["sh9", "renders"]) == []
    assert lanes(dask, ["renders"]) == 1 and beside(dask, ["renders"]) == []
    assert lanes(dask, ["sh9", "renders", "ibl"]) == 2 and beside(dask, ["sh9", "renders", "ibl"]) == ["renders"]
    assert lanes(dask, ["sh9", "ibl"]) == 2 and beside(dask, ["sh9", "ibl"]) == []


def test_a_webgl2_technique_keeps_everything_in_one_lane(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A GLSL plug-in on the webgl2 runtime shares the browser with renders: one process drives it."""
    from validate.local_models import registry

    fam = next(iter(FAMILIES.values()))
    plugin = Technique("my_shader", fam.name, lambda *a: None, "", meta={"glsl": "my.glsl", "runtime": "webgl2"})
    assert lanes(Context(out_dir=tmp_path, workers=2), ["sh9", "renders"]) == 2
    monkeypatch.setattr(registry, "FAMILIES", {**FAMILIES, "plugins": [plugin]})
    assert lanes(Context(out_dir=tmp_path, workers=2), ["sh9", "renders"]) == 1


def test_the_lanes_overlap_take_the_next_free_and_keep_the_order(tmp_path: Path) -> None:
    log: Log = []
    main_ran = threading.Event()
    ctx = Context(out_dir=tmp_path, workers=2)
    exps = {"sh9": _exp("sh9", log), "renders": _exp("renders", log, wait=main_ran), "ibl": _exp("ibl", log),
            "lights": _exp("lights", log)}
    seen: list[str] = []

    def finished(n: str, res: ExperimentResult) -> None:
        seen.append(n)
        if n == "lights":
            main_ran.set()  # renders finishes only after this lane has done the rest: they overlapped

    closed: list[bool] = []
    out = run_experiments(ctx, exps, ["sh9", "renders", "ibl", "lights"], lambda n, b: None, finished,
                          second=_thread_lane(exps, ctx, closed))
    assert list(out) == ["sh9", "renders", "ibl", "lights"] and [r.name for r in out.values()] == list(out)
    assert seen == ["sh9", "ibl", "lights", "renders"] and closed == [True]
    threads = dict(log)
    assert threads["renders"] == "validate-lane-2" and threads["sh9"] == threads["ibl"] != "validate-lane-2"


def test_serial_run_keeps_the_order(tmp_path: Path) -> None:
    log: Log = []
    exps = {n: _exp(n, log) for n in ("sh9", "renders", "ibl")}
    run_experiments(Context(out_dir=tmp_path), exps, ["renders", "sh9", "ibl"], lambda n, b: None,
                    lambda n, r: None)
    assert [n for n, _ in log] == ["renders", "sh9", "ibl"]
    assert len({th for _, th in log}) == 1


def test_an_error_in_the_second_lane_is_the_runs_error(tmp_path: Path) -> None:
    log: Log = []
    ctx = Context(out_dir=tmp_path, workers=2)
    exps = {"renders": _exp("renders", log, fail=True), "sh9": _exp("sh9", log), "ibl": _exp("ibl", log)}
    closed: list[bool] = []
    with pytest.raises(ValidateError, match="renders: broken"):
        run_experiments(ctx, exps, ["sh9", "renders", "ibl"], lambda n, b: time.sleep(0.05), lambda n, r: None,
                        second=_thread_lane(exps, ctx, closed))
    assert len(closed) == 1  # ended once (at once when this lane saw the error first, else after it)


def test_an_error_in_this_lane_stops_the_other_at_its_next_boundary(tmp_path: Path) -> None:
    log: Log = []
    ctx = Context(out_dir=tmp_path, workers=2)
    exps = {"renders": _exp("renders", log), "sh9": _exp("sh9", log, fail=True), "ibl": _exp("ibl", log),
            "lights": _exp("lights", log)}
    closed: list[bool] = []
    with pytest.raises(ValidateError, match="sh9: broken"):  # the second lane starts 0.3 s late
        run_experiments(ctx, exps, ["sh9", "renders", "ibl", "lights"], lambda n, b: time.sleep(0.3 * b),
                        lambda n, r: None, second=_thread_lane(exps, ctx, closed))
    assert closed == [False]  # abandoned at once
    time.sleep(0.5)
    assert [n for n, _ in log] == ["sh9", "renders"]  # the queue was emptied: nothing after renders


def _numbers(res: ExperimentResult) -> dict:
    out = res.to_json()
    out.pop("wall_time_s")
    return out


def test_the_child_interpreter_returns_this_processs_numbers(tmp_path: Path) -> None:
    """hemisphere --quick in the second lane's child (on a 2-worker LocalCluster) equals the run here; an unknown
    name is a one-line error and the child goes on."""
    from validate.experiments import discover
    from validate.gl import runtime
    from validate.run.lane import ProcessLane

    ctx = Context(out_dir=tmp_path, quick=True, workers=2, show_progress=False)
    try:
        here = discover()["hemisphere"].run(ctx)
        lane = ProcessLane(ctx)
        try:
            with pytest.raises(ValidateError, match="unknown experiment 'nope' in the second lane"):
                lane.run("nope")
            there = lane.run("hemisphere")
        finally:
            lane.close()
    finally:
        ctx.close()
        runtime.close_all()  # forget the child's GL runtimes noted in this process
    assert lane._proc.returncode == 0
    assert _numbers(there) == _numbers(here) and there.claims and all(c.passed for c in there.claims)


def test_two_lanes_take_the_experiments_longest_first_by_the_previous_report(tmp_path: Path) -> None:
    """With the previous report's wall times the lanes take the longest first (unknown ones before them, in
    order); the results still come back in the order asked, and a serial run keeps its order."""
    from validate.run.schedule import longest_first

    seconds = {"a": 5.0, "b": 90.0, "c": 30.0, "renders": 160.0}
    assert longest_first(["a", "b", "new", "c"], seconds) == ["new", "b", "c", "a"]
    assert longest_first(["a", "b"], {}) == ["a", "b"]
    log: Log = []
    main_done = threading.Event()
    exps = {n: _exp(n, log) for n in ("a", "b", "c")}
    exps["renders"] = _exp("renders", log, wait=main_done)  # the second lane is busy until this lane has taken all

    def finished(n: str, res: ExperimentResult) -> None:
        if n == "a":
            main_done.set()

    ctx = Context(out_dir=tmp_path, workers=2)
    out = run_experiments(ctx, exps, ["a", "renders", "b", "c"], lambda n, b: None, finished,
                          second=_thread_lane(exps, ctx, []), seconds=seconds)
    assert list(out) == ["a", "renders", "b", "c"]
    assert [n for n, th in log if th != "validate-lane-2"] == ["b", "c", "a"]  # longest first
    log.clear()
    run_experiments(Context(out_dir=tmp_path), exps, ["a", "b", "c"], lambda n, b: None, lambda n, r: None,
                    seconds=seconds)
    assert [n for n, _ in log] == ["a", "b", "c"]
