"""The order experiments run in: one lane, or two lanes that share the Dask workers.

``renders`` spends most of its wall time waiting: on Chromium (three.js, Babylon.js and Filament on SwiftShader run
in the browser's processes) and on Mitsuba's references (its own background thread). The other experiments wait
on their Dask tasks between the parts this process computes, and some compute on one core (worstcase's searches).
So when the run has Dask workers (:attr:`Context.distributed`) and more than one experiment to do, the experiments
run in **two lanes**: this process is one, a child interpreter (:class:`~validate.run.lane.ProcessLane`)
the other. The second lane starts with the :data:`BESIDE` experiments, this one with the first of the others, and
each lane, when its experiment ends, takes the next one not yet started, in the order of ``todo``. What one lane
leaves idle (a core while its tasks queue on the workers, the gaps between tasks, the browser's waits), the other
fills. When the output folder holds a previous report, the lanes take the experiments longest first by its wall
times (:func:`longest_first`), so that the short ones end the run together. Numbers do not depend on the lane or
the order: every task and reference is seeded by its inputs, never by timing.

Everything runs in one lane, in order, when the run is serial, when it has one experiment, or when a GLSL
technique on the ``webgl2`` runtime is registered (a plug-in): the browser it shares with ``renders`` would be
driven from two processes. An error in either lane stops the run at the next experiment boundary with its own
one-line message; an interrupt unwinds this process as before and ends the child with the other child processes.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable

from ..experiments.base import Background, Context, Experiment, ExperimentResult

BESIDE = ("renders",)
"""Experiments the second lane starts with (see the module docstring)."""


def lanes(ctx: Context, todo: list[str]) -> int:
    """How many lanes run ``todo``: two on a distributed run of more than one experiment, unless a registered
    GLSL technique shares the browser; else one."""
    from ..local_models.registry import FAMILIES

    if not ctx.distributed or len(todo) < 2:
        return 1
    if any(t.meta.get("runtime") == "webgl2" for fam in FAMILIES.values() for t in fam):
        return 1
    return 2


def beside(ctx: Context, todo: list[str]) -> list[str]:
    """The experiments of ``todo`` the second lane starts with (:data:`BESIDE`; none when one lane runs)."""
    return [n for n in todo if n in BESIDE] if lanes(ctx, todo) == 2 else []


Runner = Callable[[str], ExperimentResult]


def longest_first(todo: list[str], seconds: dict[str, float]) -> list[str]:
    """``todo`` in the order the two lanes take it: experiments without a duration first (in ``todo``'s order: one
    may be long), then the others longest first by ``seconds`` (the previous report's wall times). Greedy
    longest-first list scheduling ends the lanes within the last experiment's duration of each other [Graham 1969,
    "Bounds on multiprocessing timing anomalies", SIAM J. Appl. Math. 17(2)], so the short ones fill the end."""
    known = sorted((n for n in todo if n in seconds), key=lambda n: -seconds[n])
    return [n for n in todo if n not in seconds] + known


def run_experiments(ctx: Context, exps: dict[str, Experiment], todo: list[str],
                    started: Callable[[str, bool], None], finished: Callable[[str, ExperimentResult], None],
                    second: Callable[[], tuple[Runner, Callable[[bool], None]]] | None = None,
                    seconds: dict[str, float] | None = None) -> dict[str, ExperimentResult]:
    """Run ``todo`` (names of ``exps``) in :func:`lanes` lanes; ``started(name, second)`` (second: on the second
    lane) and ``finished(name, result)`` report progress; the results come back in the order of ``todo``.
    ``second()`` makes the second lane's (run, close) (default: a :class:`~validate.run.lane.ProcessLane`;
    ``close(False)`` when this lane failed: the other's experiment is abandoned). With two lanes and ``seconds``
    (each experiment's wall time in the previous report), the lanes take the experiments :func:`longest_first`."""
    first = beside(ctx, todo)
    rest = [n for n in todo if n not in first]
    queue = deque(longest_first(rest, seconds) if seconds and lanes(ctx, todo) == 2 else rest)
    lock = threading.Lock()
    done: dict[str, ExperimentResult] = {}
    other: list[Background[None]] = []

    def take() -> str | None:
        with lock:
            return queue.popleft() if queue else None

    def lane(run: Runner, starts: list[str], is_second: bool) -> None:
        name = starts[0] if starts else take()
        while name is not None:
            if not is_second and other and (exc := other[0].failed()) is not None:
                raise exc
            started(name, is_second)
            done[name] = run(name)
            finished(name, done[name])
            name = take()

    def here(name: str) -> ExperimentResult:
        return exps[name].run(ctx)

    if lanes(ctx, todo) == 1:
        lane(here, [], False)
        return {n: done[n] for n in todo}
    if second is None:
        from .lane import ProcessLane

        def second() -> tuple[Runner, Callable[[bool], None]]:
            pl = ProcessLane(ctx)
            return pl.run, pl.close
    run2, close2 = second()
    other.append(Background(lambda: lane(run2, first, True), "validate-lane-2"))
    try:
        lane(here, [], False)
    except BaseException:
        with lock:  # the second lane takes nothing more; its experiment is abandoned
            queue.clear()
        close2(False)
        raise
    try:
        other[0].result()
    finally:
        close2(True)
    return {n: done[n] for n in todo}
