"""SIGINT/SIGTERM end a run within seconds in every phase, with one line and the previous report intact.

A ``run tiny_io --quick`` subprocess (tests/infra/plugin_tiny.py) over a previous report is signalled
at several points: during start-up, in Python code, inside one long native Mitsuba render (which
does not return to the interpreter for minutes), in a blocking read from a child process that
ignores both signals (how the Node engine workers are read), and in ``subprocess.run`` of such a
child. The start-up cases hit the imports of Mitsuba's and drjit's native extensions, where a raised
exception used to abort the process (SIGABRT from ``std::terminate``). Each must exit within
:data:`EXIT_WITHIN_S` of the signal with status 128 + signum, one line
on stderr, the previous report byte for byte, no staging folder, and no child process left.

Each case starts a Python process that imports Mitsuba (≈ 5–15 s on a loaded machine), so only the
native render, the case the watchdog exists for, runs by default; the others are ``slow``.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from validate.run.interrupt import GRACE_S

REPO = Path(__file__).resolve().parents[2]
PLUGIN = Path(__file__).with_name("plugin_tiny.py")
EXIT_WITHIN_S = 5.0  # the bound; the watchdog abandons a stuck call after GRACE_S = 2 s
START_TIMEOUT_S = 120.0  # for the marker to appear (imports and the backend probe on a loaded machine)


def _previous_report(out: Path) -> dict[str, bytes]:
    (out / "figures" / "tiny_io").mkdir(parents=True)
    files = {"index.html": b"<html>previous</html>", "results.json": b'{"meta": {}, "experiments": {}}',
             "figures/tiny_io/old.png": b"previous figure"}
    for name, data in files.items():
        (out / name).write_bytes(data)
    return files


def _snapshot(out: Path) -> dict[str, bytes]:
    return {p.relative_to(out).as_posix(): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}


def _interrupt(tmp_path: Path, phase: str, sig: int, after_s: float = 0.0) -> None:
    out, mark = tmp_path / "report", tmp_path / "mark"
    mark.mkdir()
    before = _previous_report(out)
    env = {k: v for k, v in os.environ.items() if k != "VALIDATE_PROBES"}
    env.update(TINY_PHASE="" if phase == "startup" else phase, TINY_MARK=str(mark), TINY_ONLY_CONSTANT="1")
    proc = subprocess.Popen([sys.executable, "-m", "validate", "run", "tiny_io", "--quick", "--no-progress",
                             "--plugin", str(PLUGIN), "--out", str(out)], cwd=REPO, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        if phase == "startup":
            time.sleep(after_s)
        else:
            deadline = time.monotonic() + START_TIMEOUT_S
            while not (mark / phase).exists():
                assert proc.poll() is None, proc.communicate()
                assert time.monotonic() < deadline, f"phase {phase} not reached"
                time.sleep(0.05)
            time.sleep(after_s)
        assert proc.poll() is None, "the run ended before the signal"
        t0 = time.monotonic()
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=30)
        took = time.monotonic() - t0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    print(f"{phase} {signal.Signals(sig).name}: exit {took:.2f} s after the signal")
    assert took < EXIT_WITHIN_S, f"exit {took:.1f} s after {signal.Signals(sig).name}"
    assert proc.returncode == 128 + sig, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"validate: interrupted by {signal.Signals(sig).name}"), err
    assert _snapshot(out) == before
    assert not [p for p in out.iterdir() if p.name.startswith(".")]
    child = mark / "child.pid"
    if child.exists():
        pid = int(child.read_text())
        time.sleep(0.2)
        assert not Path(f"/proc/{pid}").exists() or "Z" in Path(f"/proc/{pid}/stat").read_text().split()[2], pid


def test_sigint_inside_native_render(tmp_path: Path) -> None:
    """Mitsuba's render holds the main thread in native code; the watchdog abandons it after GRACE_S."""
    assert GRACE_S < EXIT_WITHIN_S
    _interrupt(tmp_path, "render", signal.SIGINT, after_s=0.5)


@pytest.mark.slow
@pytest.mark.parametrize(("phase", "sig", "after_s"), [
    ("startup", signal.SIGINT, 0.3),  # start-up: imports of Mitsuba/drjit native extensions, the backend probe
    ("startup", signal.SIGTERM, 1.0),
    ("startup", signal.SIGTERM, 2.0),
    ("startup", signal.SIGINT, 3.0),
    ("python", signal.SIGINT, 0.5),
    ("python", signal.SIGTERM, 1.5),
    ("render", signal.SIGTERM, 2.0),
    ("pipe", signal.SIGINT, 0.5),
    ("pipe", signal.SIGTERM, 0.5),
    ("subprocess", signal.SIGINT, 1.0),
])
def test_signal_in_every_phase(tmp_path: Path, phase: str, sig: int, after_s: float) -> None:
    _interrupt(tmp_path, phase, sig, after_s)
