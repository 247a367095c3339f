"""On-disk cache of reference results, keyed by a content hash.

The key hashes everything the result depends on: the input bytes (an environment's radiance
digest), the parameters, the Mitsuba / drjit versions, the chosen variant and
:data:`REFERENCE_VERSION` (bump it when reference code changes). Entries are ``.npz`` files written
atomically (temp file + rename), so an interrupted run never leaves a corrupt entry; an unreadable
entry is recomputed.

Concurrent writers (several processes, Dask workers): every writer writes its own temporary file
and renames it over the entry, so a reader sees either no entry or a whole one, never a mix; and a
per-key advisory lock (``fcntl.flock`` on ``.locks/<key>``) makes a second process that wants the
same entry wait for the first and then read its result instead of computing it again. Without
``fcntl`` (or where the lock cannot be taken) both compute and the last rename wins — the same bytes,
since references are deterministic.

Location: ``$VALIDATE_CACHE`` if set, else ``$XDG_CACHE_HOME/validate`` (``~/.cache/validate``).
``VALIDATE_CACHE=off`` disables it.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from ..atomic import atomic_path
from ..backend import init
from ..setup.paths import array_digest as array_digest  # re-exported: the keys of every reference use it
from ..setup.paths import cache_dir

REFERENCE_VERSION = 3


def key_of(parts: dict) -> str:
    import drjit as dr
    import mitsuba as mi

    full = dict(parts, _versions=[mi.__version__, dr.__version__, init().variant, REFERENCE_VERSION])
    blob = json.dumps(full, sort_keys=True, default=str).encode()
    return hashlib.sha256(blob).hexdigest()[:40]


@contextlib.contextmanager
def key_lock(root: Path, key: str) -> Iterator[None]:
    """Exclusive advisory lock for one cache key (blocks while another process holds it)."""
    try:
        import fcntl
    except ImportError:  # not POSIX: no lock, writes stay atomic
        yield
        return
    lock_dir = root / ".locks"
    try:
        lock_dir.mkdir(parents=True, exist_ok=True)
        fh = open(lock_dir / key, "a+b")
    except OSError:  # read-only or odd file system: fall back to atomic writes only
        yield
        return
    with fh:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh.fileno(), fcntl.LOCK_UN)


def _load(path: Path) -> dict[str, np.ndarray] | None:
    if not path.exists():
        return None
    try:
        with np.load(path) as z:
            return {k: z[k] for k in z.files}
    except Exception:  # a damaged entry: recompute and replace it
        return None


def cached(kind: str, parts: dict, compute: Callable[[], dict[str, np.ndarray]]) -> dict[str, np.ndarray]:
    """Return the cached arrays for (kind, parts), computing and storing them on a miss."""
    root = cache_dir()
    if root is None:
        return compute()
    key = key_of(parts)
    path = root / kind / f"{key}.npz"
    hit = _load(path)
    if hit is not None:
        return hit
    with key_lock(root, key):
        hit = _load(path)  # another process may have written it while we waited
        if hit is not None:
            return hit
        result = compute()
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(path, suffix=".npz") as tmp:
            with open(tmp, "wb") as fh:
                np.savez(fh, **result)
    return result


def lookup(kind: str, parts: dict) -> dict[str, np.ndarray] | None:
    """The cached arrays for (kind, parts), or None (a miss, or the cache off): for callers that compute many
    misses together (one Blender process for a batch of scenes) and :func:`store` each."""
    root = cache_dir()
    return None if root is None else _load(root / kind / f"{key_of(parts)}.npz")


def store(kind: str, parts: dict, arrays: dict[str, np.ndarray]) -> None:
    """Write the entry (kind, parts) atomically (a no-op when the cache is off)."""
    root = cache_dir()
    if root is None:
        return
    path = root / kind / f"{key_of(parts)}.npz"
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path, suffix=".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)
