"""The run's process settings (validate.run.process): set where unset, kept where set, in place before numpy loads."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from validate.run import process


def test_tune_sets_what_is_unset_and_keeps_what_is_set(monkeypatch: pytest.MonkeyPatch) -> None:
    for key in process.DEFAULTS:
        monkeypatch.delenv(key, raising=False)
    monkeypatch.setenv("OPENBLAS_THREAD_TIMEOUT", "20")
    calls: list[tuple[int, int]] = []
    monkeypatch.setattr(process, "_mallopt", lambda p, v: calls.append((p, v)))
    process.tune()
    assert os.environ["OPENBLAS_THREAD_TIMEOUT"] == "20"
    assert os.environ["MALLOC_MMAP_MAX_"] == "0"
    assert int(os.environ["MALLOC_TRIM_THRESHOLD_"]) == process.TRIM_THRESHOLD
    assert os.environ["MALLOC_ARENA_MAX"] == "1"
    assert os.environ["NUMPY_MADVISE_HUGEPAGE"] == "0"
    assert os.environ["OMP_WAIT_POLICY"] == "PASSIVE"
    assert sorted(calls) == sorted([(-4, 0), (-1, process.TRIM_THRESHOLD), (-8, 1)])


def test_numpy_reads_the_hugepage_setting() -> None:
    """numpy loaded under the tuned environment does not advise huge pages (the setting is numpy's to read: a
    numpy that stopped reading it would bring back the page clearing the module docstring measures)."""
    code = ("import validate.run.process as p\np.tune()\nimport numpy\n"
            "print(numpy._core.multiarray._get_madvise_hugepage())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={k: v for k, v in os.environ.items() if k != "NUMPY_MADVISE_HUGEPAGE"})
    assert out.stdout.strip() == "False"


def test_main_tunes_before_numpy_loads() -> None:
    """What ``python -m validate`` imports before :func:`~validate.run.process.tune` runs leaves numpy unloaded
    (OpenBLAS reads OPENBLAS_THREAD_TIMEOUT when numpy loads)."""
    code = ("import sys\nimport validate.run.interrupt, validate.run.process\n"
            "print('numpy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
    main = (process.__file__.rsplit("/run/", 1)[0]) + "/__main__.py"
    text = open(main, encoding="utf-8").read()
    assert text.index("tune()") < text.index("from .cli import main")
