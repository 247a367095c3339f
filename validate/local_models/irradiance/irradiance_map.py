"""Diffuse irradiance maps: E(n) stored in a cube map or a lat-long map, looked up bilinearly.

    E(n) = ∫_{S²} L(ω) max(0, n·ω) dω        (irradiance; a white Lambertian surface reflects E/π) [1, eq. 1]

A map stores E at its texel directions; shading looks E up at the surface normal with bilinear
filtering [2]. The map's error against the true E is then the cost of its resolution and filtering.

Maps are built two ways:

* **Brute-force cosine convolution** (:func:`compute_irradiance_cube`, :func:`compute_irradiance_latlong`,
  the HDRShop / Miller–Hoffman "diffuse convolution" [2, 5]) straight from the lat-long texels:

      E(n) = π · Σ_k K(n·ω_k) Φ_k / Σ_k K(n·ω_k) Ω_k,     K(c) = max(0, c)

  over *environment nodes* k (:func:`environment_nodes`): texel t carries flux Φ_t = L_t Ω_t (its
  exact cell solid angle, :func:`validate.scenes.latlong.texel_solid_angles`); b × b texel blocks are
  merged into one node at the luminance-weighted centroid, except blocks holding more than
  ``hot_fraction`` of the luminance flux (a disc, the sun), whose texels stay separate nodes. Dividing
  by Σ K Ω (π = ∫ K dω) is the ratio estimator of [6]: a uniform environment comes out exact. Because
  K is *linear* in ω on either side of the terminator, merging is exact for luminance except in blocks
  the terminator cuts; with blocks of angular size β the relative error is ≈ β²/12 (β = 4° → 0.04 %).
* **From SH** (:func:`irradiance_cube_from_sh`, :func:`irradiance_latlong_from_sh`): the R&H order-2
  irradiance [1, eq. 8] rendered at the texel directions (:mod:`validate.local_models.irradiance.sh`).

The same machinery convolves any zonal (rotation-symmetric) kernel (:func:`convolve_zonal`): the Phong
lobes of :mod:`validate.local_models.specular.prefiltered_specular` and the GGX lobes of
:mod:`validate.local_models.specular.split_sum` use it too.

Conventions
  * World y-up, as Mitsuba; directions point *towards* the environment.
  * Cube maps: face order +X, −X, +Y, −Y, +Z, −Z; face selection by the major axis and the face
    coordinates (s_c, t_c, m_a) of [3, Table 8.19]:
    +X (−z, −y, x), −X (z, −y, −x), +Y (x, z, y), −Y (x, −z, −y), +Z (x, −y, z), −Z (−x, −y, −z);
    s = (s_c/|m_a| + 1)/2, t = (t_c/|m_a| + 1)/2; texel (row i, column j) of an N × N face is centred at
    s = (j + ½)/N, t = (i + ½)/N. Arrays are (6, N, N, 3).
  * Lat-long maps: Mitsuba's envmap convention (:mod:`validate.scenes.latlong`): H rows at
    θ_i = iπ/(H − 1), W = 2H columns at φ_j = 2π(j + ½)/W; bilinear in (φ, θ), φ wraps.
  * Cube-face seams [4]: each face is padded by one texel from its neighbours: the neighbouring
    face's bilinear value at the padding texel's direction on the extended face plane. A padding corner
    is extrapolated linearly, a + b − c, from its two edge neighbours a, b and the face's corner texel
    c. Bilinear filtering inside the padded face then blends across edges and corners without special
    cases, and stays second-order accurate: on a smooth test function the corner error at N = 32 is
    4.9·10⁻⁴ against 2.2·10⁻³ when a corner is the mean of the three corner texels (what seamless
    hardware filtering does; first order) — see ``tests/local_models/test_ibl.py``.
  * *Sparse maps*: ``needed=`` directions restrict the (expensive) convolution to the texels the
    bilinear lookups of those directions read; every other texel is NaN, so a lookup outside the
    declared footprint shows up as NaN instead of a silently wrong value.

References
  [1] R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
      SIGGRAPH 2001.
  [2] G. Miller, C. R. Hoffman, "Illumination and Reflection Maps: Simulated Objects in Simulated and
      Real Environments", SIGGRAPH 1984 course notes (diffuse and specular prefiltered maps).
  [3] M. Segal, K. Akeley, "The OpenGL Graphics System: A Specification (4.6 Core)", §8.13
      "Cube Map Texture Selection", Table 8.19.
  [4] ARB_seamless_cube_map (OpenGL 3.2 core): filtering across cube-map faces.
  [5] P. Debevec et al., HDRShop 2.0, "Diffuse / specular convolution" (the maps the seed shader reads).
  [6] B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes (prefiltering as a
      normalised weighted average: Σ L w / Σ w).
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from ...errors import ValidateError
from ...geometry import cube_texel_directions, face_coords, face_direction
from ...scenes import latlong
from ..precision import acos, constants_dr, float_type, to_dr, to_np, uint_type, vec_to_dr
from .sh import render_irradiance

MIN_FACE, MAX_FACE = 1, 4096
DEFAULT_BLOCK_DEG = 4.0  # node block size for the cosine kernel: merging error ≈ β²/12 = 0.04 %
HOT_FRACTION = 1e-3  # blocks above this share of the luminance flux keep their texels as nodes
CHUNK_PAIRS = 1 << 23  # (directions × nodes) per dense block: 32 MiB of float32
# (directions × nodes) per slice the kernel is applied to in place: 1 MiB of float32, so its buffers stay in the
# L2 cache. Elementwise, so the slicing changes no bit; the products keep the CHUNK_PAIRS blocks (BLAS sums a row
# in an order that depends on the block's shape, so a smaller block changes the last bits)
KERNEL_PAIRS = 1 << 18

Kernel = Callable[[np.ndarray], np.ndarray]


# ---------------------------------------------------------------------------------------------
# Environment nodes and zonal convolution
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class EnvironmentNodes:
    """Quadrature nodes of an environment: flux Φ (M, 3), solid angle Ω (M,), direction ω (M, 3)."""

    flux: np.ndarray
    solid_angle: np.ndarray
    direction: np.ndarray
    block: int  # texels per block side

    @property
    def count(self) -> int:
        return int(self.flux.shape[0])


def _check_radiance(radiance: np.ndarray) -> np.ndarray:
    r = np.asarray(radiance)
    if r.ndim != 3 or r.shape[2] != 3 or r.shape[0] < 2 or r.shape[1] != 2 * r.shape[0]:
        raise ValidateError(f"environment radiance of shape {r.shape}: expected a lat-long (H, 2H, 3) map")
    return r


NODE_CHUNK_TEXELS = 1 << 20  # texels per chunk of whole block rows in :func:`environment_nodes`


@dataclass(frozen=True)
class _Chunk:
    """One chunk of whole node-block rows: texel flux, solid angle, direction, luminance flux, block ids."""

    flux: np.ndarray
    omega: np.ndarray
    dirs: np.ndarray
    y: np.ndarray
    gid: np.ndarray  # block index of every texel, local to the chunk
    first_block: int  # global index of the chunk's first block
    blocks: int  # blocks in the chunk


def _chunks(rad: np.ndarray, b: int) -> Iterator[_Chunk]:
    """The map in chunks of whole rows of b × b blocks (float64 only per chunk: memory set by
    :data:`NODE_CHUNK_TEXELS`, not by the map); every block lies in one chunk, its texels in row-major order."""
    h, w = rad.shape[:2]
    nbc = -(-w // b)
    rows = b * max(1, NODE_CHUNK_TEXELS // (b * w))
    omega_rows, theta, phi = latlong.row_solid_angles(h, w), latlong.row_theta(h), latlong.col_phi(w)
    for r0 in range(0, h, rows):
        r1 = min(r0 + rows, h)
        omega = np.broadcast_to(omega_rows[r0:r1, None], (r1 - r0, w))
        dirs = latlong.spherical_to_direction(*np.meshgrid(theta[r0:r1], phi, indexing="ij"))
        flux = np.asarray(rad[r0:r1], dtype=np.float64) * omega[..., None]
        gid = (((np.arange(r0, r1) - r0) // b)[:, None] * nbc + (np.arange(w) // b)[None, :]).ravel()
        yield _Chunk(flux, omega, dirs, latlong.luminance(flux), gid, (r0 // b) * nbc, -(-(r1 - r0) // b) * nbc)


def environment_nodes(radiance: np.ndarray, block_deg: float = DEFAULT_BLOCK_DEG,
                      hot_fraction: float = HOT_FRACTION) -> EnvironmentNodes:
    """Nodes of a lat-long map (Mitsuba convention): b × b texel blocks, b = round(block_deg / Δθ)
    (Δθ = 180°/(H − 1)), each at its luminance-weighted centroid (geometric centroid if black); the
    texels of blocks above ``hot_fraction`` of the luminance flux stay separate nodes.

    Two passes over chunks of whole block rows (:func:`_chunks`): block sums, then the hot blocks' texels —
    the same sums in the same order as one pass over the whole map, without full-size float64 arrays."""
    if not block_deg > 0 or not 0 < hot_fraction < 1:
        raise ValidateError(f"environment_nodes: block_deg={block_deg}, hot_fraction={hot_fraction}: "
                            "expected block_deg > 0 and 0 < hot_fraction < 1")
    rad = _check_radiance(radiance)
    h, w = rad.shape[:2]
    b = max(1, int(round(block_deg / (180.0 / (h - 1)))))
    nb = -(-h // b) * -(-w // b)
    b_flux, b_omega, b_y = np.zeros((nb, 3)), np.zeros(nb), np.zeros(nb)
    cen_y, cen_g = np.zeros((nb, 3)), np.zeros((nb, 3))
    for ch in _chunks(rad, b):
        sl = slice(ch.first_block, ch.first_block + ch.blocks)

        def bsum(v: np.ndarray, ch: _Chunk = ch) -> np.ndarray:
            return np.bincount(ch.gid, weights=v.ravel(), minlength=ch.blocks)

        b_flux[sl] = np.stack([bsum(ch.flux[..., c]) for c in range(3)], axis=-1)
        b_omega[sl], b_y[sl] = bsum(ch.omega), bsum(ch.y)
        cen_y[sl] = np.stack([bsum(ch.y * ch.dirs[..., k]) for k in range(3)], axis=-1)
        cen_g[sl] = np.stack([bsum(ch.omega * ch.dirs[..., k]) for k in range(3)], axis=-1)
    cen = np.where((b_y > 0)[:, None], cen_y, cen_g)
    cen /= np.maximum(np.linalg.norm(cen, axis=-1, keepdims=True), 1e-300)
    total = b_y.sum()
    hot = b_y > hot_fraction * total if (b > 1 and total > 0) else np.zeros(nb, dtype=bool)
    keep = ~hot
    hot_flux, hot_omega, hot_dirs = [np.zeros((0, 3))], [np.zeros(0)], [np.zeros((0, 3))]
    if hot.any():
        for ch in _chunks(rad, b):
            texel_hot = hot[ch.first_block + ch.gid]
            if texel_hot.any():
                hot_flux.append(ch.flux.reshape(-1, 3)[texel_hot])
                hot_omega.append(ch.omega.ravel()[texel_hot])
                hot_dirs.append(ch.dirs.reshape(-1, 3)[texel_hot])
    flux_out = np.concatenate([b_flux[keep], *hot_flux])
    omega_out = np.concatenate([b_omega[keep], *hot_omega])
    dir_out = np.concatenate([cen[keep], *hot_dirs])
    return EnvironmentNodes(flux_out, omega_out, dir_out, b)


def cosine_kernel(c: np.ndarray) -> np.ndarray:
    """K(c) = max(0, c): the clamped cosine of Lambertian irradiance (∫ K dω = π)."""
    return np.maximum(c, 0.0)


def _spatial_batches(dirs: np.ndarray, cells: int) -> list[np.ndarray]:
    """Index sets of ``dirs`` grouped by a cells × cells grid on each cube face (nearby directions)."""
    face, x, y = face_coords(dirs, cells)
    key = (face * cells + np.clip(y.astype(np.int64), 0, cells - 1)) * cells + np.clip(x.astype(np.int64), 0,
                                                                                       cells - 1)
    order = np.argsort(key, kind="stable")
    ks = key[order]
    cuts = np.flatnonzero(np.diff(ks)) + 1
    return np.split(order, cuts)


def _cosines(d: np.ndarray, nd: np.ndarray) -> np.ndarray:
    """d (B, 3) @ nd (K, 3)ᵀ in float32 on one BLAS thread for this thread
    (:class:`validate.numerics.blas.one_blas_thread`, thread-local): a few thousand three-term products per row,
    where waking the threads costs more CPU than the product (×6 in the cap path, measured). The same bits as the
    threaded product (each entry is one three-term sum)."""
    from ...numerics.blas import one_blas_thread

    with one_blas_thread():
        return d @ nd.T


def convolve_zonal(nodes: EnvironmentNodes, dirs: np.ndarray, kernel: Kernel, kernel_integral: float = 1.0,
                   support_cos: float = -1.0) -> np.ndarray:
    """V(r) = C · Σ_k K(r·ω_k) Φ_k / Σ_k K(r·ω_k) Ω_k at unit directions ``dirs`` (N, 3) → (N, 3).

    C = ∫ K dω (π for the clamped cosine, 1 for a normalised lobe): the ratio estimator [6] of
    ∫ L(ω) K(r·ω) dω. K must vanish for r·ω < ``support_cos``; when the support is a small cap, only
    nodes within it (plus the batch's own angular radius) are visited (scipy cKDTree on the sphere).
    """
    dirs = np.asarray(dirs, dtype=np.float64).reshape(-1, 3)
    out = np.full((dirs.shape[0], 3), np.nan)
    if dirs.shape[0] == 0:
        return out
    cap_fraction = (1.0 - support_cos) / 2.0
    if support_cos <= -1.0 or cap_fraction > 0.25:
        return convolve_zonal_dense_many(nodes, dirs, lambda c: [kernel(c)], [kernel_integral])[0]
    nd = nodes.direction.astype(np.float32)
    fo32 = np.concatenate([nodes.flux, nodes.solid_angle[:, None]], axis=1).astype(np.float32)  # (M, 4)
    from scipy.spatial import cKDTree

    tree = cKDTree(nodes.direction)
    support = float(np.arccos(np.clip(support_cos, -1.0, 1.0)))
    # batches of directions about half the support across, so a batch's candidate cap stays ≈ 2× the support
    cells = int(np.clip(np.ceil(np.pi / max(support, 1e-3)), 1, 64))
    for idx in _spatial_batches(dirs, cells):
        d = dirs[idx]
        centre = d.sum(axis=0)
        centre /= np.linalg.norm(centre)
        radius = float(np.arccos(np.clip((d @ centre).min(), -1.0, 1.0)))
        ang = min(np.pi, radius + support)
        cand = np.asarray(tree.query_ball_point(centre, 2.0 * np.sin(ang / 2.0) + 1e-9), dtype=np.int64)
        if cand.size == 0:
            continue
        c = _cosines(d.astype(np.float32), nd[cand])
        acc = (kernel(c).astype(np.float32, copy=False) @ fo32[cand]).astype(np.float64)
        out[idx] = kernel_integral * acc[:, :3] / np.maximum(acc[:, 3:], 1e-300)
    return out


def convolve_zonal_dense_many(nodes: EnvironmentNodes, dirs: np.ndarray,
                              kernels: Callable[[np.ndarray], list[np.ndarray]],
                              kernel_integrals: list[float]) -> list[np.ndarray]:
    """[V_j(r)] = [C_j · Σ_k K_j(r·ω_k) Φ_k / Σ_k K_j(r·ω_k) Ω_k] for several kernels at once (the dense path of
    :func:`convolve_zonal`, whole-sphere support, is this with one kernel): ``kernels(c)`` returns every K_j at
    the cosines ``c``, so they can share intermediate values (powers of c). The cosine blocks are computed once
    for all kernels; each kernel's values are stored in float32 and summed by one float32 product with (Φ, Ω),
    so each V_j has the bits of ``convolve_zonal(nodes, dirs, K_j, C_j)``."""
    dirs = np.asarray(dirs, dtype=np.float64).reshape(-1, 3)
    outs = [np.full((dirs.shape[0], 3), np.nan) for _ in kernel_integrals]
    if dirs.shape[0] == 0:
        return outs
    nd = nodes.direction.astype(np.float32)
    fo32 = np.concatenate([nodes.flux, nodes.solid_angle[:, None]], axis=1).astype(np.float32)  # (M, 4)
    chunk = max(1, CHUNK_PAIRS // max(1, nodes.count))
    rows = max(1, KERNEL_PAIRS // max(1, nodes.count))
    for s in range(0, dirs.shape[0], chunk):
        c = _cosines(dirs[s:s + chunk].astype(np.float32), nd)
        ks = [np.empty_like(c) for _ in kernel_integrals]
        for r in range(0, c.shape[0], rows):
            for kj, v in zip(ks, kernels(c[r:r + rows]), strict=True):
                kj[r:r + rows] = v
        for out, kj, ci in zip(outs, ks, kernel_integrals, strict=True):
            acc = (kj @ fo32).astype(np.float64)
            out[s:s + chunk] = ci * acc[:, :3] / np.maximum(acc[:, 3:], 1e-300)
    return outs


def convolve_cosine(nodes: EnvironmentNodes, normals: np.ndarray) -> np.ndarray:
    """E(n) = π Σ max(0, n·ω_k) Φ_k / Σ max(0, n·ω_k) Ω_k at ``normals`` (N, 3) → (N, 3)."""
    return convolve_zonal(nodes, normals, cosine_kernel, np.pi)


def _check_face(n: int) -> int:
    if not isinstance(n, (int, np.integer)) or not MIN_FACE <= n <= MAX_FACE:
        raise ValidateError(f"cube face size {n!r}: expected an integer in [{MIN_FACE}, {MAX_FACE}]")
    return int(n)


@functools.lru_cache(maxsize=16)
def padding_table(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Sources of the padded faces (6, N+2, N+2): four flat texel indices into the (6·N·N) texels and
    their weights. Interior texels are themselves; an edge padding texel is the bilinear interpolation,
    on the neighbouring face, at the padding texel's direction on the extended face plane (clamped to
    that face's texel centres). Corner padding texels have zero weights here: :func:`_pad` sets them."""
    p = n + 2
    src = np.zeros((6, p, p, 4), dtype=np.int64)
    wts = np.zeros((6, p, p, 4), dtype=np.float64)
    f, py, px = np.meshgrid(np.arange(6), np.arange(p), np.arange(p), indexing="ij")
    iy, ix = py - 1, px - 1
    inside_y, inside_x = (iy >= 0) & (iy < n), (ix >= 0) & (ix < n)
    m = inside_y & inside_x
    src[m, 0] = (f[m] * n + iy[m]) * n + ix[m]
    wts[m, 0] = 1.0
    e = inside_y ^ inside_x
    sc = (ix[e] + 0.5) / n * 2.0 - 1.0
    tc = (iy[e] + 0.5) / n * 2.0 - 1.0
    g, gx, gy = face_coords(face_direction(f[e], sc, tc), n)
    gx, gy = np.clip(gx, 0.0, n - 1.0), np.clip(gy, 0.0, n - 1.0)
    x0 = np.minimum(np.floor(gx).astype(np.int64), max(n - 2, 0))
    y0 = np.minimum(np.floor(gy).astype(np.int64), max(n - 2, 0))
    x1, y1 = np.minimum(x0 + 1, n - 1), np.minimum(y0 + 1, n - 1)
    wx, wy = gx - x0, gy - y0
    for k, (yy, xx, ww) in enumerate([(y0, x0, (1 - wx) * (1 - wy)), (y0, x1, wx * (1 - wy)),
                                      (y1, x0, (1 - wx) * wy), (y1, x1, wx * wy)]):
        src[e, k] = (g * n + yy) * n + xx
        wts[e, k] = ww
    return src, wts


def _corner_neighbours(n: int) -> list[tuple[tuple[int, int], tuple[int, int], tuple[int, int]]]:
    """For each padded corner (py, px): its two edge padding neighbours and the face's own corner texel."""
    last = n + 1
    out = []
    for cy, ny in ((0, 1), (last, n)):
        for cx, nx in ((0, 1), (last, n)):
            out.append(((cy, cx), (cy, nx), (ny, cx)))
    return out


def _pad(faces: np.ndarray) -> np.ndarray:
    """Padded faces (6, N+2, N+2, C): interior, edges from the neighbours (:func:`padding_table`), and
    each corner = a + b − c from its two edge neighbours a, b (which come from the two adjacent faces)
    and the face's own corner texel c: linear extrapolation, exact for a function linear in the face
    coordinates (module docstring)."""
    n = faces.shape[1]
    src, wts = padding_table(n)
    flat = faces.reshape(-1, faces.shape[-1])
    vals = np.where((wts > 0)[..., None], flat[src], 0.0)  # a zero weight must not pull in a NaN
    out = np.einsum("fyxk,fyxkc->fyxc", wts, vals)
    for (cy, cx), (ay, ax), (by, bx) in _corner_neighbours(n):
        out[:, cy, cx] = out[:, ay, ax] + out[:, by, bx] - out[:, by, ax]
    return out


def _bilinear_taps(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Padded-face integer corner (x0 + 1, y0 + 1) and fractions of continuous texel coords."""
    x0, y0 = np.floor(x), np.floor(y)
    return x0.astype(np.int64) + 1, y0.astype(np.int64) + 1, x - x0, y - y0


# ---------------------------------------------------------------------------------------------
# Maps
# ---------------------------------------------------------------------------------------------

@dataclass
class CubeMap:
    """A cube map (6, N, N, C) in the convention of the module docstring; NaN marks unevaluated texels."""

    faces: np.ndarray

    def __post_init__(self) -> None:
        f = self.faces
        if f.ndim != 4 or f.shape[0] != 6 or f.shape[1] != f.shape[2]:
            raise ValidateError(f"cube map of shape {f.shape}: expected (6, N, N, C)")
        self._padded: np.ndarray | None = None

    @property
    def face_size(self) -> int:
        return int(self.faces.shape[1])

    @property
    def texel_count(self) -> int:
        return int(np.prod(self.faces.shape[:3]))

    @property
    def padded(self) -> np.ndarray:
        """(6, N+2, N+2, C): each face with its one-texel border from the neighbours (seams, [4])."""
        if self._padded is None:
            self._padded = _pad(self.faces.astype(np.float64)).astype(np.float32)
        return self._padded

    @staticmethod
    def footprint(n: int, dirs: np.ndarray) -> np.ndarray:
        """Boolean (6, N, N): the texels that bilinear lookups of ``dirs`` read (through the padding)."""
        n = _check_face(n)
        face, x, y = face_coords(np.asarray(dirs).reshape(-1, 3), n)
        px, py, _, _ = _bilinear_taps(x, y)
        p = n + 2
        src, wts = padding_table(n)
        taps = np.zeros((6, p, p), dtype=bool)
        for dy in (0, 1):
            for dx in (0, 1):
                taps[face, np.clip(py + dy, 0, p - 1), np.clip(px + dx, 0, p - 1)] = True
        for (cy, cx), (ay, ax), (by, bx) in _corner_neighbours(n):
            hit = taps[:, cy, cx]
            taps[hit, ay, ax] = taps[hit, by, bx] = taps[hit, by, ax] = True
        used = np.zeros(6 * n * n, dtype=bool)
        used[src[taps][wts[taps] > 0]] = True
        return used.reshape(6, n, n)

    @classmethod
    def build(cls, fn: Callable[[np.ndarray], np.ndarray], n: int, needed: np.ndarray | None = None,
              channels: int = 3) -> CubeMap:
        """Evaluate ``fn(dirs (K, 3)) -> (K, C)`` at the texel directions (only the footprint of
        ``needed`` directions, if given; other texels NaN)."""
        n = _check_face(n)
        dirs = cube_texel_directions(n).reshape(-1, 3)
        faces = np.full((6 * n * n, channels), np.nan, dtype=np.float32)
        mask = np.ones(6 * n * n, dtype=bool) if needed is None else cls.footprint(n, needed).ravel()
        if mask.any():
            faces[mask] = np.asarray(fn(dirs[mask]), dtype=np.float32).reshape(-1, channels)
        return cls(faces.reshape(6, n, n, channels))

    def lookup_numpy(self, dirs: np.ndarray) -> np.ndarray:
        """Bilinear lookup (numpy; the slow reference for :meth:`lookup`): (..., 3) → (..., C)."""
        d = np.asarray(dirs, dtype=np.float64)
        n, pad = self.face_size, self.padded
        face, x, y = face_coords(d, n)
        px, py, fx, fy = _bilinear_taps(x, y)
        px1, py1 = np.minimum(px + 1, n + 1), np.minimum(py + 1, n + 1)
        fx, fy = fx[..., None], fy[..., None]
        top = pad[face, py, px] * (1 - fx) + pad[face, py, px1] * fx
        bot = pad[face, py1, px] * (1 - fx) + pad[face, py1, px1] * fx
        return top * (1 - fy) + bot * fy

    def lookup(self, dirs: np.ndarray) -> np.ndarray:
        """Bilinear lookup in drjit (the model's shading path): unit-or-not directions (K, 3) → (K, C).
        Face selection and coordinates as [3, Table 8.19]; the padded faces handle the seams."""
        import drjit as dr

        Float, UInt = float_type(), uint_type()
        x, y, z = vec_to_dr(dirs)
        n = self.face_size
        p = n + 2
        ax, ay, az = dr.abs(x), dr.abs(y), dr.abs(z)
        use_x = (ax >= ay) & (ax >= az)
        use_y = ~use_x & (ay >= az)
        face = dr.select(use_x, dr.select(x >= 0, UInt(0), UInt(1)),
                         dr.select(use_y, dr.select(y >= 0, UInt(2), UInt(3)),
                                   dr.select(z >= 0, UInt(4), UInt(5))))
        sc = dr.select(use_x, dr.select(x >= 0, -z, z), dr.select(use_y, x, dr.select(z >= 0, x, -x)))
        tc = dr.select(use_x, -y, dr.select(use_y, dr.select(y >= 0, z, -z), -y))
        ma = dr.maximum(dr.select(use_x, ax, dr.select(use_y, ay, az)), 1e-30)
        # the face size as opaque values, not literals: one compiled kernel for every face size
        half_n, top = constants_dr([0.5 * n, p - 2])
        pu = UInt(p)
        dr.make_opaque(pu)
        fxc = (sc / ma + 1.0) * half_n - 0.5
        fyc = (tc / ma + 1.0) * half_n - 0.5
        x0, y0 = dr.floor(fxc), dr.floor(fyc)
        wx, wy = fxc - x0, fyc - y0
        ix = UInt(dr.clip(x0 + 1.0, 0.0, top))
        iy = UInt(dr.clip(y0 + 1.0, 0.0, top))
        base = (face * pu + iy) * pu + ix
        pad = self.padded
        out = []
        for c in range(pad.shape[-1]):
            data = to_dr(pad[..., c])
            v00 = dr.gather(Float, data, base)
            v01 = dr.gather(Float, data, base + 1)
            v10 = dr.gather(Float, data, base + pu)
            v11 = dr.gather(Float, data, base + pu + 1)
            v = dr.lerp(dr.lerp(v00, v01, wx), dr.lerp(v10, v11, wx), wy)
            out.append(to_np(v))
        return np.stack(out, axis=-1)


@dataclass
class LatLongMap:
    """A lat-long map (H, 2H, C) in Mitsuba's envmap convention; NaN marks unevaluated texels."""

    data: np.ndarray

    def __post_init__(self) -> None:
        d = self.data
        if d.ndim != 3 or d.shape[0] < 2 or d.shape[1] != 2 * d.shape[0]:
            raise ValidateError(f"lat-long map of shape {d.shape}: expected (H, 2H, C)")

    @property
    def height(self) -> int:
        return int(self.data.shape[0])

    @property
    def texel_count(self) -> int:
        return int(self.data.shape[0] * self.data.shape[1])

    @staticmethod
    def _coords(dirs: np.ndarray, h: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        w = 2 * h
        theta, phi = latlong.direction_to_spherical(np.asarray(dirs, dtype=np.float64))
        yc = theta / np.pi * (h - 1)
        xc = phi / (2 * np.pi) * w - 0.5
        y0 = np.clip(np.floor(yc).astype(np.int64), 0, h - 2)
        x0 = np.floor(xc).astype(np.int64)
        return y0, x0, np.clip(yc - y0, 0.0, 1.0), xc - x0

    @staticmethod
    def footprint(h: int, dirs: np.ndarray) -> np.ndarray:
        """Boolean (H, 2H): the texels that bilinear lookups of ``dirs`` read."""
        if h < 2:
            raise ValidateError(f"lat-long map height {h}: expected ≥ 2")
        y0, x0, _, _ = LatLongMap._coords(np.asarray(dirs).reshape(-1, 3), h)
        used = np.zeros((h, 2 * h), dtype=bool)
        for dy in (0, 1):
            for dx in (0, 1):
                used[y0 + dy, np.mod(x0 + dx, 2 * h)] = True
        return used

    @classmethod
    def build(cls, fn: Callable[[np.ndarray], np.ndarray], h: int, needed: np.ndarray | None = None,
              channels: int = 3) -> LatLongMap:
        if not isinstance(h, (int, np.integer)) or not 2 <= h <= MAX_FACE:
            raise ValidateError(f"lat-long map height {h!r}: expected an integer in [2, {MAX_FACE}]")
        dirs = latlong.texel_directions(h, 2 * h).reshape(-1, 3)
        data = np.full((h * 2 * h, channels), np.nan, dtype=np.float32)
        mask = np.ones(h * 2 * h, dtype=bool) if needed is None else cls.footprint(h, needed).ravel()
        if mask.any():
            data[mask] = np.asarray(fn(dirs[mask]), dtype=np.float32).reshape(-1, channels)
        return cls(data.reshape(h, 2 * h, channels))

    def lookup_numpy(self, dirs: np.ndarray) -> np.ndarray:
        return latlong.bilinear_lookup(self.data.astype(np.float64), np.asarray(dirs, dtype=np.float64))

    def lookup(self, dirs: np.ndarray) -> np.ndarray:
        """Bilinear lookup in drjit, bilinear in (φ, θ) with φ wrapping (Mitsuba's envmap filter)."""
        import drjit as dr

        Float, UInt = float_type(), uint_type()
        x, y, z = vec_to_dr(dirs)
        h = self.height
        w = 2 * h
        theta = acos(y)
        phi = dr.atan2(x, -z)
        phi = dr.select(phi < 0, phi + 2 * dr.pi, phi)
        yc = theta * ((h - 1) / dr.pi)
        xc = phi * (w / (2 * dr.pi)) - 0.5
        y0 = dr.clip(dr.floor(yc), 0.0, float(h - 2))
        wy = dr.clip(yc - y0, 0.0, 1.0)
        x0f = dr.floor(xc)
        wx = xc - x0f
        x0 = UInt(dr.select(x0f < 0, x0f + w, x0f))
        x0 = dr.select(x0 >= w, x0 - w, x0)
        x1 = dr.select(x0 + 1 >= w, x0 + 1 - w, x0 + 1)
        r0 = UInt(y0) * w
        out = []
        for c in range(self.data.shape[-1]):
            data = to_dr(self.data[..., c])
            v00 = dr.gather(Float, data, r0 + x0)
            v01 = dr.gather(Float, data, r0 + x1)
            v10 = dr.gather(Float, data, r0 + w + x0)
            v11 = dr.gather(Float, data, r0 + w + x1)
            v = dr.lerp(dr.lerp(v00, v01, wx), dr.lerp(v10, v11, wx), wy)
            out.append(to_np(v))
        return np.stack(out, axis=-1)


IrradianceMap = CubeMap | LatLongMap


def compute_irradiance_cube(radiance: np.ndarray, face_size: int, nodes: EnvironmentNodes | None = None,
                            needed: np.ndarray | None = None) -> CubeMap:
    """Irradiance cube map by brute-force cosine convolution of the lat-long texels (module doc)."""
    nodes = nodes if nodes is not None else environment_nodes(radiance)
    return CubeMap.build(lambda d: convolve_cosine(nodes, d), face_size, needed)


def compute_irradiance_latlong(radiance: np.ndarray, height: int, nodes: EnvironmentNodes | None = None,
                               needed: np.ndarray | None = None) -> LatLongMap:
    """Irradiance lat-long map (height H, width 2H) by brute-force cosine convolution."""
    nodes = nodes if nodes is not None else environment_nodes(radiance)
    return LatLongMap.build(lambda d: convolve_cosine(nodes, d), height, needed)


def irradiance_cube_from_sh(coeffs: np.ndarray, face_size: int) -> CubeMap:
    """Irradiance cube map from SH lighting coefficients ((l+1)², 3): E = Σ A_l L_lm Y_lm [1, eq. 8]."""

    return CubeMap.build(lambda d: render_irradiance(coeffs, d), face_size)


def irradiance_latlong_from_sh(coeffs: np.ndarray, height: int) -> LatLongMap:
    """Irradiance lat-long map from SH lighting coefficients."""

    return LatLongMap.build(lambda d: render_irradiance(coeffs, d), height)


def shade_lambert(irradiance_map: IrradianceMap, normals: np.ndarray, albedo: np.ndarray | float) -> np.ndarray:
    """Outgoing radiance of a Lambertian surface: L_o = ρ/π · E_map(n)."""
    return np.asarray(albedo, dtype=np.float64) / np.pi * irradiance_map.lookup(normals)
