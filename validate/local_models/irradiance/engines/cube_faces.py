"""Cube faces for the engines, rendered from the same radiance function the reference integrates.

The reference integrates Mitsuba's envmap radiance: bilinear in (φ, θ) between the lat-long samples
(:mod:`validate.scenes.latlong`). Each cube texel here holds that function's *average over the
texel's solid angle*, L_texel = ∫_texel L dω / Ω_texel, so that a face carries the map's flux and a
sun keeps its energy whatever the face size. The map is split as L = L₀ + D:

* D is the bilinear radiance of the *hot* texels alone (each brighter than 50 × the mean radiance
  Φ_Y/4π: a sun, a lamp, a bright zenith row): every bilinear patch it touches gets a g × g
  Gauss–Legendre rule (weights Δθ Δφ w_a w_b sin θ; g ∈ [4, 16], two nodes per cube texel across a
  lat-long row), each node's flux D w goes to the cube texel its direction falls in, and the texel
  gains that flux over its exact solid angle Ω_texel — exact to ~10⁻⁶ of the flux.
* L₀ (the map with the hot texels zeroed) is smooth enough for a midpoint rule: s × s sub-texel points
  on the face plane, weighted by dω/dA = r⁻³, L₀_texel = Σ L₀(ω_k) r_k⁻³ / Σ r_k⁻³, with s such that the
  sub-texel spacing is no wider than the lat-long row spacing π/(H − 1) (2 ≤ s ≤ 4).

The face flux Σ L_texel Ω_texel is measured against the map's (:func:`face_flux`) and reported beside
every result.

Layout: faces +X, −X, +Y, −Y, +Z, −Z; texel (row i, column j) of an N × N face is centred at
s = (j + ½)/N, t = (i + ½)/N of OpenGL's cube-map selection table [1, Table 8.19]
(:func:`validate.local_models.irradiance.irradiance_map.face_direction`). Both engines read faces in exactly this
layout: three.js's ``LightProbeGenerator.fromCubeRenderTarget`` (WebGL readback rows, bottom-up) and
Babylon.js's ``CubeMapToSphericalPolynomialTools._FileFaces`` (right, left, up, down, front, back) —
checked texel by texel in ``tests/experiments/test_engines.py``.

References
  [1] M. Segal, K. Akeley, "The OpenGL Graphics System: A Specification (4.6 Core)", §8.13, Table 8.19.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ....errors import ValidateError
from ....geometry import cube_texel_directions, cube_texel_solid_angles, face_coords, face_direction
from ....scenes import latlong
from .. import sh as shm

MAX_SUPERSAMPLE = 4
HOT_CONTRAST = 50.0  # a texel brighter than 50 × the mean radiance Φ_Y/4π is splatted exactly
MAX_HOT = 16384  # at most this many hot texels (those holding the most flux)
MIN_HOT_NODES, MAX_HOT_NODES = 4, 16  # Gauss–Legendre nodes per patch axis for the hot part


def supersample_for(height: int, face_size: int) -> int:
    """Sub-texel points per axis for L₀: ⌈(2/N) / (π/(H − 1))⌉ (sub-texel spacing ≤ the lat-long row
    spacing), clipped to [2, 4]."""
    s = math.ceil((2.0 / face_size) / (math.pi / max(height - 1, 1)))
    return int(min(max(s, 2), MAX_SUPERSAMPLE))


ROW_BLOCK_TEXELS = 1 << 20  # texels per row block when scanning the map (no full-size float64 temporaries)


def _row_blocks(height: int, width: int) -> range:
    return range(0, height, max(1, ROW_BLOCK_TEXELS // max(width, 1)))


def hot_texels(radiance: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rows, cols) of the texels brighter than ``HOT_CONTRAST`` × the mean radiance Φ_Y/4π (at most
    ``MAX_HOT``, those holding the most flux), in row-major order; two passes over row blocks."""
    h, w = radiance.shape[:2]
    omega = latlong.row_solid_angles(h, w)
    step = max(1, ROW_BLOCK_TEXELS // max(w, 1))
    total = sum(float(latlong.luminance(np.asarray(radiance[s:s + step], dtype=np.float64)).sum(axis=1)
                      @ omega[s:s + step]) for s in _row_blocks(h, w))
    limit = HOT_CONTRAST * total / (4.0 * np.pi)
    idx, flux = [], []
    for s in _row_blocks(h, w):
        y = latlong.luminance(np.asarray(radiance[s:s + step], dtype=np.float64))
        k = np.flatnonzero(y.ravel() > limit)
        idx.append(k + s * w)
        flux.append(y.ravel()[k] * omega[s + k // w])
    idx_all, flux_all = np.concatenate(idx), np.concatenate(flux)
    if len(idx_all) > MAX_HOT:
        idx_all = np.sort(idx_all[np.argsort(flux_all)[::-1][:MAX_HOT]])
    return np.unravel_index(idx_all, (h, w))


def hot_nodes_for(height: int, face_size: int) -> int:
    """Gauss nodes per patch axis for the hot part: two per cube texel across a lat-long row spacing,
    ⌈2 · (π/(H − 1)) / (2/N)⌉, clipped to [4, 16]."""
    g = math.ceil(2.0 * (math.pi / max(height - 1, 1)) / (2.0 / face_size))
    return int(min(max(g, MIN_HOT_NODES), MAX_HOT_NODES))


@functools.lru_cache(maxsize=8)
def _sampling_plan(h: int, w: int, n: int, s: int) -> tuple[np.ndarray, ...]:
    """Bilinear taps of every sub-texel point (the arithmetic of :func:`latlong.bilinear_lookup`) and its
    weight r⁻³ / Σ r⁻³ within its texel; depends only on the sizes, so it is computed once per run."""
    sub = (np.arange(n * s, dtype=np.float64) + 0.5) / (n * s) * 2.0 - 1.0
    tc, sc = np.meshgrid(sub, sub, indexing="ij")
    wt = (1.0 + sc * sc + tc * tc) ** -1.5  # dω/dA on the face plane
    wt = wt / np.repeat(np.repeat(wt.reshape(n, s, n, s).sum(axis=(1, 3)), s, 0), s, 1)
    d = np.stack([face_direction(f, sc, tc) for f in range(6)])
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    theta, phi = latlong.direction_to_spherical(d)
    taps = latlong.bilinear_taps(theta, phi, h, w)
    return tuple(a for idx, wb in taps for a in (idx.ravel(), (wb * wt[None]).ravel()))


def _supersampled(radiance: np.ndarray, n: int, s: int, hot: np.ndarray | None = None) -> np.ndarray:
    """Σ_k L₀(ω_k) r_k⁻³ / Σ_k r_k⁻³ over the s × s sub-texel points of each texel, (6, N, N, 3), where L₀ is
    the map with the texels of flat index ``hot`` (sorted) zeroed — read through the taps, never modified.

    Channel by channel (gathered from the map in place into contiguous planes, one scratch product reused): the
    same products L·w in float64, added tap after tap as the (M, 3) form did, without its strided gathers and
    temporaries (bit-identical; about 30 % less CPU)."""
    h, w = radiance.shape[:2]
    plan = _sampling_plan(h, w, n, s)
    flat = radiance.reshape(-1, 3)
    planes = [flat[:, c] for c in range(3)]  # views: the map is not copied
    m = 6 * n * s * n * s
    acc = [np.zeros(m) for _ in range(3)]
    product = np.empty(m)
    for idx, wb in zip(plan[0::2], plan[1::2], strict=True):
        wk = wb if hot is None or len(hot) == 0 else np.where(_is_hot(idx, hot), 0.0, wb)
        for c in range(3):
            np.multiply(planes[c][idx], wk, out=product)
            acc[c] += product
    return np.stack(acc, axis=-1).reshape(6, n, s, n, s, 3).sum(axis=(2, 4))


def _only_hot_lit(radiance: np.ndarray, hot: np.ndarray) -> bool:
    """Whether every non-zero texel is hot, scanned by row blocks (no full-size temporaries: a map is lit almost
    everywhere, and its lit-texel indices would be 8 bytes a texel); stops at the first block with more lit texels
    than there are hot ones."""
    h, w = radiance.shape[:2]
    step = max(1, ROW_BLOCK_TEXELS // max(w, 1))
    for s in _row_blocks(h, w):
        lit = np.flatnonzero(np.any(radiance[s:s + step] != 0.0, axis=-1).ravel())
        if len(lit) > len(hot) or not np.all(_is_hot(lit + s * w, hot)):
            return False
    return True


def _is_hot(idx: np.ndarray, hot: np.ndarray) -> np.ndarray:
    """Whether each flat texel index is in the sorted array ``hot``."""
    pos = np.minimum(np.searchsorted(hot, idx), len(hot) - 1)
    return hot[pos] == idx


def _hot_values(radiance: np.ndarray, hot: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """D(i, j): the map's radiance at texel (i, j) if it is hot, else 0 (float64, (..., 3))."""
    idx = i * radiance.shape[1] + j
    return np.asarray(radiance.reshape(-1, 3)[idx], dtype=np.float64) * _is_hot(idx, hot)[..., None]


def _splat_hot(radiance: np.ndarray, rows: np.ndarray, cols: np.ndarray, n: int, g: int) -> np.ndarray:
    """Flux of the bilinear function D (the map at the hot texels ``rows, cols``, zero elsewhere) per cube texel."""
    h, w = radiance.shape[:2]
    hot = np.sort(rows.astype(np.int64) * w + cols)
    pi = np.concatenate([rows - 1, rows - 1, rows, rows])
    pj = np.concatenate([cols - 1, cols, cols - 1, cols]) % w
    keep = (pi >= 0) & (pi < h - 1)
    patches = np.unique(np.stack([pi[keep], pj[keep]], axis=1), axis=0)
    flux = np.zeros((6 * n * n, 3))
    if len(patches) == 0:
        return flux
    i, j = patches[:, 0], patches[:, 1]
    j1 = (j + 1) % w
    xg, wg = np.polynomial.legendre.leggauss(g)
    xg, wg = (xg + 1.0) / 2.0, wg / 2.0
    a, b = np.meshgrid(xg, xg, indexing="ij")
    wab = np.outer(wg, wg)
    dth, dph = math.pi / (h - 1), 2.0 * math.pi / w
    theta = latlong.row_theta(h)[i][:, None, None] + a * dth
    phi = latlong.col_phi(w)[j][:, None, None] + b * dph
    a, b = a[None, ..., None], b[None, ..., None]
    def d(ii: np.ndarray, jj: np.ndarray) -> np.ndarray:
        return _hot_values(radiance, hot, ii, jj)[:, None, None]

    lv = ((1 - a) * (1 - b) * d(i, j) + (1 - a) * b * d(i, j1) + a * (1 - b) * d(i + 1, j) + a * b * d(i + 1, j1))
    weight = dth * dph * wab[None] * np.sin(theta)
    face, x, y = face_coords(latlong.spherical_to_direction(theta, phi), n)
    idx = (face * n + np.clip(np.floor(y), 0, n - 1).astype(np.int64)) * n + np.clip(np.floor(x), 0, n - 1).astype(
        np.int64)
    for c in range(3):
        flux[:, c] = np.bincount(idx.ravel(), (lv[..., c] * weight).ravel(), 6 * n * n)
    return flux


def render_faces(radiance: np.ndarray, face_size: int, supersample: int | None = None) -> np.ndarray:
    """Texel-averaged radiance of the six faces, (6, N, N, 3) float32 (see the module docstring)."""
    if radiance.ndim != 3 or radiance.shape[2] != 3 or radiance.shape[0] < 2:
        raise ValidateError(f"cube faces: radiance must be an (H ≥ 2, W, 3) lat-long map, got {radiance.shape}")
    if not 1 <= face_size <= 4096:
        raise ValidateError(f"cube faces: face size {face_size} outside [1, 4096]")
    n, h, w = face_size, radiance.shape[0], radiance.shape[1]
    rows, cols = hot_texels(radiance)
    hot = np.sort(rows.astype(np.int64) * w + cols)
    if len(hot) and _only_hot_lit(radiance, hot):  # L₀ = 0 (a few suns, nothing else)
        faces = np.zeros((6, n, n, 3))
    else:
        faces = _supersampled(radiance, n, supersample or supersample_for(h, n), hot)
    if len(rows):
        flux = _splat_hot(radiance, rows, cols, n, hot_nodes_for(h, n)).reshape(6, n, n, 3)
        faces += flux / cube_texel_solid_angles(n)[None, :, :, None]
    return faces.astype(np.float32)


def face_flux(faces: np.ndarray) -> np.ndarray:
    """Φ = Σ L_texel Ω_texel per channel (exact texel solid angles), (3,)."""
    omega = cube_texel_solid_angles(faces.shape[1])
    return np.einsum("fijc,ij->c", faces.astype(np.float64), omega)


def project_faces_sh9(faces: np.ndarray) -> np.ndarray:
    """Order-2 SH coefficients (9, 3) of the faces with exact texel solid angles, float64, in the suite's
    basis (:mod:`validate.local_models.irradiance.sh`): the engines' projection done exactly, for comparison."""
    n = faces.shape[1]
    d = cube_texel_directions(n).reshape(-1, 3)
    omega = np.broadcast_to(cube_texel_solid_angles(n), (6, n, n)).reshape(-1)
    basis = shm.eval_basis_numpy(d, 2)
    return basis.T @ (faces.reshape(-1, 3).astype(np.float64) * omega[:, None])


def render_sh9(coeffs: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """E(n) = Σ_l A_l Σ_m L_lm Y_lm(n) (R&H 2001 eq. 8) in float64, (N, 3)."""
    al = np.array([shm.clamped_cosine_al(shm.degree_of(k)) for k in range(9)])
    return shm.eval_basis_numpy(np.asarray(normals, dtype=np.float64), 2) @ (al[:, None] * coeffs[:9])


__all__ = ["render_faces", "face_flux", "project_faces_sh9", "render_sh9", "supersample_for", "hot_texels",
           "hot_nodes_for"]
