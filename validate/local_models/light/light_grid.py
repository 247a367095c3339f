"""Area lights as n×n point lights (Ganovelli et al. §6.7.6 [1]), with and without shadow rays.

The irradiance of a Lambertian emitter of radiance L at a receiver x with normal n is the area
integral [1, eq. 6.44–6.49]

    E(x) = ∫_A L max(0, n_L·(x − q)/r) max(0, n·(q − x)/r) / r² · V(x, q) dA(q),   r = |q − x|,

which the n×n grid replaces by the product midpoint rule: the emitter's parameter square is cut
into n×n equal cells, each cell a point light at its centre q_k carrying the cell's area A/n²:

    E_n(x) = Σ_k L (A/n²) max(0, n_L·ω_k') max(0, n·ω_k) / r_k² · V_k.

* rectangle: q = c + s·a + t·b, (s, t) ∈ [−1, 1]² (a, b the half-edge vectors), cell centres
  s = 2(i + o)/n − 1 with o = ``grid_offset`` (½: midpoint rule; 0: the left-endpoint rule,
  kept so that a wrong rule can be shown to converge more slowly);
* disc: the cells of the unit square mapped to the disc by Shirley & Chiu's concentric map [2],
  which is area-preserving, so every cell again carries A/n²;
* sphere: seen from x, a sphere of radius r at distance d covers the same solid angle as the disc
  spanned by its tangent circle (centre c + (r²/d) ŵ, ŵ = (x − c)/d, radius r √(1 − r²/d²), facing
  x), and a uniform radiance over equal solid angle gives equal irradiance; that disc is gridded as
  above. Its points lie inside the sphere, so shadow rays end on or inside the light.

Error (quadrature theory): for an integrand with continuous second derivatives the composite
midpoint rule has error (h²/24) ∫ f'' + O(h⁴) per axis, h = 2/n, so E_n − E = O(n⁻²); the left-
endpoint rule's error is O(n⁻¹) [3, §2.2–2.3]. Shadow edges (V discontinuous) reduce the rate in
the penumbra. ``grid`` = n (default 8, 1…64); n = 1 is a single point light at the centre with the
emitter's on-axis intensity L·A cos ψ.

References
  [1] F. Ganovelli et al., *Introduction to Computer Graphics*, CRC 2014, §6.7.6, eq. 6.44–6.49.
  [2] P. Shirley, K. Chiu, "A Low Distortion Map Between Disk and Square", JGT 2(3), 1997.
  [3] P. J. Davis, P. Rabinowitz, *Methods of Numerical Integration*, 2nd ed., Academic Press 1984,
      §2.2–2.3 (rectangle and midpoint rules, error terms).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ..families import light
from ..precision import float_type, to_dr, uint_type
from .common import Visible, as_points, require, shadow

AREA_KINDS = ("rectangle", "disk", "sphere")
DEFAULT_GRID = 8
MAX_GRID = 64
CHUNK_TERMS = 1 << 21  # receiver × grid-point terms per drjit pass (bounds memory)


def grid_parameters(n: int, offset: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """(u, v) ∈ [0, 1]² of the n×n cells' sample points ((i + offset)/n), each (n²,)."""
    g = (np.arange(n) + offset) / n
    uu, vv = np.meshgrid(g, g, indexing="ij")
    return uu.ravel(), vv.ravel()


def concentric_map(u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shirley–Chiu [2]: unit square → unit disc, area-preserving."""
    a, b = 2 * u - 1, 2 * v - 1
    first = np.abs(a) > np.abs(b)
    r = np.where(first, a, b)
    with np.errstate(divide="ignore", invalid="ignore"):
        phi = np.where(first, (np.pi / 4) * (b / np.where(a == 0, 1, a)),
                       np.pi / 2 - (np.pi / 4) * (a / np.where(b == 0, 1, b)))
    r = np.where((a == 0) & (b == 0), 0.0, r)
    return r * np.cos(phi), r * np.sin(phi)


def emitter_points(light_map: Mapping[str, Any], x: np.ndarray, n: int, offset: float
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sample points q (N, K, 3), emitter normals n_L (N, K, 3) and cell areas (N, 1) for receivers x (N, 3)."""
    kind = light_map["type"]
    u, v = grid_parameters(n, offset)
    c = np.asarray(light_map["position"], dtype=np.float64)
    big_n = x.shape[0]
    if kind == "rectangle":
        require(light_map, "axes", "normal")
        a, b = np.asarray(light_map["axes"], dtype=np.float64)
        q = c + (2 * u - 1)[:, None] * a + (2 * v - 1)[:, None] * b
        area = 4.0 * np.linalg.norm(a) * np.linalg.norm(b) / n**2
        nl = np.asarray(light_map["normal"], dtype=np.float64)
        return (np.broadcast_to(q, (big_n,) + q.shape), np.broadcast_to(nl, (big_n, q.shape[0], 3)),
                np.full((big_n, 1), area))
    dx, dy = concentric_map(u, v)
    if kind == "disk":
        require(light_map, "axes", "normal", "radius")
        rad = float(light_map["radius"])
        a, b = np.asarray(light_map["axes"], dtype=np.float64)
        q = c + rad * (dx[:, None] * a + dy[:, None] * b)
        nl = np.asarray(light_map["normal"], dtype=np.float64)
        return (np.broadcast_to(q, (big_n,) + q.shape), np.broadcast_to(nl, (big_n, q.shape[0], 3)),
                np.full((big_n, 1), np.pi * rad**2 / n**2))
    require(light_map, "radius")  # sphere: the tangent-circle disc facing each receiver
    rad = float(light_map["radius"])
    w = x - c
    d = np.linalg.norm(w, axis=1, keepdims=True)
    if np.any(d <= rad):
        raise ValidateError("light of type 'sphere': a receiver lies inside the emitting sphere")
    w = w / d
    helper = np.where(np.abs(w[:, 1:2]) < 0.9, [[0.0, 1.0, 0.0]], [[1.0, 0.0, 0.0]])
    a = np.cross(helper, w)
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    b = np.cross(w, a)
    centre = c + (rad * rad / d) * w
    rho = rad * np.sqrt(1.0 - (rad / d) ** 2)  # (N, 1)
    # q = centre + ρ (dx a + dy b), the same products and sums formed in place (one (N, K, 3) buffer, not four)
    q = dx[None, :, None] * a[:, None, :]
    q += dy[None, :, None] * b[:, None, :]
    q *= rho[:, :, None]
    q += centre[:, None, :]
    return q, np.broadcast_to(w[:, None, :], q.shape), np.pi * rho**2 / n**2


def grid_irradiance(light_map: Mapping[str, Any], points: Any, normals: Any, visible: Visible | None,
                    shadowed: bool) -> np.ndarray:
    """E_n(x) of the module docstring; drjit evaluates the N×n² point-light terms, in chunks of receivers."""
    require(light_map, "position", "radiance", kinds=AREA_KINDS)
    n = int(light_map.get("grid", DEFAULT_GRID))
    offset = float(light_map.get("grid_offset", 0.5))
    if not 1 <= n <= MAX_GRID:
        raise ValidateError(f"light grid n = {n}: accepted range 1…{MAX_GRID}")
    x, nx = as_points(points, normals)
    step = max(1, CHUNK_TERMS // (n * n))
    parts = [_grid_chunk(light_map, x[i:i + step], nx[i:i + step], n, offset, visible if shadowed else None)
             for i in range(0, x.shape[0], step)]
    return np.concatenate(parts) if parts else np.zeros(0)


def _packed_rows_to_dr(packed: np.ndarray) -> list[Any]:
    """The columns of a row-major (M, k) float64 array as drjit arrays: exactly precision.packed_to_dr's upload and
    gathers (entry j of row i at k·i + j), for an array already laid out as its packed input."""
    import drjit as dr

    m, k = packed.shape
    data = to_dr(packed)
    idx = dr.arange(uint_type(), m) * k
    return [dr.gather(float_type(), data, idx + j) for j in range(k)]


def _grid_chunk(light_map: Mapping[str, Any], x: np.ndarray, nx: np.ndarray, n: int, offset: float,
                visible: Visible | None) -> np.ndarray:
    import drjit as dr

    q, nl, area = emitter_points(light_map, x, n, offset)
    k = q.shape[1]
    # the nine columns (v = q − x receiver → emitter point, the receiver normal, the emitter normal) written side
    # by side into one (N, K, 9) buffer, the row-major packed input of precision.packed_to_dr (one input per column
    # misses the kernel cache) built in place instead of from nine strided column copies stacked again
    packed = np.empty(q.shape[:2] + (9,))
    np.subtract(q, x[:, None, :], out=packed[..., 0:3])
    packed[..., 3:6] = nx[:, None, :]
    packed[..., 6:9] = nl
    vx, vy, vz, rx, ry, rz, lx, ly, lz = _packed_rows_to_dr(packed.reshape(-1, 9))
    r2 = vx * vx + vy * vy + vz * vz
    inv_r = dr.rsqrt(r2)
    cos_r = (vx * rx + vy * ry + vz * rz) * inv_r
    cos_l = -(vx * lx + vy * ly + vz * lz) * inv_r
    term = np.array(dr.maximum(cos_r, 0.0) * dr.maximum(cos_l, 0.0) / r2, dtype=np.float64).reshape(-1, k)
    if visible is not None:
        lit = np.flatnonzero(term > 0)  # flat index i·K + j of the lit terms, in row-major order as np.nonzero
        vis = np.zeros_like(term)
        if lit.size:
            i, j = np.divmod(lit, k)
            # rectangle, disc: q is one (K, 3) grid broadcast over the receivers; read it, not the broadcast view
            qk = np.take(q[0], j, axis=0) if q.strides[0] == 0 else np.take(q.reshape(-1, 3), lit, axis=0)
            vis.reshape(-1)[lit] = shadow(visible, np.take(x, i, axis=0), np.take(nx, i, axis=0), qk)
        term = term * vis
    return float(light_map["radiance"]) * area[:, 0] * term.sum(axis=1)


@light.register("area_grid", "area light as n×n point lights, midpoint rule, no shadow rays (Ganovelli §6.7.6)",
                lights=AREA_KINDS)
def area_grid(light_map: Mapping[str, Any], points: Any, normals: Any, visible: Visible | None = None) -> np.ndarray:
    """E_n(x) without visibility (module docstring); n = light['grid'] (default 8)."""
    return grid_irradiance(light_map, points, normals, visible, shadowed=False)


@light.register("area_grid_shadowed", "area light as n×n point lights, one shadow ray per point", lights=AREA_KINDS)
def area_grid_shadowed(light_map: Mapping[str, Any], points: Any, normals: Any,
                       visible: Visible | None = None) -> np.ndarray:
    """E_n(x) with one shadow ray per grid point (module docstring); n = light['grid'] (default 8)."""
    return grid_irradiance(light_map, points, normals, visible, shadowed=True)
