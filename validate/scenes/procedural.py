"""Built-in environments, so the default run needs no files.

Each is baked to a lat-long map in Mitsuba's convention (:mod:`validate.scenes.latlong`); that map is
the environment both the reference and the local models see. Where a texel is the average of a
discontinuous function (disc edges, the sun), it is the mean of s×s stratified point samples over
the texel's cell.

* ``constant`` — L = (1.0, 0.8, 0.6): closed form E = πL.
* ``two_tone`` — sky L_s above the horizon (y > 0), ground L_g below: closed form
  E = π(L_s(1 + cos β)/2 + L_g(1 − cos β)/2), β the angle between n and +y.
* ``sunsky_XXdeg`` — Mitsuba's ``sunsky`` (Hosek–Wilkie sky + sun, physical units, turbidity 3,
  albedo 0.3) at sun elevations 5°, 30°, 60°. sunsky is z-up; it is rotated so its zenith is +y.
* ``bandlimited`` — a positive order-2 SH function: SH9 irradiance is exact for it.
* ``disc_on_sky`` — a 4° (half-angle) disc 400× brighter than a dim uniform sky.
* ``near_directional`` — a 0.5° disc on black: approaches the directional worst case of SH9.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from . import latlong
from .environment import Environment

SKY = np.array([0.55, 0.70, 1.00])
GROUND = np.array([0.35, 0.28, 0.20])
CONSTANT = np.array([1.0, 0.8, 0.6])
SUN_ELEVATIONS_DEG = (5.0, 30.0, 60.0)

# Order-2 SH coefficients (rows L00, L1m1, L10, L11, L2m2, L2m1, L20, L21, L22; columns RGB) of the
# band-limited environment; positive everywhere (checked in ``bandlimited``).
BANDLIMITED_SH = np.array([
    [2.0, 1.8, 1.6],
    [0.30, 0.35, 0.45],
    [-0.20, -0.10, 0.05],
    [0.25, 0.20, 0.10],
    [0.10, 0.05, 0.00],
    [0.15, 0.20, 0.25],
    [0.20, 0.15, 0.10],
    [-0.10, -0.05, 0.05],
    [0.12, 0.10, 0.08],
])


def _cell_average(height: int, width: int, fn: Callable[[np.ndarray], np.ndarray], s: int) -> np.ndarray:
    """Mean of fn over s×s stratified points in each texel cell (cells clipped at the poles)."""
    out = np.zeros((height, width, 3), dtype=np.float64)
    e = latlong.row_cell_edges(height)
    ph = latlong.col_phi(width)
    dph = 2 * np.pi / width
    for a in range(s):
        # stratify in cos θ between the cell edges so samples are area-uniform
        c0, c1 = np.cos(e[:-1]), np.cos(e[1:])
        ct = c0 + (c1 - c0) * (a + 0.5) / s
        th = np.arccos(np.clip(ct, -1, 1))
        for b in range(s):
            tt, pp = np.meshgrid(th, ph + ((b + 0.5) / s - 0.5) * dph, indexing="ij")
            out += fn(latlong.spherical_to_direction(tt, pp))
    return (out / (s * s)).astype(np.float32)


def _point_sampled(height: int, width: int, fn: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    return fn(latlong.texel_directions(height, width)).astype(np.float32)


def direction_from_elevation(elevation_deg: float, azimuth_deg: float = 0.0) -> np.ndarray:
    """World direction (y-up) at an elevation above the horizon and azimuth φ (0 = −z, 90° = +x)."""
    e, a = np.radians(elevation_deg), np.radians(azimuth_deg)
    return np.array([np.cos(e) * np.sin(a), np.sin(e), -np.cos(e) * np.cos(a)])


def constant(height: int = 64) -> Environment:
    rad = np.broadcast_to(CONSTANT.astype(np.float32), (height, 2 * height, 3)).copy()
    return Environment("constant", rad, description="uniform L = (1.0, 0.8, 0.6)", layout="procedural",
                       tags=("closed_form",))


def two_tone(height: int = 256, sky: np.ndarray = SKY, ground: np.ndarray = GROUND) -> Environment:
    """Sky above the horizon, ground below; row values point-sampled (horizon falls between rows)."""
    def fn(d: np.ndarray) -> np.ndarray:
        return np.where(d[..., 1:2] > 0, sky, ground)
    return Environment("two_tone", _point_sampled(height, 2 * height, fn),
                       description="two-tone sky (0.55, 0.70, 1.00) over ground (0.35, 0.28, 0.20)",
                       layout="procedural", tags=("closed_form",))


def cap(direction: np.ndarray, half_angle_deg: float) -> Callable[[np.ndarray], np.ndarray]:
    cos_a = np.cos(np.radians(half_angle_deg))
    direction = direction / np.linalg.norm(direction)
    return lambda d: (d @ direction > cos_a).astype(np.float64)[..., None]


def disc_on_sky(height: int = 256, half_angle_deg: float = 4.0, elevation_deg: float = 35.0,
                contrast: float = 400.0) -> Environment:
    sky = np.array([0.05, 0.06, 0.08])
    inside = cap(direction_from_elevation(elevation_deg, 30.0), half_angle_deg)
    fn = lambda d: sky + inside(d) * contrast * np.array([0.06, 0.055, 0.05])  # noqa: E731
    return Environment("disc_on_sky", _cell_average(height, 2 * height, fn, 4),
                       description=f"{half_angle_deg:g}° disc, {contrast:g}× a dim sky, elevation {elevation_deg:g}°",
                       layout="procedural")


def near_directional(height: int = 512, half_angle_deg: float = 0.5, elevation_deg: float = 40.0) -> Environment:
    inside = cap(direction_from_elevation(elevation_deg, -60.0), half_angle_deg)
    fn = lambda d: inside(d) * np.array([1.0, 1.0, 1.0])  # noqa: E731
    return Environment("near_directional", _cell_average(height, 2 * height, fn, 6),
                       description=f"{half_angle_deg:g}° disc on black: the directional worst case of SH9",
                       layout="procedural")


def bandlimited(height: int = 128) -> Environment:
    from ..local_models.sh import eval_basis_numpy

    def fn(d: np.ndarray) -> np.ndarray:
        return eval_basis_numpy(d, 2) @ BANDLIMITED_SH
    rad = _point_sampled(height, 2 * height, fn)
    assert rad.min() > 0.1, "band-limited environment must stay positive"
    return Environment("bandlimited", rad, description="positive order-2 SH function (SH9 exact)",
                       layout="procedural", tags=("closed_form",))


def sunsky(elevation_deg: float, height: int = 512, supersample: int = 4) -> Environment:
    """Mitsuba ``sunsky`` baked to a lat-long map (cell-averaged so the sun's energy is kept)."""
    import mitsuba as mi

    from ..backend import init
    from ..reference.mitsuba_eval import eval_emitter

    backend = init()
    if not backend.is_vectorized:  # the scalar fallback evaluates one direction at a time
        height, supersample = min(height, 64), 1
    w = direction_from_elevation(elevation_deg, 45.0)
    # the sky's zenith follows to_world (z → +y); sun_direction is taken in world space (measured:
    # the baked sun lands on this vector, tests/test_procedural.py)
    emitter = mi.load_dict({
        "type": "sunsky", "sun_direction": [float(v) for v in w], "turbidity": 3.0,
        "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90),
    })
    rad = _cell_average(height, 2 * height, lambda d: eval_emitter(emitter, d), supersample)
    return Environment(f"sunsky_{elevation_deg:g}deg", rad,
                       description=f"Mitsuba sunsky, sun at {elevation_deg:g}° elevation (physical units)",
                       layout="procedural", tags=("sunsky",))


def builtin_environments(quick: bool = False) -> list[Environment]:
    """Every built-in environment (quick mode: smaller maps)."""
    k = 2 if quick else 1
    envs = [constant(), two_tone(256 // k), bandlimited(), disc_on_sky(256 // k), near_directional(512 // k)]
    envs += [sunsky(e, height=512 // k, supersample=4 // k) for e in SUN_ELEVATIONS_DEG]
    return envs


BUILTIN_NAMES = ("constant", "two_tone", "bandlimited", "disc_on_sky", "near_directional",
                 *(f"sunsky_{e:g}deg" for e in SUN_ELEVATIONS_DEG))
