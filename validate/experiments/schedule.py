"""The order experiments run in: one after another, except the experiments that mostly wait on another process.

``renders`` spends most of its wall time waiting: on Chromium (three.js, Babylon.js and Filament on SwiftShader run
in the browser's processes) and on Mitsuba's references (its own background thread). When the run has Dask workers
(:attr:`Context.distributed`) and more than one experiment to do, such an experiment runs on a thread of this
process *beside* the others (:data:`BESIDE`): while the others' per-environment tasks run on the workers, this
process's core and the gaps between tasks are free for the browser. Numbers do not depend on it: every task and
reference is seeded by its inputs, never by timing (docs/scale.md).

What makes the overlap safe:

* the playwright sync API is bound to the thread that starts the browser; the only user of the browser in a run is
  ``renders`` itself — unless a GLSL technique of the ``webgl2`` runtime is registered (a plug-in), which then
  shares the browser from another thread: in that case everything runs in order;
* the report's figures are drawn under :data:`validate.report.plots.FIGURE_LOCK` (matplotlib's drawing is not
  thread-safe);
* an error of the experiment beside stops the run at the next experiment boundary with its own one-line message;
  an interrupt unwinds the main thread as before (the thread beside is a daemon and dies with the process).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

from .base import Background, Context, Experiment, ExperimentResult

BESIDE = ("renders",)
"""Experiments that run beside the others when the run has Dask workers (see the module docstring)."""


def beside(ctx: Context, todo: list[str]) -> list[str]:
    """The experiments of ``todo`` that run on a thread beside the others (none unless distributed, with more
    than one experiment, and no registered GLSL technique sharing the browser)."""
    from ..local_models.registry import FAMILIES

    if not ctx.distributed or len(todo) < 2:
        return []
    if any(t.meta.get("runtime") == "webgl2" for fam in FAMILIES.values() for t in fam):
        return []
    return [n for n in todo if n in BESIDE]


def run_experiments(ctx: Context, exps: dict[str, Experiment], todo: list[str],
                    started: Callable[[str, bool], None], finished: Callable[[str, ExperimentResult], None]
                    ) -> dict[str, ExperimentResult]:
    """Run ``todo`` (names of ``exps``): the :func:`beside` ones on threads started first, the rest in order on
    this thread. ``started(name, beside)`` and ``finished(name, result)`` report progress; the results come back
    in the order of ``todo``."""
    side: dict[str, Background[ExperimentResult]] = {}
    for n in beside(ctx, todo):
        started(n, True)
        side[n] = Background(partial(exps[n].run, ctx), f"validate-{n}")
    done: dict[str, ExperimentResult] = {}
    for n in todo:
        if n in side:
            continue
        for th in side.values():
            if (exc := th.failed()) is not None:
                raise exc
        started(n, False)
        done[n] = exps[n].run(ctx)
        finished(n, done[n])
    for n, th in side.items():
        done[n] = th.result()
        finished(n, done[n])
    return {n: done[n] for n in todo}
