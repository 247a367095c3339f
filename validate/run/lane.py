"""A second lane of experiments in a child interpreter of its own, sharing the run's Dask workers.

Two experiments at once in one process is not safe: Dr.Jit's variables, its common-subexpression cache and
Mitsuba's render state are process-wide, and two threads rendering at once failed here (measured: arealights'
``mi.render`` beside ibl's raised ``jit_var_sub(r2683, r0): operands have incompatible sizes``). A child process
shares none of that: :class:`ProcessLane` starts ``python -m validate.run.lane`` once, sends it the run's
:class:`~validate.experiments.base.Context` (with the environments already loaded, so both lanes see the same
arrays) and the address of the run's Dask scheduler, then one experiment name at a time; the child runs it and
sends the :class:`~validate.experiments.base.ExperimentResult` back. Figures go to the same staging folder.

The child chooses its Mitsuba variant with the same probe (:func:`validate.backend.init`, whose result it
inherits through the environment), loads the run's plug-ins (``ctx.worker_setup``), starts its own GL runtimes
when an experiment asks for one, and reports their ``GL_RENDERER`` strings with each result
(:func:`validate.gl.runtime.note_elsewhere`). It ignores SIGINT: an interrupt is the parent's to handle, and the
parent ends its child processes (:func:`validate.run.interrupt.end_children`); it exits when the parent closes the
pipe. Numbers do not depend on the lane: every task and reference is seeded by its inputs.
"""

from __future__ import annotations

import dataclasses
import os
import pickle
import signal
import socket
import subprocess
import sys
import traceback
from multiprocessing.connection import Connection
from typing import Any

from ..errors import ValidateError
from ..experiments.base import Context, ExperimentResult


class LaneError(RuntimeError):
    """An experiment in the child failed with an exception that could not be sent back as it was."""


class ProcessLane:
    """The child interpreter of the second lane (module docstring); :meth:`run` one experiment, :meth:`close`."""

    def __init__(self, ctx: Context) -> None:
        parent, child = socket.socketpair()
        self._proc = subprocess.Popen([sys.executable, "-m", "validate.run.lane", str(child.fileno())],
                                      pass_fds=(child.fileno(),), close_fds=True,
                                      env={**os.environ, "PYTHONUNBUFFERED": "1"})  # its lines among ours
        child.close()
        self._conn = Connection(parent.detach())
        scheduler = ctx.scheduler or ctx.client().scheduler.address
        lane_ctx = dataclasses.replace(ctx, scheduler=scheduler, _client=None, _env_cache={})
        self._conn.send((lane_ctx, dict(ctx._env_cache)))

    def run(self, name: str) -> ExperimentResult:
        """Run experiment ``name`` in the child; its exception is re-raised here (its traceback printed first
        unless it is a :class:`~validate.errors.ValidateError`, whose one line is the message)."""
        from ..gl import runtime

        try:
            self._conn.send(name)
            status, value, extra = self._conn.recv()
        except (EOFError, OSError) as exc:
            raise ValidateError(f"{name}: the second lane's process ended (exit status {self._proc.poll()}): "
                                f"{type(exc).__name__}") from None
        if status == "ok":
            runtime.note_elsewhere(extra)
            return value
        if not isinstance(value, ValidateError):
            print(extra, file=sys.stderr, end="", flush=True)
        raise value

    def close(self, wait: bool = True) -> None:
        """End the child: with ``wait``, tell it to stop (it closes its GL runtimes and its Dask client) and give
        it 20 s; without (the run failed), or when it does not stop, kill it."""
        if wait:
            try:
                self._conn.send(None)
            except OSError:
                pass
        self._conn.close()
        try:
            self._proc.wait(timeout=20 if wait else 0)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            self._proc.wait()


def _portable(exc: BaseException) -> BaseException:
    """``exc`` if it survives pickling, else a :class:`LaneError` with its type and first line."""
    try:
        pickle.loads(pickle.dumps(exc))
        return exc
    except Exception:
        text = (str(exc).strip().splitlines() or [""])[0]
        return LaneError(f"{type(exc).__name__}: {text}")


def _serve(conn: Connection) -> None:
    from ..backend import init
    from ..experiments import discover
    from ..gl import runtime

    ctx, envs = conn.recv()
    ctx._env_cache.update(envs)
    init()
    if ctx.worker_setup is not None:
        ctx.worker_setup()
    exps = discover()
    try:
        while (name := conn.recv()) is not None:
            try:
                if name not in exps:
                    raise ValidateError(f"unknown experiment {name!r} in the second lane")
                res: Any = ("ok", exps[name].run(ctx), runtime.meta())
            except BaseException as exc:  # sent back; the parent re-raises it
                res = ("error", _portable(exc), traceback.format_exc())
            conn.send(res)
    except EOFError:  # the parent went away
        pass
    finally:
        runtime.close_all()
        ctx.close()


if __name__ == "__main__":
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _serve(Connection(int(sys.argv[1])))
    sys.stdout.flush()
    os._exit(0)
