"""Choose and initialise the Mitsuba / drjit variant, safely.

Order of preference: ``cuda_ad_rgb`` (a working GPU) → ``llvm_ad_rgb`` (vectorised CPU) →
``scalar_rgb`` (slow, always works). ``VALIDATE_VARIANT`` overrides the choice.

Each candidate is *probed in a subprocess* before this process touches it: with Debian's default
libLLVM 14/15, drjit's LLVM backend aborts the whole process (``LLVM ERROR: Cannot select ...
fminimum``), which no ``try`` can catch. The probe runs a tiny kernel that uses ``minimum`` and
reports success or the reason. Results are remembered in ``VALIDATE_PROBED_VARIANT`` so child
processes (and a pytest session) probe once.

All local models are written once against drjit arrays of the chosen variant (:data:`Float`), so
the same code runs on CUDA, LLVM and (slowly) scalar dynamic arrays.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from .errors import ValidateError

CANDIDATES = ("cuda_ad_rgb", "llvm_ad_rgb", "scalar_rgb")

_PROBE = r"""
import sys
import mitsuba as mi
import drjit as dr
mi.set_variant(sys.argv[1])
if sys.argv[1].startswith('scalar'):
    x = dr.scalar.ArrayXf([1.0, 2.0, 3.0])
else:
    x = mi.Float([1.0, 2.0, 3.0])
s = dr.sum(dr.minimum(x, 2.0))
s = float(s[0]) if dr.is_array_v(s) else float(s)
assert abs(s - 5.0) < 1e-6, s
e = mi.load_dict({'type': 'constant'})
print('ok')
"""

HINTS = {
    "llvm_ad_rgb": "drjit's LLVM backend needs libLLVM >= 16: `apt-get install libllvm19` "
                   "(or set DRJIT_LIBLLVM_PATH)",
    "cuda_ad_rgb": "no working CUDA GPU/driver",
}


@dataclass(frozen=True)
class Backend:
    variant: str
    reason: str  # why this variant was chosen

    @property
    def is_vectorized(self) -> bool:
        return not self.variant.startswith("scalar")

    @property
    def device(self) -> str:
        return {"cuda": "GPU (CUDA)", "llvm": "CPU (LLVM, vectorised)"}.get(
            self.variant.split("_")[0], "CPU (scalar, slow)")

    def describe(self) -> str:
        return f"{self.variant} — {self.device}; {self.reason}"


def probe_variant(variant: str, timeout: float = 180.0) -> tuple[bool, str]:
    """Run a tiny Mitsuba/drjit program with ``variant`` in a subprocess. Returns (ok, message)."""
    try:
        proc = subprocess.run([sys.executable, "-c", _PROBE, variant], capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        return False, f"probe of {variant} timed out after {timeout:.0f} s"
    if proc.returncode == 0 and proc.stdout.strip().endswith("ok"):
        return True, "probe passed"
    lines = [ln for ln in (proc.stderr or proc.stdout).strip().splitlines() if ln.strip()]
    last = lines[-1] if lines else f"exit status {proc.returncode}"
    return False, last[:200]


def choose_variant() -> Backend:
    """Pick the variant (see module docstring). Raises :class:`ValidateError` on a bad override."""
    import mitsuba as mi

    remembered = os.environ.get("VALIDATE_PROBED_VARIANT")
    override = os.environ.get("VALIDATE_VARIANT")
    if remembered and (not override or remembered.split("|")[0] == override):
        name, _, reason = remembered.partition("|")
        return Backend(name, reason or "probed earlier")
    if override:
        if override not in mi.variants():
            raise ValidateError(f"VALIDATE_VARIANT={override}: unknown variant; available: "
                                f"{', '.join(v for v in mi.variants() if v.endswith('_rgb'))}")
        ok, msg = probe_variant(override)
        if not ok:
            raise ValidateError(f"VALIDATE_VARIANT={override}: variant does not work here ({msg}); "
                                f"{HINTS.get(override, '')}")
        backend = Backend(override, "set by VALIDATE_VARIANT")
    else:
        failures = []
        backend = None
        for name in CANDIDATES:
            if name not in mi.variants():
                failures.append(f"{name}: not compiled in")
                continue
            ok, msg = probe_variant(name)
            if ok:
                why = "first working of cuda → llvm → scalar"
                if failures:
                    why += " (" + "; ".join(failures) + ")"
                backend = Backend(name, why)
                break
            failures.append(f"{name}: {HINTS.get(name, msg[:80])}")
        if backend is None:
            raise ValidateError("no Mitsuba variant works here: " + "; ".join(failures))
    os.environ["VALIDATE_PROBED_VARIANT"] = f"{backend.variant}|{backend.reason}"
    return backend


_ACTIVE: Backend | None = None


def init() -> Backend:
    """Choose the variant once per process and activate it in Mitsuba."""
    global _ACTIVE
    if _ACTIVE is None:
        import mitsuba as mi

        backend = choose_variant()
        mi.set_variant(backend.variant)
        _ACTIVE = backend
    return _ACTIVE


def float_type() -> Any:
    """The dynamic drjit float array of the active variant (``mi.Float`` or scalar ``ArrayXf``)."""
    import drjit as dr
    import mitsuba as mi

    backend = init()
    return mi.Float if backend.is_vectorized else dr.scalar.ArrayXf


def uint_type() -> Any:
    import drjit as dr
    import mitsuba as mi

    backend = init()
    return mi.UInt32 if backend.is_vectorized else dr.scalar.ArrayXu


def load_scene(description: dict[str, Any]) -> Any:
    """``mi.load_dict(description, optimize=False)``: a scene whose shapes and emitters are in the dict's order.

    Mitsuba 3.9's default ``optimize=True`` runs the parser's ``transform_merge_meshes``: every mesh (``obj``,
    ``rectangle``, ``mi.Mesh`` ...) is regrouped by the ``merge`` shape (src/shapes/merge.cpp) in an
    ``std::unordered_map`` keyed by its BSDF/emitter *pointers*, so the scene's shape and emitter lists come out in
    an order that changes from one load to the next. With two or more emitters, that order decides which emitter
    each sample's emitter-selection number picks: the same seed gives a different (equally valid) estimate —
    measured: the tube's three emitters (cylinder + two ``obj`` caps), 5 loads in 60 in the other order, every
    pixel different. ``optimize=False`` (no mesh merging, no merging of identical nodes) keeps the dict's order:
    150 loads in 150 identical."""
    import mitsuba as mi

    init()
    return mi.load_dict(description, optimize=False)


@contextlib.contextmanager
def drjit_threads(count: int | None) -> Iterator[None]:
    """Dr.Jit's thread pool at ``count`` threads meanwhile (None: as it is), the count as it was after."""
    import drjit as dr

    if count is None:
        yield
        return
    before = dr.thread_count()
    dr.set_thread_count(count)
    try:
        yield
    finally:
        dr.set_thread_count(before)


def bitmap_io_threads() -> contextlib.AbstractContextManager[None]:
    """At least two Dr.Jit pool threads while Mitsuba reads or writes an image file (:func:`drjit_threads`).

    Mitsuba's OpenEXR (and RGBE) I/O hands its work to Dr.Jit's thread pool and waits for it; with a pool of one
    thread (``dr.set_thread_count(1)``, as worstcase's search and brdfs' elementwise kernels run) nothing runs
    that work and the call never returns (measured: ``mi.Bitmap("….exr")`` and ``Bitmap.write("….exr")`` still
    waiting after 40 s, OpenEXR's ``TaskGroup`` destructor on its semaphore; the same calls on two threads: a few
    milliseconds)."""
    import drjit as dr

    return drjit_threads(None if dr.thread_count() >= 2 else 2)


RAY_PACKET = 64  # rays: every array handed to a Mitsuba scene query is padded to a multiple of this (see below)


def padded_count(n: int) -> int:
    """``n`` rounded up to a multiple of :data:`RAY_PACKET` (at least one packet).

    Why: on the LLVM variant, ``Scene.ray_test`` / ``ray_intersect`` (Mitsuba 3.9.1, drjit 1.x, Embree)
    read a ray component array *past its end* when its length is not a multiple of the packet width.
    Normally the bytes past the end are mapped (malloc slack) and only masked-off lanes see them, but when a
    large buffer's end lies within a few dozen bytes of an unmapped page the read faults: SIGSEGV in a
    drjit worker thread (``nt [1]``). Measured here: 135 154 rays (the ``lights`` disc frame's shadow
    rays, 135 154 mod 16 = 2) from numpy, run with ``GLIBC_TUNABLES=glibc.malloc.mmap_threshold=4096``
    (every allocation its own mapping, so no slack hides the over-read), crash on every run — in
    ``segment_visible``, and in a 20-line script with one sphere and nothing else loaded (no GL); 135 155
    crash; 135 168 (a multiple of 16) and any count padded to a multiple of 64 never crash. In an ordinary
    run the fault needs an unlucky heap layout, hence the rare ``-11`` of ``all --quick``. Only rays whose
    components come from numpy (zero-copy or strided import) were seen to fault; rays computed by drjit kernels
    (``dr.arange``/``dr.gather``, a sensor's ``sample_ray``) ran clean at the same counts, so only the former
    are padded. Padding costs at most 63 extra rays. The first ``n`` results of a ``ray_test`` (and of
    ``ray_intersect`` on analytic shapes) are unchanged, but on a triangle mesh the rays of the former partial
    packet may hit ULPs apart (likely Embree's packet vs single-ray traversal): measured 1e-9 relative in
    ``ibl``'s dented-sphere G-buffer, which is therefore left unpadded. Checked bit-identical on ``--quick``
    results.json with fresh caches: brdfs, lights, shadows, uberlight."""
    return max(RAY_PACKET, -(-int(n) // RAY_PACKET) * RAY_PACKET)


def pad_rows(a: Any, count: int) -> Any:
    """``a`` (N, …) as a C-contiguous float32 array of ``count`` ≥ N rows: the last row repeated (a row of zeros
    when N = 0). Used with :func:`padded_count` for arrays that become rays of a scene query."""
    import numpy as np

    a = np.asarray(a, dtype=np.float32)
    if a.shape[0] > count:
        raise ValidateError(f"pad_rows: {a.shape[0]} rows do not fit in {count}")
    filler = a[-1:] if a.shape[0] else np.zeros((1, *a.shape[1:]), dtype=np.float32)
    return np.ascontiguousarray(np.concatenate([a, np.repeat(filler, count - a.shape[0], axis=0)]))
