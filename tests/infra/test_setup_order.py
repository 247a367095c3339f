"""``python -m validate setup``: the pieces are checked at once, then installed and reported in their order."""

from __future__ import annotations

import threading

import pytest

from validate.setup import install
from validate.setup.install import Piece, State


def test_checks_run_together_installs_and_lines_keep_the_order(monkeypatch: pytest.MonkeyPatch) -> None:
    barrier = threading.Barrier(3, timeout=10)  # every first check waits for the other two: they must overlap
    present = {"a": True, "b": False, "c": True}
    installed: list[str] = []

    def check(name: str):
        def run() -> State:
            if not installed:  # the first round of checks
                barrier.wait()
            return State(present[name], f"{name} {'here' if present[name] else 'absent'}")
        return run

    def put(name: str):
        def run(log) -> bool:
            installed.append(name)
            present[name] = True
            return True
        return run

    monkeypatch.setattr(install, "PIECES", tuple(Piece(n, f"piece {n}", check(n), put(n)) for n in "abc"))
    lines: list[str] = []
    assert install.setup(log=lines.append) == 0
    assert installed == ["b"]
    assert [ln.split()[2] for ln in lines if ln.startswith("setup: ok")] == ["a", "b", "c"]
    assert lines[0] == "setup: ok      a         a here  [piece a]"
    assert "b: missing (b absent); installing" in lines[1]


def test_check_only_reports_missing_without_installing(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(install, "PIECES", (Piece("x", "piece x", lambda: State(False, "x absent"),
                                                  lambda log: pytest.fail("installed under --check")),))
    lines: list[str] = []
    assert install.setup(check=True, log=lines.append) == 1
    assert lines == ["setup: MISSING x         x absent  [piece x]"]


def test_a_failed_blender_install_leaves_no_half_made_venv(tmp_path, monkeypatch) -> None:
    """pip failing after the venv was made (offline, no wheel): the venv is removed, so the check and the experiment
    agree that Blender is absent, and one warning line names the step."""
    import subprocess
    from types import SimpleNamespace

    from validate.setup import install, paths

    monkeypatch.setenv("VALIDATE_HOME", str(tmp_path))
    calls = []

    def run(cmd, **kw):
        calls.append(cmd)
        if "venv" in cmd:
            paths.blender_python().parent.mkdir(parents=True)
            paths.blender_python().write_text("")
            return SimpleNamespace(returncode=0, stderr="")
        return SimpleNamespace(returncode=1, stderr="ERROR: No matching distribution found for bpy==5.0.1")

    monkeypatch.setattr(subprocess, "run", run)
    monkeypatch.setattr(install.shutil, "which", lambda name: f"/usr/bin/{name}")
    log: list[str] = []
    assert install.install_blender(log.append) is False
    assert len(calls) == 2 and not paths.blender_venv().exists()
    assert log == [f"setup: WARNING: {paths.blender_python()} -m pip … failed: ERROR: No matching distribution found "
                   "for bpy==5.0.1"]
