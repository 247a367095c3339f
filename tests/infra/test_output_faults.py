"""Output faults are one line and lose nothing.

An ``--out`` that cannot be created or written, and a full disk at any write, give
``validate: error: <path>: <problem>`` with exit status 2, leave the previous report byte for byte
and no file in a fresh output folder. Runs in-process on the ``tiny_io`` fixture experiment
(tests/infra/plugin_tiny.py: three ≈ 28 KB figures, the pages and results.json), so each case costs
well under a second after the first.

Two kinds of full disk: a real one (a 2 MiB tmpfs, needs root to mount; skipped with the reason
otherwise) filled to several levels, and an injected one that works anywhere: ``os.replace`` of
the k-th finished temporary file raises ``OSError(ENOSPC)`` (k = 1 … every write of a run), and
``os.rename`` of the j-th step of the final swap fails (the transaction rolls back).
"""

from __future__ import annotations

import errno
import os
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

from validate import cli
from validate.experiments.base import EXPERIMENTS

PLUGIN = Path(__file__).with_name("plugin_tiny.py")
WRITES_PER_RUN = 6  # 3 figures + results.json + 2 pages (tiny_io), each one atomic replace


@pytest.fixture(autouse=True)
def tiny(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """Only a small constant environment (the fault cases need none of the built-ins); the fixture
    experiment is unregistered afterwards so other in-process runs do not see it."""
    from validate.scenes import procedural

    monkeypatch.setattr(procedural, "builtin_environments", lambda quick=False: [procedural.constant(16)])
    monkeypatch.delenv("VALIDATE_PROBES", raising=False)
    for var in ("TINY_PHASE", "TINY_FIGURES", "TINY_VALUE"):
        monkeypatch.delenv(var, raising=False)
    yield
    EXPERIMENTS.pop("tiny_io", None)


def run(out: Path, capsys: pytest.CaptureFixture[str], *extra: str) -> tuple[int, list[str]]:
    code = cli.main(["run", "tiny_io", "--quick", "--no-progress", "--plugin", str(PLUGIN), "--out", str(out),
                     *extra])
    err = capsys.readouterr().err.strip().splitlines()
    return code, err


def snapshot(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def assert_one_line(code: int, err: list[str], path: str, problem: str) -> None:
    assert code == 2, err
    assert len(err) == 1 and err[0].startswith(f"validate: error: {path}"), err
    assert problem in err[0], err


@pytest.fixture
def previous(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> tuple[Path, dict[str, bytes]]:
    out = tmp_path / "report"
    code, err = run(out, capsys)
    assert code == 0, err
    return out, snapshot(out)


# -- an --out that cannot be created or written ------------------------------------------------------

def test_out_under_proc(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = Path("/proc/validate-no-such-dir/report")
    code, err = run(out, capsys)
    assert_one_line(code, err, str(out), "cannot create the output folder")
    assert not out.exists()


@pytest.mark.parametrize("where", ["file_is_out", "file_is_parent"])
def test_file_in_the_way(tmp_path: Path, capsys: pytest.CaptureFixture[str], where: str) -> None:
    blocker = tmp_path / "blocker"
    blocker.write_text("not a folder")
    out = blocker if where == "file_is_out" else blocker / "report"
    code, err = run(out, capsys)
    assert_one_line(code, err, str(out), "cannot create the output folder")
    assert blocker.read_text() == "not a folder"


def test_read_only_out(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "ro"
    out.mkdir()
    (out / "index.html").write_text("previous")
    if os.geteuid() == 0:  # root writes through mode bits: a read-only mount instead
        if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m,ro", "tmpfs", str(out)],
                          capture_output=True).returncode != 0:
            pytest.skip("running as root and cannot mount a read-only tmpfs")
        try:
            code, err = run(out, capsys)
        finally:
            subprocess.run(["umount", str(out)], check=False)
    else:
        out.chmod(0o555)
        try:
            code, err = run(out, capsys)
        finally:
            out.chmod(0o755)
    assert_one_line(code, err, str(out), "cannot create the output folder")
    assert (out / "index.html").read_text() == "previous"


# -- a full disk, injected -----------------------------------------------------------------------

def _fail_at(monkeypatch: pytest.MonkeyPatch, name: str, k: int, inside: Path) -> list[int]:
    """Make the k-th ``os.<name>`` whose source lies in ``inside`` raise ENOSPC; returns the call count."""
    real = getattr(os, name)
    calls = [0]

    def fake(src: str | os.PathLike[str], dst: str | os.PathLike[str], *a: object, **kw: object) -> None:
        if Path(src).resolve().is_relative_to(inside.resolve()):
            calls[0] += 1
            if calls[0] == k:
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(dst))
        real(src, dst, *a, **kw)

    monkeypatch.setattr(os, name, fake)
    return calls


@pytest.mark.parametrize("k", range(1, WRITES_PER_RUN + 1))
def test_enospc_at_kth_write_keeps_previous_report(previous: tuple[Path, dict[str, bytes]], k: int,
                                                  monkeypatch: pytest.MonkeyPatch,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    out, before = previous
    monkeypatch.setenv("TINY_VALUE", "0.015")  # the new run's numbers differ from the previous report's
    calls = _fail_at(monkeypatch, "replace", k, out)
    code, err = run(out, capsys)
    assert calls[0] == k  # it failed where it was asked to, and wrote nothing after
    assert_one_line(code, err, str(out), "No space left on device")
    assert ".staging-" not in err[0]  # the path is named as the output it was going to be
    assert snapshot(out) == before
    assert [p.name for p in out.iterdir() if p.name.startswith(".")] == []


@pytest.mark.parametrize("k", range(1, WRITES_PER_RUN + 1))
def test_enospc_in_fresh_folder_leaves_nothing(tmp_path: Path, k: int, monkeypatch: pytest.MonkeyPatch,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "fresh" / "report"
    _fail_at(monkeypatch, "replace", k, tmp_path)
    code, err = run(out, capsys)
    assert_one_line(code, err, str(out), "No space left on device")
    assert not (tmp_path / "fresh").exists()


@pytest.mark.parametrize("j", range(1, 9))
def test_failed_swap_rolls_back(previous: tuple[Path, dict[str, bytes]], j: int, monkeypatch: pytest.MonkeyPatch,
                                capsys: pytest.CaptureFixture[str]) -> None:
    """The final renames (figures, page, results.json, index.html, with the old ones moved aside):
    a failure at any one puts every earlier one back."""
    out, before = previous
    monkeypatch.setenv("TINY_VALUE", "0.015")
    _fail_at(monkeypatch, "rename", j, out)
    code, err = run(out, capsys)
    assert code == 2 and len(err) == 1 and err[0].startswith("validate: error:"), err
    assert snapshot(out) == before


# -- a full disk, real (tmpfs) ----------------------------------------------------------------------

@pytest.fixture
def small_disk(tmp_path: Path) -> Iterator[Path]:
    disk = tmp_path / "disk"
    disk.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(disk)], capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs ({(r.stderr or 'mount failed').strip()}); the injected ENOSPC "
                    "tests cover the same paths")
    try:
        yield disk
    finally:
        subprocess.run(["umount", "-l", str(disk)], check=False)


def _fill(disk: Path, leave: int) -> None:
    """Fill the file system until ``leave`` bytes (about) are free."""
    st = os.statvfs(disk)
    free = st.f_bavail * st.f_frsize
    if free > leave:
        with open(disk / "filler", "ab") as fh:
            fh.write(b"\0" * (free - leave))


@pytest.mark.parametrize("leave", [0, 40_000, 90_000, 110_000])  # before/among the figures, at the pages
def test_real_full_disk(small_disk: Path, leave: int, monkeypatch: pytest.MonkeyPatch,
                        capsys: pytest.CaptureFixture[str]) -> None:
    out = small_disk / "report"
    code, err = run(out, capsys)
    assert code == 0, err
    before = snapshot(out)
    monkeypatch.setenv("TINY_VALUE", "0.015")
    _fill(small_disk, leave)
    code, err = run(out, capsys)
    assert_one_line(code, err, str(out), "No space left on device")
    assert snapshot(out) == before
    fresh = small_disk / "fresh"
    code, err = run(fresh, capsys)
    assert_one_line(code, err, str(fresh), "No space left on device")
    assert not fresh.exists()
    shutil.rmtree(out)
