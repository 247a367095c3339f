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
    return sorted(p for p in root.rglob("*") if p.is_file())


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
