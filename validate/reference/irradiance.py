"""Reference irradiance by deterministic quadrature of Mitsuba's own radiance.

    E(n) = ∫_{S²} L(ω) max(0, n·ω) dω

L is whatever Mitsuba's emitter returns (``emitter.eval``), never the local models' code.

Method
  1. Radiance nodes. Mitsuba's envmap radiance is bilinear in (φ, θ) between its texel samples
     (θ_i = iπ/(H−1), φ_j = 2π(j+½)/W; see :mod:`validate.scenes.latlong`). Every interval
     [θ_i, θ_{i+1}] × [φ_j, φ_{j+1}] gets a g × g Gauss–Legendre product rule, weights
     w = Δθ w_a sin θ_a · Δφ w_b, and ``emitter.eval`` is called at every node. On each patch the
     integrand is (bilinear) × sin θ, so ∫L dω is integrated essentially exactly (a sun confined to
     one texel keeps its energy and its position).
  2. Kernel cells. The nodes are binned into H_c × 2H_c cells uniform in θ and φ. Per cell keep
     Φ_c = Σ L w (RGB) and the luminance-weighted centroid ω_c = normalize(Σ Y(L) w ω) (the geometric
     centroid where the cell is black): with the node at the centroid the kernel's first-order
     variation across the cell cancels.
  3. Cells holding more than 10⁻³ of the total luminance flux (a sun, a small disc) are not
     collapsed: their radiance nodes are kept individually (at most 2¹⁴ of them), so a source smaller
     than a cell still sees the max(0, ·) kink of the kernel at node resolution.
  4. E(n) = Σ_c Φ_c max(0, n·ω_c), organised by cones (:func:`irradiance_at`): node clusters wholly
     above a block of normals' horizon add n·M_C (a 3 × 3 moment, float64), those wholly below add 0,
     the rest (the terminator band) a dense float32 product, node by node.

Large maps (H > :data:`TEXEL_PATH_MAX_SMALL` rows: texels ≥ 2× finer than the finest cells) take the
*texel path* instead of steps 1–3, streaming the map in row blocks so that memory stays at the map
plus a few blocks (an 8192×16384 map would need 1.7·10⁹ Gauss nodes; its 1.5 GiB map needs 2·10⁹
bytes more): every texel interval (patch) [θ_i, θ_{i+1}] × [φ_{j−1}, φ_j] of the bilinear radiance
is integrated *exactly* in closed form from its four corner texels,

    Φ_p = (Δφ/2) [I0_i (L_{i,j−1} + L_{i,j}) + I1_i (L_{i+1,j−1} + L_{i+1,j})],
    I1_i = ∫ t sin θ dθ = −cos θ_{i+1} + (sin θ_{i+1} − sin θ_i)/Δθ,  I0_i = (cos θ_i − cos θ_{i+1}) − I1_i,

(t = (θ − θ_i)/Δθ), placed at the patch centre; the patches are binned into the same cells (step 2,
fine grid; the coarse cells are its 2×2 sums) and concentrated cells are kept patch by patch (step 3).
The radiance function is Mitsuba's: the convention (bilinear in (φ, θ), θ_i = iπ/(H−1),
φ_j = 2π(j+½)/W) is checked against ``emitter.eval`` on every run (:func:`check_convention`, on a
subsampled copy of the map, 4096 directions) and a disagreement stops the run.

Steps 1–3 depend on the map alone (not on the normals): their nodes (Φ_c, ω_c) are cached by the map's digest,
H_c and g (:func:`cached_cell_nodes`, kind ``irradiance_nodes``), so the experiments that integrate the same map
(sh9, engines, ibl, the path-traced cross-check) share one evaluation of Mitsuba's emitter per grid.

Convergence is *shown*, not assumed: the quadrature runs at (H_c, g) and at (2H_c, g + 1); the
second is the reference. Its uncertainty is the largest change over all normals, per channel,
δ_c = max_n |E_fine − E_coarse|, applied to every normal: a per-normal difference can vanish by
chance where the two rules happen to agree, so it is no per-normal bound, whereas δ_c exceeds the
true error everywhere in the closed-form tests (measured error/δ ≤ 0.34).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..backend import init
from ..errors import ValidateError
from ..numerics.blas import one_blas_thread
from ..scenes import latlong
from ..scenes.environment import Environment
from ..scenes.mitsuba_eval import eval_emitter
from .cache import array_digest, cached

EVAL_CHUNK = 1 << 21  # directions per emitter.eval call (as validate.scenes.mitsuba_eval.CHUNK)
DEFAULT_CELLS = 64  # H_c of the coarse grid (the reference uses 2·H_c): converges to < 2e-4 of peak here
REFINE_FRACTION = 1e-3
MAX_REFINED_NODES = 1 << 14  # enough for a sun or a small disc (a few cells); bounds the cost
# The texel path's cells hold many more patches (8192 rows: 64×64 per fine cell, × 4 sub-nodes): a 1°
# sun spans up to 4 fine cells, which 2¹⁶ nodes cover (2¹⁴ covered one: convergence 0.053 % at 8k).
MAX_REFINED_NODES_TEXEL = 1 << 16
TEXEL_PATH_MAX_SMALL = 512  # maps with more rows take the streamed texel path (all built-ins have ≤ 512)
BLOCK_BYTES = 32 << 20  # texel-path row blocks: ~32 MiB of float64 patch data at a time
# Mitsuba evaluates in float32 (see tests/reference/test_latlong.py: measured 1.8e-6 of the values on random
# directions); a convention slip is an O(1) difference.
CONVENTION_TOL = 1e-4
Nodes = tuple[np.ndarray, np.ndarray]  # (Φ_c (M, 3), ω_c (M, 3))


@dataclass
class ReferenceIrradiance:
    """Reference E(n) (N, 3) with its per-normal quadrature uncertainty (N, 3)."""

    irradiance: np.ndarray
    uncertainty: np.ndarray
    cells: int

    @property
    def convergence(self) -> float:
        """max_n |E_fine − E_coarse| / max_n E over normals and channels (the doubling change)."""
        peak = self.irradiance.max(axis=0)
        return float(np.max(self.uncertainty.max(axis=0) / np.maximum(peak, 1e-30)))


def gauss_order(env: Environment, cells: int) -> int:
    """Gauss points per texel interval: ≥ 2, and enough that nodes are ≥ 2× as dense as cells."""
    if env.height < 2 or env.width < 1:
        raise ValidateError(f"environment {env.name!r}: {env.width}×{env.height} lat-long map is too small "
                            "to integrate (rows sit at θ_i = iπ/(H−1): H ≥ 2)")
    return max(2, int(np.ceil(2.0 * cells / (env.height - 1))))


def _grid_axes(env: Environment, g: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Step 1's product rule as its two axes: node θ (R,), node φ (C,), and their weights Δθ w_a sin θ_a (R,) and
    Δφ w_b (C,); a node's weight is the product of its row's and its column's."""
    h, w = env.height, env.width
    x, wx = np.polynomial.legendre.leggauss(g)
    x, wx = (x + 1) / 2, wx / 2  # on [0, 1]
    dth, dph = np.pi / (h - 1), 2 * np.pi / w
    th = (latlong.row_theta(h)[:-1, None] + dth * x[None, :]).reshape(-1)
    wth = (dth * wx[None, :] * np.ones((h - 1, 1))).reshape(-1) * np.sin(th)
    ph = (latlong.col_phi(w)[:, None] + dph * x[None, :]).reshape(-1)
    wph = np.full(ph.shape, 0.0) + np.tile(dph * wx, w)
    return th, ph, wth, wph


def _grid_block(th: np.ndarray, ph: np.ndarray, wth: np.ndarray, wph: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Directions (R·C, 3) and weights (R·C,) of the grid rows ``th`` × columns ``ph``, row-major: the directions
    ``latlong.spherical_to_direction(th[:, None], ph[None, :])`` written in place (the same values), as a view of
    three contiguous (R·C,) component planes. Row by row the same numbers as the whole grid's."""
    st = np.sin(th)[:, None]
    planes = np.empty((3, th.size, ph.size))
    planes[0] = np.sin(ph)[None, :] * st
    planes[1] = np.cos(th)[:, None]
    planes[2] = -np.cos(ph)[None, :] * st
    weights = (wth[:, None] * wph[None, :]).reshape(-1)
    return planes.reshape(3, -1).T, weights


def _node_grid(env: Environment, g: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Step 1's product grid: node θ (R,), node φ (C,), directions (R·C, 3) and weights (R·C,), row-major
    (the directions as a view of three contiguous (R·C,) component planes)."""
    th, ph, wth, wph = _grid_axes(env, g)
    d, weights = _grid_block(th, ph, wth, wph)
    return th, ph, d, weights


def radiance_nodes(env: Environment, g: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Directions (M, 3), solid-angle weights (M,) and Mitsuba radiance (M, 3) of step 1."""
    _, _, d, weights = _node_grid(env, g)
    return d, weights, _mitsuba_radiance(env, d)


def _mitsuba_radiance(env: Environment, d: np.ndarray) -> np.ndarray:
    import mitsuba as mi

    return eval_emitter(mi.load_dict(env.mitsuba_emitter()), d)


def _mitsuba_radiance_planes(env: Environment, d: np.ndarray, emitter: object = None) -> np.ndarray:
    """Mitsuba's radiance (3, M) float64 at directions ``d`` (M, 3), one contiguous plane per channel: the
    ``emitter.eval`` of :func:`validate.scenes.mitsuba_eval.eval_emitter` (the same float32 directions, incident
    ``si.wi = −d``, the same lanes) fed from and read into channel planes, without the (M, 3) interleaving and its
    strided passes (eval_emitter itself on a scalar variant)."""
    import drjit as dr
    import mitsuba as mi

    if emitter is None:
        emitter = mi.load_dict(env.mitsuba_emitter())
    if not init().is_vectorized:
        return np.ascontiguousarray(eval_emitter(emitter, d).T)
    planes = d.T  # (3, M)
    out = np.empty((3, planes.shape[1]))
    for s in range(0, planes.shape[1], EVAL_CHUNK):
        neg = -planes[:, s:s + EVAL_CHUNK].astype(np.float32)  # = −float32(d), as eval_emitter's −chunk[:, k]
        si = dr.zeros(mi.SurfaceInteraction3f, neg.shape[1])
        si.wi = mi.Vector3f(neg[0], neg[1], neg[2])
        out[:, s:s + EVAL_CHUNK] = np.array(emitter.eval(si)).reshape(3, -1)
    return out


def _node_cells(th: np.ndarray, ph: np.ndarray, d: np.ndarray, hc: int, wc: int) -> np.ndarray:
    """Cell index (R·C,) of every node of the grid: row ⌊θ H_c/π⌋, column ⌊φ W_c/2π⌋ with (θ, φ) as
    :func:`latlong.direction_to_spherical` gives them from the node's direction. Computed once per grid
    row / column; a row or column within 10⁻⁹ of a cell edge (Gauss point ½ on an edge, g odd) is binned
    node by node from its directions, as rounding decides it there. One (R, C) index array is formed
    (row·W_c + column, the per-row and per-column indices broadcast), then the edge rows / columns are
    overwritten node by node."""
    rows, cols = th.size, ph.size
    d3 = d.reshape(rows, cols, 3)
    theta = np.arccos(np.clip(np.cos(th), -1.0, 1.0))
    phi = np.mod(np.arctan2(np.sin(ph), np.cos(ph)), 2.0 * np.pi)
    fr, fc = theta / np.pi * hc, phi / (2 * np.pi) * wc
    row = np.minimum(fr.astype(np.int64), hc - 1)
    col = np.minimum(fc.astype(np.int64), wc - 1)
    edge_r = np.flatnonzero(np.abs(fr - np.round(fr)) < 1e-9)
    edge_c = np.flatnonzero(np.abs(fc - np.round(fc)) < 1e-9)
    cell = row[:, None] * wc + col[None, :]
    col_edge = None
    if edge_c.size:
        _, p = latlong.direction_to_spherical(d3[:, edge_c])
        col_edge = np.minimum((p / (2 * np.pi) * wc).astype(np.int64), wc - 1)  # (R, edge columns)
        cell[:, edge_c] = row[:, None] * wc + col_edge
    if edge_r.size:
        t, _ = latlong.direction_to_spherical(d3[edge_r])
        row_edge = np.minimum((t / np.pi * hc).astype(np.int64), hc - 1)  # (edge rows, C)
        col_at = np.broadcast_to(col[None, :], row_edge.shape).copy()
        if col_edge is not None:
            col_at[:, edge_c] = col_edge[edge_r]
        cell[edge_r] = row_edge * wc + col_at
    return cell.reshape(-1)


BAND_NODES = 1 << 17  # grid nodes per band of cell_nodes (1 MiB per float64 array: a band's arrays stay in cache)


def _cell_row_span(th: np.ndarray, hc: int) -> tuple[np.ndarray, np.ndarray]:
    """Per grid row, the lowest and highest cell row its nodes can be binned to (:func:`_node_cells`): ⌊θ H_c/π⌋,
    or both neighbours of the cell edge for a row within 10⁻⁹ of one (binned node by node there)."""
    theta = np.arccos(np.clip(np.cos(th), -1.0, 1.0))
    fr = theta / np.pi * hc
    row = np.minimum(fr.astype(np.int64), hc - 1)
    edge = np.abs(fr - np.round(fr)) < 1e-9
    lo = np.where(edge, np.clip(np.round(fr).astype(np.int64) - 1, 0, hc - 1), row)
    hi = np.where(edge, np.clip(np.round(fr).astype(np.int64), 0, hc - 1), row)
    return lo, hi


def _bands(th: np.ndarray, cols: int, hc: int) -> list[tuple[int, int]]:
    """Grid rows [s, e) in bands of about :data:`BAND_NODES` nodes, cut only where no cell has nodes on both sides
    (every cell row above the cut ends before every cell row below it starts), so each cell's nodes lie in one band,
    in grid order."""
    lo, hi = _cell_row_span(th, hc)
    ok = np.r_[False, np.maximum.accumulate(hi)[:-1] < np.minimum.accumulate(lo[::-1])[::-1][1:]]
    per = max(1, BAND_NODES // max(cols, 1))
    bands, s = [], 0
    for i in np.flatnonzero(ok):
        if i - s >= per:
            bands.append((s, int(i)))
            s = int(i)
    bands.append((s, th.size))
    return bands


def cell_nodes(env: Environment, cells: int, g: int) -> tuple[np.ndarray, np.ndarray]:
    """(Φ_c (M, 3), ω_c (M, 3)) of the quadrature with H_c = ``cells`` and g Gauss points (steps 1–3).

    The grid is evaluated in bands of rows (:func:`_bands`) that never split a cell: every per-cell sum is the
    same node-order sum as over the whole grid (the same bits), while a band's arrays stay in cache instead of
    ~10⁸-byte arrays mapped and page-faulted per grid. The per-node products are formed channel by channel on
    contiguous rows. Step 3's nodes are kept per band for the cells that can still qualify (luminance flux above
    :data:`REFINE_FRACTION` of the flux so far, a lower bound of the total), then chosen as over the whole grid."""
    import mitsuba as mi

    th, ph, wth, wph = _grid_axes(env, g)
    hc, wc = cells, 2 * cells
    n_cells = hc * wc
    emitter = mi.load_dict(env.mitsuba_emitter())
    flux = np.zeros((n_cells, 3))
    cen = np.zeros((n_cells, 3))
    cell_y = np.zeros(n_cells)
    counts = np.zeros(n_cells, dtype=np.int64)
    running = 0.0
    cand_cell, cand_flux, cand_dir = [], [], []
    for s, e in _bands(th, ph.size, hc):
        d, w = _grid_block(th[s:e], ph, wth[s:e], wph)
        lw_c = _mitsuba_radiance_planes(env, d, emitter)  # (3, m): L per node and channel, then Φ = L w in place
        lw_c *= w
        cell = _node_cells(th[s:e], ph, d, hc, wc)
        for c in range(3):
            flux[:, c] += np.bincount(cell, lw_c[c], n_cells)
        # Y = 0.2126 R + 0.7152 G + 0.0722 B as latlong.luminance (the same products, summed in the same order: the
        # same bits) on the contiguous channel planes instead of the strided (M, 3) columns
        y = lw_c[0] * 0.2126
        y += lw_c[1] * 0.7152
        y += lw_c[2] * 0.0722
        d_c = d.T  # (3, m): the block's contiguous planes
        b_cen = np.stack([np.bincount(cell, y * d_c[k], n_cells) for k in range(3)], axis=-1)
        b_y = np.bincount(cell, y, n_cells)
        b_counts = np.bincount(cell, None, n_cells)
        weak = (b_y <= 0) & (b_counts > 0)  # black cells: the geometric centroid (unoccupied ones are dropped)
        if weak.any():
            geo = np.stack([np.bincount(cell, w * d_c[k], n_cells) for k in range(3)], axis=-1)
            b_cen[weak] = geo[weak]
        cen += b_cen
        cell_y += b_y
        counts += b_counts
        running += float(b_y.sum())
        # a lower bound of the final test (1e-9 below: `running` is summed in another order than the total)
        maybe = (b_y > REFINE_FRACTION * running * (1 - 1e-9)) & (b_counts <= MAX_REFINED_NODES)
        if maybe.any():
            at = np.flatnonzero(maybe[cell])
            cand_cell.append(cell[at])
            cand_flux.append(lw_c.T[at])
            cand_dir.append(d[at])
    norm = np.linalg.norm(cen, axis=-1, keepdims=True)
    cen = np.divide(cen, norm, out=np.zeros_like(cen), where=norm > 0)

    # step 3: keep the radiance nodes of cells with concentrated flux
    total = cell_y.sum()
    keep = counts > 0
    extra_flux, extra_dir = [], []
    if total > 0:
        budget = MAX_REFINED_NODES
        chosen = []
        for c_idx in np.argsort(cell_y)[::-1]:
            if cell_y[c_idx] <= REFINE_FRACTION * total or counts[c_idx] > budget:
                break
            budget -= counts[c_idx]
            keep[c_idx] = False
            chosen.append(c_idx)
        if chosen:  # their nodes, cell by cell in the order chosen, each cell's in node order (one pass)
            rank = np.full(n_cells, -1, dtype=np.int64)
            rank[chosen] = np.arange(len(chosen))
            node_cell = np.concatenate(cand_cell)
            node_rank = rank[node_cell]
            sel = np.flatnonzero(node_rank >= 0)
            sel = sel[np.argsort(node_rank[sel], kind="stable")]
            extra_flux.append(np.concatenate(cand_flux)[sel])
            extra_dir.append(np.concatenate(cand_dir)[sel])
    flux_out = np.concatenate([flux[keep]] + extra_flux)
    dir_out = np.concatenate([cen[keep]] + extra_dir)
    return flux_out, dir_out


NODE_BINS = 16  # node clusters of irradiance_at: cube-map bins, NODE_BINS² per face (radius ≲ 4°)
NORMAL_BINS = 8  # normal blocks of irradiance_at: NORMAL_BINS² per face (radius ≲ 8°)
TILE_FLOATS = 1 << 18  # cosines per dense tile of irradiance_at (1 MiB of float32: stays in cache)
# the cone test's guard against rounding in the angles (radians; the cones' radii are computed in float64)
ANGLE_MARGIN = 1e-7


def _cube_bins(unit: np.ndarray, bins: int) -> np.ndarray:
    """Cube-map bin of each direction (N, 3): face (major axis and sign), then a bins × bins grid."""
    a = np.abs(unit)
    face = np.argmax(a, axis=1)
    ar = np.arange(len(unit))
    major = np.where(a[ar, face] > 0, a[ar, face], 1.0)
    iu = np.clip(((unit[ar, (face + 1) % 3] / major + 1) * (bins / 2)).astype(np.int64), 0, bins - 1)
    iv = np.clip(((unit[ar, (face + 2) % 3] / major + 1) * (bins / 2)).astype(np.int64), 0, bins - 1)
    return ((face * 2 + (unit[ar, face] < 0)) * bins + iu) * bins + iv


def _cones(unit: np.ndarray, bins: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Group unit vectors by :func:`_cube_bins`: (order, group starts in ``order``, axes (G, 3), radii (G,)):
    axis = normalised mean direction, radius = the largest angle from it to a member (float64)."""
    b = _cube_bins(unit, bins)
    order = np.argsort(b, kind="stable")
    sb = b[order]
    starts = np.flatnonzero(np.r_[True, sb[1:] != sb[:-1]])
    u = unit[order]
    s = np.add.reduceat(u, starts, axis=0)
    norm = np.linalg.norm(s, axis=1, keepdims=True)
    axes = s / np.where(norm > 0, norm, 1.0)
    cos = np.einsum("ij,ij->i", u, np.repeat(axes, np.diff(np.r_[starts, len(u)]), axis=0))
    radii = np.arccos(np.clip(np.minimum.reduceat(cos, starts), -1.0, 1.0))
    radii[norm[:, 0] <= 0] = np.pi
    return order, starts, axes, radii


def _unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(v/|v| with 0 where |v| is 0 or not finite, valid mask)."""
    norm = np.linalg.norm(v, axis=1)
    ok = np.isfinite(norm) & (norm > 0)
    return np.where(ok[:, None], v / np.where(ok, norm, 1.0)[:, None], 0.0), ok


def irradiance_at(flux: np.ndarray, nodes: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """E(n) = Σ_c Φ_c max(0, n·ω_c) (step 4), the same sum organised by cones.

    The nodes are grouped into cube-map clusters C (:data:`NODE_BINS`) and the normals into blocks B
    (:data:`NORMAL_BINS`), each bounded by a cone (axis, radius r_C or s_B). With γ the angle between the
    axes, every n ∈ B and ω ∈ C have angle(n, ω) ∈ [γ − r_C − s_B, γ + r_C + s_B] (triangle inequality), so

    * γ + r_C + s_B < π/2: n·ω > 0 for the whole pair, and Σ_{c∈C} Φ_c max(0, n·ω_c) = n · M_C with the
      3 × 3 moment M_C = Σ_{c∈C} ω_c Φ_cᵀ (float64), summed over such clusters per block;
    * γ − r_C − s_B > π/2: n·ω < 0, the pair contributes exactly 0;
    * otherwise (the terminator band) the clamped sum is taken node by node, as a dense float32 product
      in cache-sized tiles (:data:`TILE_FLOATS`), with BLAS on one thread.

    The result is the dense sum's up to rounding (the linear part is float64, more accurate than the
    dense float32 product; measured on a 1k probe: 6·10⁻⁷ of the peak from the all-dense float32 sum),
    at about a fifth of the products (the cost of a tile is its terminator band, ~sin(r + s) of it)."""
    out = np.zeros((normals.shape[0], 3), dtype=np.float64)
    lit = np.any(flux != 0, axis=1)  # black nodes contribute exactly 0
    flux, nodes = np.asarray(flux[lit], dtype=np.float64), np.asarray(nodes[lit], dtype=np.float64)
    if normals.shape[0] == 0 or flux.shape[0] == 0:
        return out
    nunit, _ = _unit(nodes)
    corder, cstart, caxis, crad = _cones(nunit, NODE_BINS)
    flux, nodes = flux[corder], nodes[corder]
    csize = np.diff(np.r_[cstart, len(nodes)])
    moment = np.add.reduceat(nodes[:, :, None] * flux[:, None, :], cstart, axis=0).reshape(-1, 9)
    nodes32 = nodes.astype(np.float32)
    # Φ padded to 16 columns: OpenBLAS's sgemm is ~7× slower for 3 columns than for 16 (measured,
    # 10k normals × 65k nodes: 4.9 s vs 0.7 s); the padding columns are zero and dropped. A block's band nodes
    # are gathered as 3 columns into one zero-padded buffer (the same tiles as gathering padded rows: 5× less
    # memory traffic than gathering 64-byte rows)
    flux3 = flux.astype(np.float32)
    band_flux = np.zeros((len(flux), 16), dtype=np.float32)
    uunit, ok = _unit(normals)
    border, bstart, baxis, brad = _cones(uunit, NORMAL_BINS)
    bend = np.r_[bstart[1:], len(border)]
    brad[np.add.reduceat((~ok[border]).astype(np.int64), bstart) > 0] = np.pi  # a bad normal: all dense
    gamma = np.arccos(np.clip(baxis @ caxis.T, -1.0, 1.0))
    spread = brad[:, None] + crad[None, :]
    positive = gamma + spread < np.pi / 2 - ANGLE_MARGIN
    negative = gamma - spread > np.pi / 2 + ANGLE_MARGIN
    linear = (positive.astype(np.float64) @ moment).reshape(-1, 3, 3)
    with one_blas_thread():
        for k in range(len(bstart)):
            idx = border[bstart[k]:bend[k]]
            n64 = normals[idx]
            e = n64 @ linear[k]
            band = np.flatnonzero(~positive[k] & ~negative[k])
            if band.size:
                sizes = csize[band]
                total = int(sizes.sum())
                at = np.repeat(cstart[band] - np.r_[0, np.cumsum(sizes)[:-1]], sizes) + np.arange(total)
                w = np.take(nodes32, at, axis=0)
                band_flux[:total, :3] = np.take(flux3, at, axis=0)
                f = band_flux[:total]
                n32 = n64.astype(np.float32)
                step = max(1, TILE_FLOATS // len(idx))
                for s in range(0, total, step):
                    cosines = n32 @ w[s:s + step].T
                    np.maximum(cosines, 0.0, out=cosines)
                    e += (cosines @ f[s:s + step])[:, :3]
            out[idx] = e
    return out


def uses_texel_path(env: Environment, cells: int) -> bool:
    """Large maps (more than TEXEL_PATH_MAX_SMALL rows) whose patches are at least as fine as the fine
    cells (every fine cell holds whole patches) take the streamed texel path."""
    return env.height > TEXEL_PATH_MAX_SMALL and env.height - 1 >= 2 * cells and env.width >= 4 * cells


def check_convention(env: Environment, n: int = 4096, max_rows: int = 256) -> float:
    """max |L_Mitsuba − L_bilinear| / max L over ``n`` seeded random directions, on the map subsampled
    to ≤ ``max_rows`` rows (the convention, not the data, is under test); raises past CONVENTION_TOL."""
    import mitsuba as mi

    step = max(1, -(-env.height // max_rows))
    thumb = np.ascontiguousarray(env.radiance[::step, ::step], dtype=np.float32)
    d = np.random.default_rng(20010812).normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    emitter = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(thumb)})
    diff = float(np.abs(eval_emitter(emitter, d) - latlong.bilinear_lookup(thumb.astype(np.float64), d)).max())
    rel = diff / max(float(thumb.max()), 1e-30)
    if rel > CONVENTION_TOL:
        raise RuntimeError(f"environment {env.name!r}: Mitsuba's envmap differs from the lat-long convention "
                           f"by {rel:.2g} of the peak (tolerance {CONVENTION_TOL:g})")
    return rel


def _patch_rows(h: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per patch row i (H−1): θ at the centre, and the exact weights I0_i, I1_i of the module docstring."""
    th = latlong.row_theta(h)
    dth = np.pi / (h - 1)
    t0, t1 = th[:-1], th[1:]
    i1 = -np.cos(t1) + (np.sin(t1) - np.sin(t0)) / dth
    i0 = (np.cos(t0) - np.cos(t1)) - i1
    return t0 + dth / 2, i0, i1


def _patch_block(rad: np.ndarray, s: int, e: int, i0: np.ndarray, i1: np.ndarray) -> np.ndarray:
    """Φ_p (e−s, W, 3) float32 of patch rows s..e−1; patch column k spans φ_{k−1}..φ_k (centre 2πk/W).
    float32 per patch (relative rounding 6e-8); every sum over patches is taken in float64."""
    block = rad[s:e + 1]
    pair = np.array(block, dtype=np.float32)  # L_{·,k−1} + L_{·,k}, wrapping at k = 0
    pair[:, 1:] += block[:, :-1]
    pair[:, 0] += block[:, -1]
    half_dph = np.float32(np.pi / rad.shape[1])
    w0 = (half_dph * i0[s:e]).astype(np.float32)[:, None, None]
    w1 = (half_dph * i1[s:e]).astype(np.float32)[:, None, None]
    out = pair[:-1] * w0
    out += pair[1:] * w1
    return out


def texel_cell_nodes(env: Environment, cells: int) -> tuple[Nodes, Nodes]:
    """The texel path (module docstring): ((Φ, ω) coarse with H_c = ``cells``, (Φ, ω) fine with 2H_c)."""
    rad = env.radiance
    h, w = rad.shape[:2]
    hf, wf = 2 * cells, 4 * cells
    th_c, i0, i1 = _patch_rows(h)
    ph_c = np.arange(w) * (2 * np.pi / w)
    sin_p, cos_p = np.sin(ph_c).astype(np.float32), np.cos(ph_c).astype(np.float32)
    col_cell = np.minimum((np.arange(w) * wf) // w, wf - 1)
    starts = np.searchsorted(col_cell, np.arange(wf))
    row_cell = np.minimum((th_c / np.pi * hf).astype(np.int64), hf - 1)
    flux = np.zeros((hf, wf, 3))
    mom = np.zeros((hf, wf, 3))  # Σ Y Φ-weighted direction
    lum = np.zeros((hf, wf))
    count = np.zeros((hf, wf), dtype=np.int64)
    step = max(1, BLOCK_BYTES // (w * 3 * 8 * 4))
    for s in range(0, h - 1, step):
        e = min(h - 1, s + step)
        f = _patch_block(rad, s, e, i0, i1)
        y = latlong.luminance(f)
        rc = row_cell[s:e]
        st, ct = np.sin(th_c[s:e])[:, None], np.cos(th_c[s:e])[:, None]
        parts = {"f": np.add.reduceat(f, starts, axis=1, dtype=np.float64),
                 "y": np.add.reduceat(y, starts, axis=1, dtype=np.float64),
                 "ys": np.add.reduceat(y * sin_p, starts, axis=1, dtype=np.float64) * st,
                 "yc": np.add.reduceat(y * cos_p, starts, axis=1, dtype=np.float64) * st}
        np.add.at(flux, rc, parts["f"])
        np.add.at(lum, rc, parts["y"])
        np.add.at(mom, rc, np.stack([parts["ys"], parts["y"] * ct, -parts["yc"]], axis=-1))
        np.add.at(count, rc, np.diff(np.append(starts, w))[None, :].repeat(e - s, axis=0))
    centre = latlong.spherical_to_direction(((np.arange(hf) + 0.5) * np.pi / hf)[:, None],
                                            ((np.arange(wf) + 0.5) * 2 * np.pi / wf)[None, :])
    grids = []
    for k in (2, 1):  # coarse (2×2 sums of the fine cells), then fine
        fl = flux.reshape(hf // k, k, wf // k, k, 3).sum(axis=(1, 3))
        mo = mom.reshape(hf // k, k, wf // k, k, 3).sum(axis=(1, 3))
        ly = lum.reshape(hf // k, k, wf // k, k).sum(axis=(1, 3))
        ct = count.reshape(hf // k, k, wf // k, k).sum(axis=(1, 3))
        grids.append(_texel_refine(rad, fl, mo, ly, ct, centre[::k, ::k], (row_cell // k, col_cell // k), 3 - k))
    return grids[0], grids[1]


def _texel_refine(rad: np.ndarray, flux: np.ndarray, mom: np.ndarray, lum: np.ndarray, count: np.ndarray,
                  centre: np.ndarray, index: tuple[np.ndarray, np.ndarray], sub: int) -> Nodes:
    """Cell nodes (Φ_c, ω_c) of one grid; cells above REFINE_FRACTION of the luminance flux keep their
    patches individually, each split into sub × sub exact sub-patches (brightest cells first, within
    MAX_REFINED_NODES_TEXEL nodes). The coarse grid uses sub = 1, the fine grid sub = 2, so the doubling
    change also measures the node resolution inside a sun, as g → g + 1 does on the Gauss path."""
    wc = lum.shape[1]
    norm = np.linalg.norm(mom, axis=-1, keepdims=True)
    cen = np.where(norm > 0, mom / np.where(norm > 0, norm, 1.0), centre)
    keep = count > 0
    total, budget = lum.sum(), MAX_REFINED_NODES_TEXEL
    extra: list[Nodes] = []
    if total > 0:
        for c_idx in np.argsort(lum.ravel())[::-1]:
            r, c = divmod(int(c_idx), wc)
            if lum[r, c] <= REFINE_FRACTION * total or count[r, c] * sub * sub > budget:
                break
            budget -= int(count[r, c]) * sub * sub
            keep[r, c] = False
            extra.append(subpatch_nodes(rad, np.nonzero(index[0] == r)[0], np.nonzero(index[1] == c)[0], sub))
    return (np.concatenate([flux[keep]] + [e[0] for e in extra]),
            np.concatenate([cen[keep]] + [e[1] for e in extra]))


def subpatch_nodes(rad: np.ndarray, rows: np.ndarray, cols: np.ndarray, sub: int) -> Nodes:
    """Exact flux and centre direction of the sub × sub sub-patches of patches (rows × cols): the
    bilinear radiance restricted to a sub-patch is bilinear with corners interpolated from the
    patch's four texels, so the closed form of the module docstring applies on the sub-interval."""
    h, w = rad.shape[:2]
    dth, dph = np.pi / (h - 1), 2 * np.pi / w
    r0, r1 = int(rows[0]), int(rows[-1]) + 1
    block = rad[r0:r1 + 1].astype(np.float64)
    left, right = np.roll(block, 1, axis=1)[:, cols], block[:, cols]  # texel columns k−1, k
    fracs = np.arange(sub + 1) / sub
    fluxes, dirs = [], []
    for a in range(sub):
        ta, tb = latlong.row_theta(h)[rows] + fracs[a] * dth, latlong.row_theta(h)[rows] + fracs[a + 1] * dth
        i1 = -np.cos(tb) + (np.sin(tb) - np.sin(ta)) / (dth / sub)
        i0 = (np.cos(ta) - np.cos(tb)) - i1
        for b in range(sub):
            corners = []
            for v in (fracs[a], fracs[a + 1]):
                row = (1 - v) * left[:-1] + v * left[1:], (1 - v) * right[:-1] + v * right[1:]
                corners.append(sum((1 - u) * row[0] + u * row[1] for u in (fracs[b], fracs[b + 1])))
            fluxes.append((dph / sub / 2) * (i0[:, None, None] * corners[0] + i1[:, None, None] * corners[1]))
            ph = (cols - 0.5 + (fracs[b] + fracs[b + 1]) / 2) * dph  # patch k spans φ_{k−1}..φ_k
            dirs.append(latlong.spherical_to_direction(((ta + tb) / 2)[:, None], ph[None, :]))
    return np.concatenate([f.reshape(-1, 3) for f in fluxes]), np.concatenate([d.reshape(-1, 3) for d in dirs])


def cached_cell_nodes(env: Environment, cells: int, g: int) -> Nodes:
    """:func:`cell_nodes` through the reference cache, keyed by the map's digest, H_c and g (not by the normals):
    the nodes depend on the map alone, so every experiment that integrates the same map at the same (H_c, g)
    (sh9, engines, ibl, the path-traced cross-check's quadrature) reads the float64 arrays the first one stored
    (the same bits) instead of evaluating Mitsuba's emitter and binning the nodes again."""
    def compute() -> dict[str, np.ndarray]:
        flux, dirs = cell_nodes(env, cells, g)
        return {"flux": flux, "dirs": dirs}

    r = cached("irradiance_nodes", {"env": env.digest, "cells": cells, "g": g, "method": "gauss-cell-nodes"}, compute)
    return r["flux"], r["dirs"]


def cached_texel_cell_nodes(env: Environment, cells: int) -> tuple[Nodes, Nodes]:
    """:func:`texel_cell_nodes` (after :func:`check_convention`) through the reference cache, keyed by the map's
    digest and H_c, as :func:`cached_cell_nodes`."""
    def compute() -> dict[str, np.ndarray]:
        check_convention(env)
        (cf, cd), (ff, fd) = texel_cell_nodes(env, cells)
        return {"coarse_flux": cf, "coarse_dirs": cd, "fine_flux": ff, "fine_dirs": fd}

    r = cached("irradiance_nodes", {"env": env.digest, "cells": cells, "method": "texel-cell-nodes"}, compute)
    return (r["coarse_flux"], r["coarse_dirs"]), (r["fine_flux"], r["fine_dirs"])


def reference_irradiance(env: Environment, normals: np.ndarray, cells: int = DEFAULT_CELLS) -> ReferenceIrradiance:
    """Reference E at ``normals`` (N, 3): the (2·cells, g+1) quadrature, with max_n |E_fine − E_coarse|
    (per channel) as its uncertainty."""
    normals = np.ascontiguousarray(normals, dtype=np.float64)

    texel_path = uses_texel_path(env, cells)

    def compute() -> dict[str, np.ndarray]:
        if texel_path:
            coarse_nodes, fine_nodes = cached_texel_cell_nodes(env, cells)
            return {"fine": irradiance_at(*fine_nodes, normals), "coarse": irradiance_at(*coarse_nodes, normals)}
        g = gauss_order(env, cells)
        coarse = irradiance_at(*cached_cell_nodes(env, cells, g), normals)
        fine = irradiance_at(*cached_cell_nodes(env, 2 * cells, g + 1), normals)
        return {"fine": fine, "coarse": coarse}

    method = "texel-cells" if texel_path else "gauss-cells"
    parts = {"env": env.digest, "normals": array_digest(normals), "cells": cells, "method": method}
    r = cached("irradiance", parts, compute)
    delta = np.abs(r["fine"] - r["coarse"]).max(axis=0, initial=0.0)
    return ReferenceIrradiance(r["fine"], np.broadcast_to(delta, r["fine"].shape).copy(), cells)
