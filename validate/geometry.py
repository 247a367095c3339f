"""Directions, frames and cube-map geometry: the ground floor every layer may use (numpy only).

Conventions
  * World y-up, as Mitsuba; directions are (..., 3) float64 arrays.
  * Cube maps: face order +X, −X, +Y, −Y, +Z, −Z (:data:`CUBE_FACES`); face selection by the major axis
    and the face coordinates (s_c, t_c, m_a) of [1, Table 8.19]:
    +X (−z, −y, x), −X (z, −y, −x), +Y (x, z, y), −Y (x, −z, −y), +Z (x, −y, z), −Z (−x, −y, −z);
    s = (s_c/|m_a| + 1)/2, t = (t_c/|m_a| + 1)/2; texel (row i, column j) of an N × N face is centred at
    s = (j + ½)/N, t = (i + ½)/N.
  * The solid angle of the face rectangle [0, a] × [0, b] at unit distance is atan(ab / √(a² + b² + 1))
    [2], so a texel's exact solid angle is the inclusion–exclusion of four such corners; six faces sum to 4π.

References
  [1] M. Segal, K. Akeley, "The OpenGL Graphics System: A Specification (4.6 Core)", §8.13
      "Cube Map Texture Selection", Table 8.19.
  [2] A. Van Oosterom, J. Strackee, "The Solid Angle of a Plane Triangle", IEEE Trans. Biomed. Eng. 30(2),
      1983 (the rectangle corner form used by cmgen and Filament's ``CubemapUtils::solidAngle``).
"""

from __future__ import annotations

import numpy as np

CUBE_FACES = ("+x", "-x", "+y", "-y", "+z", "-z")
NORM_FLOOR = 1e-300  # |x| floor in :func:`unit`: a zero vector stays zero instead of NaN


def unit(x: np.ndarray) -> np.ndarray:
    """x / |x| along the last axis, as float64 (a zero vector stays zero: |x| is floored at 1e-300)."""
    x = np.asarray(x, dtype=np.float64)
    return x / np.maximum(np.linalg.norm(x, axis=-1, keepdims=True), NORM_FLOOR)


def perp(n: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to each n ((3,) or (N, 3)): n × x̂, or n × ŷ where |n_x| ≥ 0.9."""
    n = np.asarray(n, dtype=np.float64)
    a = np.where(np.abs(n[..., :1]) < 0.9, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    return unit(np.cross(n, a))


def frame(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(t, b) completing unit n to a right-handed orthonormal frame (t, b, n): t = :func:`perp` (n), b = n × t."""
    t = perp(n)
    return t, np.cross(np.asarray(n, dtype=np.float64), t)


def face_direction(face: np.ndarray | int, sc: np.ndarray, tc: np.ndarray) -> np.ndarray:
    """Unnormalised direction of face coordinates (s_c, t_c) ∈ [−1, 1]² on ``face`` [1, Table 8.19]."""
    sc, tc, face = np.broadcast_arrays(np.asarray(sc, dtype=np.float64), np.asarray(tc, dtype=np.float64),
                                       np.asarray(face))
    one = np.ones(face.shape)
    cand = np.stack([
        np.stack([one, -tc, -sc], -1), np.stack([-one, -tc, sc], -1),
        np.stack([sc, one, tc], -1), np.stack([sc, -one, -tc], -1),
        np.stack([sc, -tc, one], -1), np.stack([-sc, -tc, -one], -1)], 0)
    return np.take_along_axis(cand, face[None, ..., None].astype(np.int64), axis=0)[0]


def face_coords(dirs: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(face, x, y) for directions (..., 3): x = s N − ½, y = t N − ½ continuous texel coordinates
    (texel (i, j) centred at (x, y) = (j, i)), face by the major axis [1, Table 8.19]."""
    d = np.asarray(dirs, dtype=np.float64)
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    ax, ay, az = np.abs(x), np.abs(y), np.abs(z)
    use_x = (ax >= ay) & (ax >= az)
    use_y = ~use_x & (ay >= az)
    face = np.where(use_x, np.where(x >= 0, 0, 1), np.where(use_y, np.where(y >= 0, 2, 3),
                                                            np.where(z >= 0, 4, 5)))
    sc = np.select([face == 0, face == 1, face == 2, face == 3, face == 4], [-z, z, x, x, x], -x)
    tc = np.select([face == 0, face == 1, face == 2, face == 3, face == 4], [-y, -y, z, -z, -y], -y)
    ma = np.select([face < 2, face < 4], [ax, ay], az)
    ma = np.maximum(ma, NORM_FLOOR)
    return face, (sc / ma + 1.0) * 0.5 * n - 0.5, (tc / ma + 1.0) * 0.5 * n - 0.5


def cube_texel_directions(n: int) -> np.ndarray:
    """Unit directions of all texel centres, (6, N, N, 3)."""
    c = (np.arange(n) + 0.5) / n * 2.0 - 1.0
    tc, sc = np.meshgrid(c, c, indexing="ij")
    d = np.stack([face_direction(f, sc, tc) for f in range(6)], 0)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def cube_texel_solid_angles(n: int) -> np.ndarray:
    """Exact solid angle of every texel of a face (N, N) (the same for all faces); 6 faces sum to 4π.
    Ω of the face rectangle [0, a] × [0, b] (unit distance) is atan(ab / √(a² + b² + 1)) [2]."""
    e = np.linspace(-1.0, 1.0, n + 1)
    a, b = np.meshgrid(e, e, indexing="ij")
    f = np.arctan2(a * b, np.sqrt(a * a + b * b + 1.0))
    return f[1:, 1:] - f[:-1, 1:] - f[1:, :-1] + f[:-1, :-1]


__all__ = ["CUBE_FACES", "cube_texel_directions", "cube_texel_solid_angles", "face_coords", "face_direction",
           "frame", "perp", "unit"]
