"""The content-hash reference cache (validate.reference.cache)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from validate.reference import cache


class Counter:
    """A compute function that counts its calls and returns fresh arrays."""

    def __init__(self) -> None:
        self.calls = 0

    def __call__(self) -> dict[str, np.ndarray]:
        self.calls += 1
        return {"a": np.arange(12, dtype=np.float64).reshape(3, 4) / 7, "b": np.array([1, 2, 3], np.int32)}


def _entries(root: Path) -> list[Path]:
    """Cache files, without the per-key lock files under ``.locks/``."""
    return sorted(p for p in root.rglob("*") if p.is_file() and ".locks" not in p.parts)


@pytest.fixture
def cache_root(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("VALIDATE_CACHE", str(tmp_path))
    return tmp_path


def test_miss_computes_and_hit_returns_identical_data(cache_root: Path) -> None:
    compute = Counter()
    parts = {"env": "abc", "cells": 8}
    first = cache.cached("unit", parts, compute)
    assert compute.calls == 1
    second = cache.cached("unit", parts, compute)
    assert compute.calls == 1  # hit: not recomputed
    assert set(second) == {"a", "b"}
    for k in first:
        assert second[k].dtype == first[k].dtype and np.array_equal(second[k], first[k])
    # other parts, other key
    cache.cached("unit", {"env": "abc", "cells": 16}, compute)
    assert compute.calls == 2
    entries = _entries(cache_root)
    assert len(entries) == 2 and all(p.suffix == ".npz" and p.parent.name == "unit" for p in entries)
    assert not any(p.name.startswith(".") for p in entries)  # no temporary files left behind


def test_corrupted_entry_is_recomputed(cache_root: Path) -> None:
    compute = Counter()
    parts = {"env": "corrupt-me"}
    cache.cached("unit", parts, compute)
    (entry,) = _entries(cache_root)
    entry.write_bytes(b"not a zip file at all")
    again = cache.cached("unit", parts, compute)
    assert compute.calls == 2
    assert np.array_equal(again["a"], Counter()()["a"])
    assert _entries(cache_root) == [entry]  # replaced in place, no temp files
    cache.cached("unit", parts, compute)  # and now readable again
    assert compute.calls == 2


def test_truncated_entry_is_recomputed(cache_root: Path) -> None:
    compute = Counter()
    cache.cached("unit", {"x": 1}, compute)
    (entry,) = _entries(cache_root)
    entry.write_bytes(entry.read_bytes()[:40])
    cache.cached("unit", {"x": 1}, compute)
    assert compute.calls == 2


def test_off_disables_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("VALIDATE_CACHE", "off")
    monkeypatch.chdir(tmp_path)
    assert cache.cache_dir() is None
    compute = Counter()
    cache.cached("unit", {"k": 1}, compute)
    cache.cached("unit", {"k": 1}, compute)
    assert compute.calls == 2
    assert _entries(tmp_path) == []


def test_key_depends_on_every_part() -> None:
    base = {"env": "e", "normals": "n", "cells": 8}
    k = cache.key_of(base)
    assert k == cache.key_of(dict(base))  # deterministic
    for change in ({"env": "f"}, {"normals": "m"}, {"cells": 9}, {"extra": 1}):
        assert cache.key_of({**base, **change}) != k


def test_array_digest_sees_values_shape_and_dtype() -> None:
    a = np.arange(6, dtype=np.float64)
    assert cache.array_digest(a) == cache.array_digest(a.copy())
    assert cache.array_digest(a) != cache.array_digest(a.reshape(2, 3))
    assert cache.array_digest(a) != cache.array_digest(a.astype(np.float32))
    b = a.copy()
    b[3] += 1e-12
    assert cache.array_digest(a) != cache.array_digest(b)


# Two processes that want the same five entries at the same time. Each compute sleeps 0.2 s (long
# enough that both processes are inside `cached` together) and appends its key to a log.
_WRITER = """
import sys, time, numpy as np
from validate.reference import cache
if sys.argv[2] == "nolock":
    import contextlib
    cache.key_lock = lambda root, key: contextlib.nullcontext()
log = open(sys.argv[1], "a")
def compute(k):
    def f():
        time.sleep(0.2)
        log.write(f"{k}\\n"); log.flush()
        return {"v": np.full(1000, float(k))}
    return f
for k in range(5):
    r = cache.cached("race", {"k": k}, compute(k))
    assert r["v"].shape == (1000,) and (r["v"] == k).all()
print("ok")
"""


@pytest.mark.parametrize("mode", ["lock", "nolock"])
def test_two_concurrent_writers(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, mode: str) -> None:
    """With the per-key lock each entry is computed once in all; without it (no fcntl) both processes
    compute and rename — still every read is whole and no temporary file is left behind."""
    import os
    import subprocess
    import sys

    cache_root = tmp_path / "cache"
    monkeypatch.setenv("VALIDATE_CACHE", str(cache_root))
    log = tmp_path / "computed.log"
    env = dict(os.environ, VALIDATE_CACHE=str(cache_root))
    procs = [subprocess.Popen([sys.executable, "-c", _WRITER, str(log), mode], env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(2)]
    outs = [p.communicate(timeout=120) for p in procs]
    assert all(p.returncode == 0 for p in procs), outs
    computed = log.read_text().split()
    if mode == "lock":
        assert sorted(computed) == [str(k) for k in range(5)]  # each key once, across both processes
    else:
        assert sorted(set(computed)) == [str(k) for k in range(5)]
    entries = _entries(cache_root)
    assert len(entries) == 5 and not any(p.name.startswith(".") for p in entries)
    for k in range(5):
        assert np.array_equal(cache.cached("race", {"k": k}, Counter())["v"], np.full(1000, float(k)))
