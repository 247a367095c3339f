"""The precision policy of the technique families: one drjit float dtype per family, set at the registry boundary.

Every family declares the dtype its techniques compute in (``define_family(..., precision="float32" |
"float64", precision_reason=...)``, the table in :mod:`.families`). :meth:`.registry.Family.call` makes that
dtype *active* for the duration of the call; a technique converts its numpy inputs with :func:`to_dr` (a flat
drjit array of the active dtype on the active backend), computes with drjit, and hands numpy back with
:func:`to_np` (float64, the registry's output type). Numpy stays at the boundary only: per-environment or
per-light set-up (an SH projection, a fit's table) may be numpy, the per-receiver evaluation is drjit.

Active dtype and backend, innermost first: :func:`computing_in` (tests, benches: ``with computing_in("float64",
backend="scalar"): ...``), then the family of the :meth:`~.registry.Family.call` in progress, then
:data:`DEFAULT` (float32, what :func:`validate.backend.float_type` gives, for helpers called directly).

Backends: ``"llvm"`` (``drjit.llvm.ad``), ``"cuda"`` (``drjit.cuda.ad``), ``"scalar"`` (``drjit.scalar``'s dynamic
``ArrayXf``/``ArrayXf64``); ``None`` means the active Mitsuba variant's (:func:`validate.backend.init`). drjit
arrays of different backends coexist in one process, so the same technique runs on every variant without
switching Mitsuba's.

drjit's kernel cache: a kernel is reused when its IR hash repeats. A Python float in an expression is baked into
the kernel as a literal (a new light, a new kernel), and one input array per column lets the hash follow drjit's
variable numbering; techniques hand per-call numbers over with :func:`constants_dr` (opaque) and per-receiver
columns with :func:`packed_to_dr` / :func:`vec_to_dr` (one packed input), so a repeated call with new numbers or a
new size compiles nothing (tests/local_models/test_ports.py, kernel history).

Unit round-off u = 2⁻²⁴ (float32), 2⁻⁵³ (float64) (Higham, *Accuracy and Stability of Numerical Algorithms*,
2nd ed., §2.1); :data:`UNIT_ROUNDOFF`.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

import numpy as np

from ..errors import ValidateError

PRECISIONS = ("float32", "float64")
DEFAULT = "float32"
BACKENDS = ("llvm", "cuda", "scalar")
UNIT_ROUNDOFF = {"float32": 2.0**-24, "float64": 2.0**-53}
NUMPY_DTYPE = {"float32": np.float32, "float64": np.float64}

_OVERRIDE: ContextVar[tuple[str | None, str | None]] = ContextVar("validate_precision_override", default=(None, None))
_FAMILY: ContextVar[str | None] = ContextVar("validate_precision_family", default=None)
_TRACE: ContextVar[list[str] | None] = ContextVar("validate_precision_trace", default=None)


def check_precision(precision: str, where: str = "precision") -> str:
    """``precision`` if it is one of :data:`PRECISIONS`, else a one-line error."""
    if precision not in PRECISIONS:
        raise ValidateError(f"{where}: precision {precision!r} must be one of {', '.join(PRECISIONS)}")
    return precision


@contextmanager
def computing_in(precision: str | None = None, backend: str | None = None) -> Iterator[None]:
    """Force the dtype (and/or the drjit backend) of every technique evaluated inside the block; what is not
    given is inherited from an enclosing ``computing_in``."""
    if precision is not None:
        check_precision(precision)
    if backend is not None and backend not in BACKENDS:
        raise ValidateError(f"drjit backend {backend!r} must be one of {', '.join(BACKENDS)}")
    outer = _OVERRIDE.get()
    token = _OVERRIDE.set((precision or outer[0], backend or outer[1]))
    try:
        yield
    finally:
        _OVERRIDE.reset(token)


@contextmanager
def family_precision(precision: str) -> Iterator[None]:
    """The family's declared dtype for one :meth:`~.registry.Family.call` (an override still wins)."""
    token = _FAMILY.set(check_precision(precision))
    try:
        yield
    finally:
        _FAMILY.reset(token)


@contextmanager
def tracing() -> Iterator[list[str]]:
    """Record the dtype of every drjit float type handed out by :func:`float_type` inside the block (the
    policy test: a technique that routes through this module records its family's dtype, a numpy-only one
    records nothing)."""
    seen: list[str] = []
    token = _TRACE.set(seen)
    try:
        yield seen
    finally:
        _TRACE.reset(token)


def active() -> str:
    """The dtype techniques compute in right now (override → family → :data:`DEFAULT`)."""
    return _OVERRIDE.get()[0] or _FAMILY.get() or DEFAULT


def active_backend() -> str:
    """The drjit backend right now: the override's, else the active Mitsuba variant's."""
    forced = _OVERRIDE.get()[1]
    if forced is not None:
        return forced
    from ..backend import init

    return init().variant.split("_")[0]


def float_type(precision: str | None = None, backend: str | None = None) -> Any:
    """The dynamic drjit float array type of ``precision`` on ``backend`` (default: the active ones)."""
    import drjit as dr

    p = check_precision(precision or active())
    b = backend or active_backend()
    trace = _TRACE.get()
    if trace is not None:
        trace.append(p)
    if b == "scalar":
        return dr.scalar.ArrayXf64 if p == "float64" else dr.scalar.ArrayXf
    module = dr.cuda.ad if b == "cuda" else dr.llvm.ad
    return module.Float64 if p == "float64" else module.Float


def uint_type(backend: str | None = None) -> Any:
    """The dynamic drjit uint32 array type on ``backend`` (default: the active one), for texel indices."""
    import drjit as dr

    b = backend or active_backend()
    if b == "scalar":
        return dr.scalar.ArrayXu
    return dr.cuda.ad.UInt32 if b == "cuda" else dr.llvm.ad.UInt32


def int_type(backend: str | None = None) -> Any:
    """The dynamic drjit int32 array type on ``backend`` (default: the active one)."""
    import drjit as dr

    b = backend or active_backend()
    if b == "scalar":
        return dr.scalar.ArrayXi
    return dr.cuda.ad.Int32 if b == "cuda" else dr.llvm.ad.Int32


def on_active(x: Any) -> Any:
    """A drjit float array made elsewhere (a Mitsuba-rendered map) as the active dtype and backend: itself when its
    type already is :func:`float_type`'s, else converted through numpy (a copy)."""
    t = float_type()
    return x if type(x) is t else to_dr(np.array(x))


def acos(x: Any) -> Any:
    """arccos(clip(x, −1, 1)) as atan2(√((1 − x)(1 + x)), x): the same on every backend (drjit 1.5's ``acos``
    fails on ``drjit.scalar.ArrayXf64``, a select_ size error); the factored 1 − x² keeps the accuracy near |x| = 1."""
    import drjit as dr

    c = dr.clip(x, -1.0, 1.0)
    return dr.atan2(dr.sqrt(dr.maximum((1.0 - c) * (1.0 + c), 0.0)), c)


ALIGN = 256  # bytes: ≥ drjit's LLVM vector load (16 lanes × 8 bytes = 128) and the CUDA/scalar needs


def to_dr(a: Any) -> Any:
    """numpy (any shape; flattened) or a number → a flat drjit array of the active dtype and backend.

    The values go into a numpy buffer aligned to :data:`ALIGN` bytes: drjit maps numpy memory without a copy and
    marks a pointer off its vector alignment ``unaligned`` (LLVM ``load …, align 1``), which is part of the kernel's
    IR and hash, so an input at wherever numpy's allocator put it missed the kernel cache at random (measured:
    cook_torrance, spot_cos_f recompiling on some runs and not on others, kernel history)."""
    p = active()
    src = np.asarray(a, dtype=np.float64).ravel()
    dt = np.dtype(NUMPY_DTYPE[p])
    buf = np.empty(src.size + ALIGN // dt.itemsize, dtype=dt)
    start = (-buf.ctypes.data % ALIGN) // dt.itemsize
    out = buf[start:start + src.size]
    out[...] = src
    return float_type(p)(out)


def to_np(x: Any, shape: tuple[int, ...] | None = None) -> np.ndarray:
    """A drjit array (or a number, broadcast to ``shape``) → float64 numpy, reshaped to ``shape`` if given."""
    if isinstance(x, (int, float)):
        return np.full(shape or (), float(x))
    out = np.array(x, dtype=np.float64)
    return out.reshape(shape) if shape is not None else out


def vec_to_dr(a: Any) -> tuple[Any, Any, Any]:
    """(N, 3) numpy → three flat drjit arrays (x, y, z) of the active dtype, gathered from one packed input (see
    :func:`packed_to_dr`). Three drjit arrays (x, y, z) of the active type (directions computed in drjit by the
    caller) are handed back as they are."""
    if isinstance(a, (tuple, list)) and len(a) == 3 and all(type(c) is float_type() for c in a):
        return a[0], a[1], a[2]
    m = np.asarray(a, dtype=np.float64).reshape(-1, 3)
    x, y, z = packed_to_dr(m[:, 0], m[:, 1], m[:, 2])
    return x, y, z


def packed_to_dr(*columns: Any) -> list[Any]:
    """Equal-length numpy columns → drjit arrays of the active dtype, gathered from *one* input array (the columns
    side by side, row-major). With one input per column the kernel's hash follows the order drjit numbers its
    variables in, so a repeated call of the same technique missed the kernel cache and recompiled (measured with
    drjit's kernel history; commit 1e41a37 found it first in brdf's GeometryDr)."""
    import drjit as dr

    cols = [np.asarray(c, dtype=np.float64).ravel() for c in columns]
    n, k = len(cols[0]), len(cols)
    if any(len(c) != n for c in cols):
        raise ValidateError(f"packed_to_dr: columns of lengths {[len(c) for c in cols]}: expected equal lengths")
    # row-major (n, k): entry j of row i at k·i + j, offsets that do not depend on n (an offset j·n would be a
    # literal of the size, and a new size a new kernel)
    packed = to_dr(np.stack(cols, axis=1))
    idx = dr.arange(uint_type(), n) * k
    return [dr.gather(float_type(), packed, idx + j) for j in range(k)]


def constants_dr(values: Any) -> list[Any]:
    """Per-call numbers (a light's position, a BRDF parameter) as width-1 reads of one evaluated drjit array:
    opaque to the kernel, so the next call with other numbers reuses the compiled kernel (a Python float is baked
    into the kernel as a literal, and a new literal is a new kernel)."""
    import drjit as dr

    flat = np.asarray(values, dtype=np.float64).ravel()
    data = to_dr(flat)
    dr.make_opaque(data)
    u = uint_type()
    return [dr.gather(float_type(), data, u(k)) for k in range(len(flat))]


def rgb_to_np(r: Any, g: Any, b: Any, n: int) -> np.ndarray:
    """Three drjit arrays (or numbers) → (n, 3) float64 numpy."""
    return np.stack([to_np(c, (n,)) if not isinstance(c, (int, float)) else np.full(n, float(c)) for c in (r, g, b)],
                    axis=-1)
