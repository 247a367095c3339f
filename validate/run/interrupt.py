"""SIGINT and SIGTERM act within seconds in every phase of a run.

Where a run can block when a signal arrives, and what happens there:

* Python code (numpy, the report, a blocking read from a Node worker's pipe, ``subprocess.run``,
  waiting on Dask futures): the handler runs at once and raises :class:`Interrupted` in the main
  thread; ``finally`` blocks remove the staging folder, ``subprocess.run`` kills its child.
* A native call that does not return to the interpreter: a Mitsuba render (``mi.render``) or a
  drjit kernel (``dr.eval``) runs for as long as its samples take — measured here, a 256² ``path``
  render at 512 spp: 9.3 s during which no Python signal handler runs. Both release the GIL (a
  Python thread ticking every 0.1 s ticked 91 times during that render, 18 times in a 1.9 s drjit
  reduction). So the C-level handler's byte on :func:`signal.set_wakeup_fd` wakes a watchdog thread;
  if the main thread has not finished unwinding :data:`GRACE_S` seconds after the signal, the
  watchdog abandons the call: it runs the registered cleanups (staging folder, a fresh output
  folder), ends every child process (Node workers, Chromium, Dask workers: SIGTERM, then SIGKILL
  after :data:`CHILD_GRACE_S`), prints the one-line message and leaves with ``os._exit(128 + signum)``.
* An import in progress (Mitsuba and drjit import native extensions whose initialisation calls back
  into Python): an exception raised there can abort the process (measured: ``std::terminate`` on a
  ``nanobind::python_error``, SIGABRT). The handler raises nothing while a module is being imported;
  the watchdog ends the run at once instead.
* While the finished report is renamed into place (:func:`deferred`), signals are held: the report is
  the previous one or the new one, never a mix; the watchdog waits for that step to end.

A second signal while unwinding is ignored (the watchdog already guarantees the exit). Where Python
must ignore an exception (a weakref or import-lock callback, ``__del__``), the signal's exception is
dropped without the "Exception ignored" traceback, the run goes on, and the watchdog ends it after
GRACE_S with the one line. Exit status 128 + signum: 130 for SIGINT, 143 for SIGTERM.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

GRACE_S = 2.0  # the main thread's time to unwind by itself before the watchdog abandons it
CHILD_GRACE_S = 0.5  # SIGTERM → SIGKILL for child processes
SIGNALS = (signal.SIGINT, signal.SIGTERM)
MESSAGE = ("validate: interrupted by {name}; the previous report is untouched (finished references are "
           "cached: rerun to resume)")


class Interrupted(BaseException):
    """Raised in the main thread by SIGINT or SIGTERM (a BaseException, like KeyboardInterrupt, so that
    no ``except Exception`` on the way swallows it)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


class _State:
    signum: int | None = None
    armed = False
    abandon_now = False  # the handler left the exit to the watchdog (a signal during an import)
    deferring: list[int] | None = None
    message_printed = False
    cleanups: list[Callable[[], None]] = []
    lock = threading.Lock()


def _on_signal(signum: int, frame: object) -> None:
    if _State.deferring is not None:
        _State.deferring.append(signum)
        return
    if _State.signum is not None:
        return  # already unwinding: the watchdog guarantees the exit
    _State.signum = signum
    if _importing(frame):
        _State.abandon_now = True  # an exception here can abort a native extension's initialisation
        return
    raise Interrupted(signum)


def _importing(frame: Any) -> bool:
    """Is a module being imported somewhere up the stack? (Then an exception raised by the handler
    may pass through an extension's initialisation: measured, Mitsuba's import then ends in
    ``std::terminate`` (SIGABRT) or a fatal "GIL released" error instead of unwinding.)"""
    depth = 0
    while frame is not None and depth < 500:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame, depth = frame.f_back, depth + 1
    return False


@contextlib.contextmanager
def deferred() -> Iterator[list[int]]:
    """Hold SIGINT/SIGTERM while the finished outputs are renamed into place; yields the held signals."""
    _State.deferring = []
    try:
        yield _State.deferring
    finally:
        _State.deferring = None


@contextlib.contextmanager
def cleanup(fn: Callable[[], None]) -> Iterator[None]:
    """Register ``fn`` for the watchdog to run if it abandons the main thread (idempotent cleanups only)."""
    _State.cleanups.append(fn)
    try:
        yield
    finally:
        with contextlib.suppress(ValueError):
            _State.cleanups.remove(fn)


def announce(signum: int) -> None:
    """Print the one-line message (once per process)."""
    with _State.lock:
        if _State.message_printed:
            return
        _State.message_printed = True
    print(MESSAGE.format(name=signal.Signals(signum).name), file=sys.stderr, flush=True)


def child_pids(root: int | None = None) -> list[int]:
    """Every descendant of ``root`` (default: this process), from /proc (Linux; [] elsewhere)."""
    root = os.getpid() if root is None else root
    parents: dict[int, list[int]] = {}
    try:
        entries = os.listdir("/proc")
    except OSError:
        return []
    for entry in entries:
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat", "rb") as fh:
                stat = fh.read()
        except OSError:
            continue
        ppid = int(stat[stat.rfind(b")") + 2:].split()[1])
        parents.setdefault(ppid, []).append(int(entry))
    out, todo = [], [root]
    while todo:
        for child in parents.get(todo.pop(), []):
            out.append(child)
            todo.append(child)
    return out


def end_children(grace: float = CHILD_GRACE_S) -> None:
    """SIGTERM every descendant process, then SIGKILL those still there after ``grace`` seconds."""
    pids = child_pids()
    for sig in (signal.SIGTERM, signal.SIGKILL):
        for pid in pids:
            with contextlib.suppress(OSError):
                os.kill(pid, sig)
        deadline = time.monotonic() + grace
        while sig == signal.SIGTERM and time.monotonic() < deadline:
            if not [p for p in pids if os.path.exists(f"/proc/{p}") and not _zombie(p)]:
                return
            time.sleep(0.05)


def _zombie(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            stat = fh.read()
    except OSError:
        return True
    return stat[stat.rfind(b")") + 2:stat.rfind(b")") + 3] in (b"Z", b"X")


def _abandon(signum: int) -> None:
    for fn in list(_State.cleanups):
        with contextlib.suppress(Exception):
            fn()
    end_children()
    announce(signum)
    with contextlib.suppress(Exception):
        sys.stdout.flush()
    os._exit(128 + signum)


def _watch(read_fd: int) -> None:
    while True:
        try:
            data = os.read(read_fd, 64)
        except OSError:
            data = b""
        if not data:
            with contextlib.suppress(OSError):
                os.close(read_fd)
            return
        got = [b for b in data if b in SIGNALS]
        if not got:
            continue
        t0 = time.monotonic()
        while not _State.abandon_now and (time.monotonic() - t0 < GRACE_S or _State.deferring is not None):
            time.sleep(0.05)
        if _State.armed and _State.deferring is None:
            _abandon(_State.signum or got[0])


def install() -> Callable[[], None]:
    """Install the handlers and the watchdog (main thread only; elsewhere a no-op). Returns the undo."""
    if threading.current_thread() is not threading.main_thread():
        return lambda: None
    previous = {sig: signal.signal(sig, _on_signal) for sig in SIGNALS}
    read_fd, write_fd = os.pipe()
    os.set_blocking(write_fd, False)
    try:
        old_fd = signal.set_wakeup_fd(write_fd, warn_on_full_buffer=False)
    except ValueError:
        old_fd = None
    previous_hook = sys.unraisablehook

    def quiet(unraisable: Any) -> None:  # Interrupted raised where Python must ignore exceptions
        if not isinstance(unraisable.exc_value, Interrupted):
            previous_hook(unraisable)

    sys.unraisablehook = quiet
    threading.Thread(target=_watch, args=(read_fd,), name="validate-signal-watchdog", daemon=True).start()
    _State.signum, _State.armed, _State.message_printed, _State.abandon_now = None, True, False, False

    def undo() -> None:
        _State.armed = False  # a library caller's process is never ended by the watchdog after return
        for sig, handler in previous.items():
            signal.signal(sig, handler)  # type: ignore[arg-type]
        if old_fd is not None:
            signal.set_wakeup_fd(old_fd)
        sys.unraisablehook = previous_hook
        os.close(write_fd)  # the watchdog's read returns b"" and it ends

    return undo


def interrupted() -> int | None:
    """The signal that interrupted this run, if any."""
    return _State.signum
