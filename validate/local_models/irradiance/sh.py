"""Real spherical harmonics and SH irradiance (Ramamoorthi & Hanrahan 2001).

References
  [1] R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
      SIGGRAPH 2001 — eq. 8 (E = Σ Â_l L_lm Y_lm), eq. 12 (the quadratic form, c1…c5).
  [2] R. Ramamoorthi, P. Hanrahan, "On the relationship between radiance and irradiance",
      JOSA A 18(10), 2001 — A_l of the clamped cosine, eq. 19.
  [3] P.-P. Sloan, "Stupid Spherical Harmonics (SH) Tricks", GDC 2008 — the recurrences.

Conventions
  * Real SH *without* the Condon–Shortley phase, as in [1]: Y_1,−1 = +0.488603·y,
    Y_10 = 0.488603·z, Y_11 = 0.488603·x, Y_2,−2 = 1.092548·xy, Y_2,−1 = 1.092548·yz,
    Y_20 = 0.315392(3z² − 1), Y_21 = 1.092548·xz, Y_22 = 0.546274(x² − y²).
  * The basis is a polynomial in the *world* direction (x, y, z): z is the polar axis of the SH frame
    even though the world is y-up. Index k = l(l+1) + m; order 2 ("SH9") is
    L00, L1m1, L10, L11, L2m2, L2m1, L20, L21, L22.
  * Y_l^m = √2 K_l^m Q_l^m(z) Re/Im((x + iy)^m), with K_l^m = √((2l+1)/(4π) (l−m)!/(l+m)!) and
    Q_l^m = P_l^m / sin^m θ (no (−1)^m), from Q_m^m = (2m−1)!!, Q_{m+1}^m = (2m+1) z Q_m^m,
    (l−m) Q_l^m = (2l−1) z Q_{l−1}^m − (l+m−1) Q_{l−2}^m.

The basis uses only +, −, × on its inputs, so the same code evaluates numpy arrays (for plots and
tests) and drjit arrays of any backend (the model itself).

This is the irradiance family's shared SH code (projection, basis, rendering): it registers nothing. The
truncated-SH techniques are :mod:`.sh_truncated`; the windowed, ZH3 and cmgen techniques and the
``arealight`` family's disc SH use the same functions.
"""

from __future__ import annotations

import functools
import math
import os
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np

from ...numerics.blas import one_blas_thread
from ...scenes import latlong
from ..precision import constants_dr, to_dr, vec_to_dr

# R&H 2001 eq. 12 constants [1].
C1, C2, C3, C4, C5 = 0.429043, 0.511664, 0.743125, 0.886227, 0.247708
SH9_NAMES = ("L00", "L1m1", "L10", "L11", "L2m2", "L2m1", "L20", "L21", "L22")


def n_coeffs(lmax: int) -> int:
    return (lmax + 1) ** 2


def sh_index(l: int, m: int) -> int:
    return l * (l + 1) + m


def degree_of(k: int) -> int:
    return int(math.isqrt(k))


def _k(l: int, m: int) -> float:
    return math.sqrt((2 * l + 1) / (4 * math.pi) * math.factorial(l - m) / math.factorial(l + m))


def eval_basis(x: Any, y: Any, z: Any, lmax: int) -> list[Any]:
    """All (lmax+1)² real SH basis functions at unit directions (x, y, z) — any array type."""
    out: list[Any] = [None] * n_coeffs(lmax)
    cm, sm = x * 0 + 1.0, x * 0.0  # Re/Im of (x + iy)^m
    for m in range(lmax + 1):
        if m > 0:
            cm, sm = cm * x - sm * y, cm * y + sm * x
        qmm = float(np.prod(np.arange(1, 2 * m, 2))) if m > 0 else 1.0  # (2m−1)!!
        q_prev2, q_prev = None, x * 0 + qmm
        for l in range(m, lmax + 1):
            if l == m:
                q = q_prev
            elif l == m + 1:
                q = z * (2 * m + 1) * qmm
                q_prev2, q_prev = q_prev, q
            else:
                q = (z * (2 * l - 1) * q_prev - (l + m - 1) * q_prev2) * (1.0 / (l - m))
                q_prev2, q_prev = q_prev, q
            if m == 0:
                out[sh_index(l, 0)] = q * _k(l, 0)
            else:
                s = math.sqrt(2.0) * _k(l, m)
                out[sh_index(l, m)] = q * cm * s
                out[sh_index(l, -m)] = q * sm * s
    return out


def eval_basis_numpy(d: np.ndarray, lmax: int) -> np.ndarray:
    """Basis at directions d (..., 3) as a numpy array (..., (lmax+1)²)."""
    d = np.asarray(d, dtype=np.float64)
    return np.stack(eval_basis(d[..., 0], d[..., 1], d[..., 2], lmax), axis=-1)


def clamped_cosine_al(l: int) -> float:
    """A_l of the clamped cosine max(cos θ, 0) [2, eq. 19]: A0 = π, A1 = 2π/3, odd l > 1: 0,
    even l: 2π (−1)^(l/2−1) / ((l+2)(l−1)) · l! / (2^l ((l/2)!)²)."""
    if l == 0:
        return math.pi
    if l == 1:
        return 2 * math.pi / 3
    if l % 2:
        return 0.0
    h = l // 2
    return (2 * math.pi * (-1) ** (h - 1) / ((l + 2) * (l - 1))
            * math.factorial(l) / (2 ** l * math.factorial(h) ** 2))


def _to_float(a: np.ndarray) -> Any:
    return to_dr(a)  # the active dtype of the precision policy (the irradiance family's float32)


def project_samples(directions: np.ndarray, weights: np.ndarray, radiance: np.ndarray, lmax: int) -> np.ndarray:
    """L_lm = Σ_k L(ω_k) Y_lm(ω_k) w_k over samples (directions (N,3), weights (N,), radiance (N,3))."""
    import drjit as dr

    x, y, z = (_to_float(directions[:, i]) for i in range(3))
    wl = [_to_float(radiance[:, c] * weights) for c in range(3)]
    basis = eval_basis(x, y, z, lmax)
    n = directions.shape[0]
    coeffs = np.zeros((len(basis), 3))
    for c in range(3):
        if _is_jit(x):  # one kernel: all basis products side by side, reduced block by block
            coeffs[:, c] = np.array(dr.block_sum(dr.concat([yk * wl[c] for yk in basis]), n))
        else:
            coeffs[:, c] = [float(dr.sum(yk * wl[c])) for yk in basis]
    return coeffs


def _is_jit(a: Any) -> bool:
    import drjit as dr

    return bool(dr.is_jit_v(a))


ROW_BLOCK_BYTES = 32 << 20  # rows of the map handled together (~32 MiB of texels)


@functools.lru_cache(maxsize=16)
def fourier_columns(width: int, lmax: int) -> np.ndarray:
    """T (W, 2·lmax+1): [1, cos φ_j, sin φ_j, …, cos(lmax φ_j), sin(lmax φ_j)] at the column
    centres φ_j = 2π(j+½)/W of Mitsuba's lat-long convention."""
    phi = (np.arange(width, dtype=np.float64) + 0.5) * (2.0 * np.pi / width)
    t = np.empty((width, 2 * lmax + 1))
    t[:, 0] = 1.0
    for m in range(1, lmax + 1):
        t[:, 2 * m - 1], t[:, 2 * m] = np.cos(m * phi), np.sin(m * phi)
    t.flags.writeable = False  # cached: shared by every caller
    return t


@functools.lru_cache(maxsize=16)
def row_basis_fourier(height: int, lmax: int) -> np.ndarray:
    """A (H, 2·lmax+1, K): on the row at polar angle θ_i every basis function is a trigonometric
    polynomial of degree ≤ lmax in φ (Y_lm is a degree-l polynomial in x = sin φ sin θ, y = cos θ,
    z = −cos φ sin θ), so Y_k(θ_i, φ) = Σ_q A[i, q, k] T_q(φ) exactly. A is found from the basis at
    2·lmax+1 equispaced φ per row (exact interpolation of such polynomials). Rows θ_i = iπ/(H−1)."""

    theta = latlong.row_theta(height)
    q = 2 * lmax + 1
    psi = np.arange(q) * (2.0 * np.pi / q)
    t = np.empty((q, q))
    t[:, 0] = 1.0
    for m in range(1, lmax + 1):
        t[:, 2 * m - 1], t[:, 2 * m] = np.cos(m * psi), np.sin(m * psi)
    tt, pp = np.meshgrid(theta, psi, indexing="ij")
    st = np.sin(tt)
    d = np.stack([np.sin(pp) * st, np.cos(tt), -np.cos(pp) * st], axis=-1)  # latlong convention
    y = eval_basis_numpy(d, lmax)  # (H, q, K)
    a = np.einsum("qs,isk->iqk", np.linalg.inv(t), y)
    a.flags.writeable = False  # cached: shared by every caller
    return a


POLYPHASE = (32, 16, 8, 4, 2, 1)  # phase counts tried, largest dividing the width first


def polyphase(width: int) -> int:
    """The number of phases k of :func:`fourier_row_sums`: the largest of :data:`POLYPHASE` dividing W."""
    return next(k for k in POLYPHASE if width % k == 0)


@functools.lru_cache(maxsize=16)
def _polyphase_operators(width: int, lmax: int, k: int) -> tuple[np.ndarray, np.ndarray]:
    """(T_k (1, q, W/k), C (1, q, q·k)) of :func:`fourier_row_sums`, float32, read-only."""
    t_k = np.ascontiguousarray(fourier_columns(width, lmax).T[:, ::k], dtype=np.float32)[None]
    q, step = 2 * lmax + 1, 2.0 * np.pi / width
    c = np.zeros((q, q, k))
    c[0, 0] = 1.0
    for m in range(1, lmax + 1):
        cm, sm = np.cos(m * step * np.arange(k)), np.sin(m * step * np.arange(k))
        c[2 * m - 1, 2 * m - 1], c[2 * m - 1, 2 * m] = cm, -sm  # cos m(φ + rΔ) = cos mφ cos mrΔ − sin mφ sin mrΔ
        c[2 * m, 2 * m], c[2 * m, 2 * m - 1] = cm, sm  # sin m(φ + rΔ) = sin mφ cos mrΔ + cos mφ sin mrΔ
    c = np.ascontiguousarray(c.reshape(q, q * k), dtype=np.float32)[None]
    t_k.flags.writeable = c.flags.writeable = False
    return t_k, c


def fourier_row_sums(radiance: np.ndarray, lmax: int) -> np.ndarray:
    """R[i, q, c] = Σ_j L_ijc T_q(φ_j) (:func:`fourier_columns`) for every row of a (H, W, 3) map → (H, 2·lmax+1, 3)
    float32; ``lmax = 0`` is the plain row sum Σ_j L_ij.

    Polyphase form (shift theorem): with k phases (:func:`polyphase`) and Δ = 2π/W, column j = kp + r has
    φ_j = φ_kp + rΔ, and cos m(φ + rΔ), sin m(φ + rΔ) are a rotation by mrΔ of (cos mφ, sin mφ), so

        R[i, ·, c] = Σ_r Rot_r · P[i, ·, r, c],   P[i, q, r, c] = Σ_p T_q(φ_kp) L_i,kp+r,c

    — P is one matrix product per row with the row read as a (W/k, 3k) matrix (no copy): 3k columns instead
    of 3 let BLAS run its efficient kernels at the same 2·lmax+1 multiply-adds per value; the rotations are
    a (q, q·k) product per row. Rows are shared among the process's CPUs (numpy's matmul releases the GIL)
    and, within a thread, read in blocks of about :data:`ROW_BLOCK_BYTES`, cast to float32 block by block
    (no full-size copy). Each pool thread runs its products on one BLAS thread of its own
    (:class:`validate.numerics.blas.one_blas_thread`): the pool already occupies every CPU (nested BLAS threads only
    oversubscribe it), and no two Python threads share OpenBLAS's thread server (concurrent calls into it are
    where pthreads OpenBLAS has crashed before, e.g. OpenMathLib/OpenBLAS#4981, fixed in 0.3.29; a test worker
    segfaulted here with no Python frame on the crashing thread). OpenBLAS splits a product by rows, not sums,
    so the bits are the same (tested against the direct sum)."""
    h, w = radiance.shape[:2]
    k = polyphase(w)
    t_k, rot = _polyphase_operators(w, lmax, k)
    q = t_k.shape[1]
    rows = np.empty((h, q, 3), dtype=np.float32)
    step = max(1, ROW_BLOCK_BYTES // max(1, radiance[0].nbytes))

    def work(span: tuple[int, int]) -> None:
        buf = np.empty((min(step, span[1] - span[0]), q, 3 * k), dtype=np.float32)
        with one_blas_thread():
            for s in range(span[0], span[1], step):
                e = min(s + step, span[1])
                block = np.asarray(radiance[s:e], dtype=np.float32).reshape(e - s, w // k, 3 * k)
                np.matmul(t_k, block, out=buf[:e - s])
                np.matmul(rot, buf[:e - s].reshape(e - s, q * k, 3), out=rows[s:e])

    n = min(_cpus(), h)
    bounds = np.linspace(0, h, n + 1).astype(int)
    spans = [(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if b > a]
    if len(spans) == 1:
        work(spans[0])
    else:
        list(_pool().map(work, spans))
    return rows


def _cpus() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


_POOL: dict[int, ThreadPoolExecutor] = {}  # per process id: a forked child must not reuse its parent's (dead) threads


def _pool() -> ThreadPoolExecutor:
    pid = os.getpid()
    if pid not in _POOL:
        _POOL.clear()
        _POOL[pid] = ThreadPoolExecutor(max_workers=_cpus(), thread_name_prefix="validate-rows")
    return _POOL[pid]


def project_environment(radiance: np.ndarray, lmax: int = 2) -> np.ndarray:
    """SH coefficients ((lmax+1)², 3) of a lat-long map in Mitsuba's convention, with each texel
    weighted by its exact cell solid angle Ω_i (:func:`validate.scenes.latlong.row_solid_angles`):

        L_k = Σ_i Ω_i Σ_j L_ij Y_k(θ_i, φ_j) = Σ_i Ω_i Σ_q A[i, q, k] R[i, q],   R[i, q] = Σ_j L_ij T_q(φ_j)

    (separable form, :func:`row_basis_fourier`): the map is read once, as per-row matrix products with
    the 2·lmax+1 Fourier columns (:func:`fourier_row_sums`, polyphase, rows shared among the CPUs) — near
    the cost of a plain sum (``fourier_row_sums(radiance, 0)``, measured side by side by ``validate bench``),
    no per-texel directions or basis values, memory independent of the map beyond one block per CPU.
    Equal to the direct sum :func:`project_samples` over the same texels to float32 rounding
    (tested)."""

    h, w = radiance.shape[:2]
    rows = fourier_row_sums(radiance, lmax)
    a = row_basis_fourier(h, lmax)  # (H, q, K)
    weighted = rows.astype(np.float64) * latlong.row_solid_angles(h, w)[:, None, None]
    return np.einsum("iqc,iqk->kc", weighted, a, optimize=True)


def render_irradiance(coeffs: np.ndarray, normals: np.ndarray, lmax: int | None = None) -> np.ndarray:
    """E(n) = Σ_l A_l Σ_m L_lm Y_lm(n) [1, eq. 8] at normals (N, 3); returns (N, 3).

    On a JIT variant each A_l L_lm enters as an opaque scalar (``dr.opaque``), not a literal: a literal is
    baked into the kernel, so every new map compiled a new kernel (~0.1 s each); opaque, the kernel of a
    given (N, lmax) is compiled once and reused (the same float32 products either way)."""
    import drjit as dr

    if lmax is None:
        lmax = degree_of(coeffs.shape[0] - 1)
    x, y, z = (_to_float(normals[:, i]) for i in range(3))
    basis = eval_basis(x, y, z, lmax)
    jit = _is_jit(x)
    out = []
    for c in range(3):
        acc = x * 0.0
        for k, yk in enumerate(basis):
            a = clamped_cosine_al(degree_of(k))
            if a != 0.0 and coeffs[k, c] != 0.0:
                v = float(a * coeffs[k, c])
                acc = acc + yk * (dr.opaque(type(x), v) if jit else v)
        if jit:
            dr.eval(acc)
        out.append(np.array(acc, dtype=np.float64))
    return np.stack(out, axis=-1)


def render_irradiance_rh2001(coeffs9: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """R&H's quadratic form [1, eq. 12]:
    E(n) = c1 L22 (x² − y²) + c3 L20 z² + c4 L00 − c5 L20
           + 2 c1 (L2m2 xy + L21 xz + L2m1 yz) + 2 c2 (L11 x + L1m1 y + L10 z)."""
    import drjit as dr

    x, y, z = vec_to_dr(normals)
    # the map's numbers as opaque values (precision.constants_dr; a literal per map was a new kernel per map),
    # the products C1 L22, C3 L20, C4 L00 − C5 L20 formed in float64 as the literals were: the same float32 values
    L00, L1m1, L10, L11, L2m2, L2m1, L20, L21, L22 = np.asarray(coeffs9, dtype=np.float64)[:9, :3]
    k = constants_dr(np.stack([C1 * L22, C3 * L20, C4 * L00 - C5 * L20, L2m2, L21, L2m1, L11, L1m1, L10]))
    out = []
    for c in range(3):
        q22, q20, q00, q2m2, q21, q2m1, q11, q1m1, q10 = (k[3 * j + c] for j in range(9))
        out.append(q22 * (x * x - y * y) + q20 * z * z + q00 + 2 * C1 * (q2m2 * x * y + q21 * x * z + q2m1 * y * z)
                   + 2 * C2 * (q11 * x + q1m1 * y + q10 * z))
    dr.eval(*out)  # one kernel for the three channels
    return np.stack([np.array(e, dtype=np.float64) for e in out], axis=-1)


def angular_map_samples_rh2001(angular: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Directions, solid angles and radiance of an angular map in R&H's ``prefilter`` convention:
    pixel (row i, column j) of a w×w map has u = (j − w/2)/(w/2), v = (w/2 − i)/(w/2),
    r = √(u² + v²) ≤ 1, θ = πr, φ = atan2(v, u), direction (sin θ cos φ, sin θ sin φ, cos θ)
    (+z towards the image centre), dω = (2π/w)² sinc θ, with sinc θ = sin θ / θ.

    Note: like R&H's ``prefilter.c`` this samples at pixel *corners* (j, i), not centres (j+½, i+½);
    the half-pixel shift changes L00 by ~5e-3 relative on a 1000² map (measured in
    ``tests/local_models/test_published.py``) — well inside the ±0.01 comparison with the table."""
    w = angular.shape[0]
    i, j = np.meshgrid(np.arange(w, dtype=np.float64), np.arange(w, dtype=np.float64), indexing="ij")
    u = (j - w / 2) / (w / 2)
    v = (w / 2 - i) / (w / 2)
    r = np.sqrt(u * u + v * v)
    inside = r <= 1.0
    theta = np.pi * r[inside]
    phi = np.arctan2(v[inside], u[inside])
    d = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1)
    dw = (2 * np.pi / w) ** 2 * np.sinc(theta / np.pi)  # np.sinc(x) = sin(πx)/(πx)
    return d, dw, angular[inside].astype(np.float64)


def project_angular_rh2001(angular: np.ndarray, lmax: int = 2) -> np.ndarray:
    """SH coefficients of an angular map in R&H's prefilter convention (comparable with their table)."""
    d, dw, rad = angular_map_samples_rh2001(angular)
    return project_samples(d, dw, rad, lmax)
