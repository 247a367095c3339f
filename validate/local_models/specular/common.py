"""The specular family's shared pieces: the reflection vector, the face and block sizes a lobe of width σ
needs, and the per-process cache of prefiltered maps keyed on content digests (used by the Phong-prefiltered
and the split-sum techniques; the sizing rule is derived in :mod:`.prefiltered_specular`'s docstring).
Registers nothing."""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable

import numpy as np

from ..irradiance.irradiance_map import DEFAULT_BLOCK_DEG

TEXELS_PER_LOBE = 4  # largest texel ≤ σ/4 (module docstring)
MIN_FACE = 8  # smallest cube face of a prefiltered map
MAX_FACE = 256  # largest cube face of a prefiltered map


def face_size_for_width(sigma: float) -> int:
    """Smallest power-of-two face N with 2/N ≤ σ/:data:`TEXELS_PER_LOBE`, clamped to [8, 256]."""
    need = 2.0 * TEXELS_PER_LOBE / sigma
    n = MIN_FACE
    while n < need and n < MAX_FACE:
        n *= 2
    return n


def block_deg_for_width(sigma: float) -> float:
    """Node block size: at most σ/4, at most the cosine-kernel default (4°)."""
    return min(DEFAULT_BLOCK_DEG, math.degrees(sigma) / 4.0)


def reflect(normals: np.ndarray, views: np.ndarray) -> np.ndarray:
    """Reflection vectors r = 2(n·v)n − v of unit views v (towards the eye) about unit normals n."""
    n = np.asarray(normals, dtype=np.float64)
    v = np.asarray(views, dtype=np.float64)
    return 2.0 * np.sum(n * v, axis=-1, keepdims=True) * n - v


MAP_CACHE_SIZE = 24  # prefiltered maps kept per process (sparse cube maps: ≤ 6·256²·3 float32 = 4.7 MB each)
_MAP_CACHE: dict[tuple, object] = {}


def array_digest(a: np.ndarray) -> str:
    """Content hash of an array (shape, dtype and bytes): the cache key of maps built from it."""
    a = np.ascontiguousarray(a)
    h = hashlib.blake2b(digest_size=16)
    h.update(f"{a.shape}{a.dtype}".encode())
    h.update(memoryview(a).cast("B"))
    return h.hexdigest()


def cached(key: tuple, build: Callable[[], object]) -> object:
    """``build()`` memoised on ``key`` (insertion-ordered, the oldest entry dropped beyond
    :data:`MAP_CACHE_SIZE`). Keys hold content digests of the inputs, so a changed array is a miss."""
    if key not in _MAP_CACHE:
        if len(_MAP_CACHE) >= MAP_CACHE_SIZE:
            _MAP_CACHE.pop(next(iter(_MAP_CACHE)))
        _MAP_CACHE[key] = build()
    return _MAP_CACHE[key]
