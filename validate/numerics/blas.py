"""One BLAS thread for the calling thread: small float32 products where waking OpenBLAS's threads costs more CPU than
the product (measured on the 2-core machine: 9 ms vs 0.3 ms for 64 × 4096 cosines on 2 threads vs 1).

Uses ``openblas_set_num_threads_local`` (OpenBLAS ≥ 0.3.27), which sets the count for the *calling thread only* —
never the process-wide ``openblas_set_num_threads``, which is not safe while other threads run BLAS (the
``validate-rows`` pool of :mod:`validate.local_models.irradiance.sh`). A no-op where numpy's BLAS is another library
or an older OpenBLAS. OpenBLAS splits a product by rows, not sums, so results are bit-identical either way.
"""

from __future__ import annotations

import ctypes
import functools
import glob
import os
from typing import Any

import numpy as np


@functools.lru_cache(maxsize=1)
def _setter() -> Any:
    """numpy's ``openblas_set_num_threads_local`` (ctypes), or None."""
    pattern = os.path.join(os.path.dirname(np.__file__) + ".libs", "libscipy_openblas*.so*")
    for path in glob.glob(pattern):
        try:
            fn = ctypes.CDLL(path).openblas_set_num_threads_local
        except (OSError, AttributeError):
            continue
        fn.restype, fn.argtypes = ctypes.c_int, [ctypes.c_int]
        return fn
    return None


class one_blas_thread:  # noqa: N801 - used as a context manager, like contextlib's
    """``with one_blas_thread(): ...`` runs this thread's OpenBLAS calls on one thread, then restores its count."""

    def __enter__(self) -> None:
        fn = _setter()
        self._old = fn(1) if fn is not None else None

    def __exit__(self, *exc: object) -> None:
        fn = _setter()
        if fn is not None and self._old is not None:
            fn(self._old)
