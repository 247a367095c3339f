"""Settings of the run's processes that must be in place before numpy (and the libraries it brings) loads: set by
``python -m validate`` first thing (:func:`tune`), inherited through the environment by the second lane's interpreter
(:class:`~validate.run.lane.ProcessLane`) and by the Dask workers (their nanny spawns them with this environment).

**OpenBLAS's idle threads sleep at once** (``OPENBLAS_THREAD_TIMEOUT=4``: 2⁴ cycles of polling instead of the
default 2²⁸, about 0.1 s). After every product OpenBLAS's worker threads poll for the next one until the timeout; the
suite calls BLAS thousands of times between other work (worstcase's searches, the techniques' small products), so each
call left a core spinning for up to a tenth of a second, taken from the other lane and the Dask workers on this
2-core machine (measured: 100 products of 400 × 2048 by 2048 × 3 with a few ms of Python between them, 1.07 s of CPU
at the default, 0.64 s with the timeout at 4; one thread: 0.50 s). The thread count is unchanged, so every product is
split and summed as before: the same bits.

**glibc keeps freed memory for reuse** (``MALLOC_MMAP_MAX_=0``, ``MALLOC_TRIM_THRESHOLD_`` at 2 GiB; in this process,
which started before :func:`tune` ran, the same through ``mallopt``). By default every allocation above glibc's mmap
threshold (at most 32 MiB) is a fresh mapping, page-faulted anew and unmapped when freed, and the top of the heap is
returned to the system above 128 KiB: the suite's large numpy temporaries (per-chunk quadrature arrays, the V-groove
tracer's path buffers, maps) were faulted in again and again as system time (measured: ``run brdfs --quick`` 2.34 s
and 1.68 s of system time at the defaults, 0.55 s and 0.97 s with these, the same user time; results.json
identical). The price is memory: a process keeps its peak heap until it exits.

**One malloc arena** (``MALLOC_ARENA_MAX=1``). The settings above hold for glibc's main arena only. A thread other
than the main one (a Dask worker runs its tasks on a thread-pool thread; the lanes' background threads) gets an arena of
its own, made of 64 MiB heaps that glibc unmaps whenever one falls empty, whatever the trim threshold: there every large
temporary was faulted in anew (measured: 200 numpy temporaries of 48 MB, 954 minor faults on the main thread and
198 594 on another thread; with one arena 958).

**numpy does not ask for transparent huge pages** (``NUMPY_MADVISE_HUGEPAGE=0``; read when numpy loads). numpy advises
the kernel to back every array above 4 MiB with 2 MiB pages (``madvise(MADV_HUGEPAGE)``); on this machine's kernel
(THP ``madvise`` mode, defrag ``madvise``) each such fault zeroes, and may first compact, a whole 2 MiB page.
Measured on ``run multiscatter --workers 2`` (cold cache, ``perf record -e cpu-clock`` over the run and its
workers): the kernel's page clearing (``clear_page_erms``) took 15.4 % of all samples at the defaults, 1.7 % with huge
pages off and 1.2 % with one arena as well, and the run's samples fell from 24 K to 20 K (−17 % CPU). Neither setting
changes a number: they decide where memory comes from, not what is computed.

**OpenMP's idle threads sleep at once** (``OMP_WAIT_POLICY=PASSIVE``; read when libgomp loads, with FLIP's evaluator).
By default libgomp's team spins after every parallel region, waiting for a thread the other lane has descheduled:
measured, 40 HDR-FLIP calls on 128² images took 8.36 s of CPU (8.52 s wall) with the default policy on the shared
2 cores and 2.27 s (2.37 s) passive, the error maps bit-identical (FLIP's work is per pixel).

A value already in the environment is kept (and not overridden through ``mallopt``).
"""

from __future__ import annotations

import os

TRIM_THRESHOLD = (1 << 31) - 1  # bytes of free memory at the heap's top before glibc returns it (mallopt takes an int)
DEFAULTS = {"OPENBLAS_THREAD_TIMEOUT": "4", "MALLOC_MMAP_MAX_": "0", "MALLOC_TRIM_THRESHOLD_": str(TRIM_THRESHOLD),
            "MALLOC_ARENA_MAX": "1", "NUMPY_MADVISE_HUGEPAGE": "0", "OMP_WAIT_POLICY": "PASSIVE"}
"""Environment variables :func:`tune` sets unless already set (see the module docstring)."""
MALLOPT = {"MALLOC_TRIM_THRESHOLD_": -1, "MALLOC_MMAP_MAX_": -4, "MALLOC_ARENA_MAX": -8}
"""glibc's ``mallopt`` parameters of the :data:`DEFAULTS` glibc reads at start-up (M_TRIM_THRESHOLD, M_MMAP_MAX,
M_ARENA_MAX)."""


def tune() -> None:
    """Set :data:`DEFAULTS` in ``os.environ`` where unset, inherited by the processes this one starts; the glibc
    settings also in this process (``mallopt``: glibc read its environment at start-up). OpenBLAS's is read when
    numpy loads: call this before."""
    for key, value in DEFAULTS.items():
        if key in os.environ:
            continue
        os.environ[key] = value
        if key in MALLOPT:
            _mallopt(MALLOPT[key], int(value))


def _mallopt(param: int, value: int) -> None:
    """glibc's ``mallopt(param, value)`` in this process; nothing where the C library has none (not glibc)."""
    import ctypes

    try:
        fn = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return
    fn.restype, fn.argtypes = ctypes.c_int, [ctypes.c_int, ctypes.c_int]
    fn(param, value)
