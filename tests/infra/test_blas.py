"""validate.numerics.blas.one_blas_thread: the thread-local OpenBLAS switch leaves products bit-identical, nests, and is
safe while other threads run BLAS (the case where the process-wide switch crashed a test worker)."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from validate.numerics.blas import one_blas_thread


def _operands(b: int, k: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return rng.standard_normal((b, 3)).astype(np.float32), rng.standard_normal((k, 3)).astype(np.float32)


def test_one_thread_products_equal_the_threaded_ones() -> None:
    for b, k in ((64, 4096), (2048, 300), (1, 7)):
        d, nd = _operands(b, k, b + k)
        threaded = d @ nd.T
        with one_blas_thread():
            single = d @ nd.T
            with one_blas_thread():  # nested: restores the outer count
                nested = d @ nd.T
            again = d @ nd.T
        assert np.array_equal(single, threaded) and np.array_equal(nested, threaded) and np.array_equal(again, threaded)


def test_switching_while_other_threads_multiply() -> None:
    big = np.random.default_rng(0).standard_normal((512, 512))
    want = big @ big

    def work(i: int) -> bool:
        d, nd = _operands(256, 2048, i)
        ok = True
        for _ in range(20):
            with one_blas_thread():
                ok &= np.array_equal(d @ nd.T, d @ nd.T)
            ok &= np.array_equal(big @ big, want)
        return ok

    with ThreadPoolExecutor(4) as pool:
        assert all(pool.map(work, range(8)))
