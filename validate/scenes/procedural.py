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

import math
from collections.abc import Callable

import numpy as np

from ..backend import init
from ..errors import ValidateError
from . import latlong
from .environment import Environment
from .mitsuba_eval import eval_emitter

SKY = np.array([0.55, 0.70, 1.00])
GROUND = np.array([0.35, 0.28, 0.20])
CONSTANT = np.array([1.0, 0.8, 0.6])
SUN_ELEVATIONS_DEG = (5.0, 30.0, 60.0)

# near_directional: a 0.5° (half-angle) disc of unit radiance at elevation 40°, azimuth −60°.
NEAR_DIRECTIONAL_HALF_ANGLE_DEG = 0.5
NEAR_DIRECTIONAL_ELEVATION_DEG = 40.0
NEAR_DIRECTIONAL_AZIMUTH_DEG = -60.0
# Its map keeps 512 rows even in quick mode: at 256 rows (0.7° texels for a 1° disc) the 6×6 stratified
# cell average loses 0.54 % of the disc's flux (measured), at 512 rows 0.015 %.
NEAR_DIRECTIONAL_HEIGHT = 512


def near_directional_half_angle() -> float:
    """α of the built-in ``near_directional`` environment as a model sees it: its disc's half-angle plus one
    texel diagonal (√2 π / H: the cells its cell-averaged texels cover), in radians."""
    return math.radians(NEAR_DIRECTIONAL_HALF_ANGLE_DEG) + math.sqrt(2.0) * math.pi / NEAR_DIRECTIONAL_HEIGHT

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


def _cell_average(height: int, width: int, fn: Callable[[np.ndarray], np.ndarray], s: int,
                  theta_support: tuple[float, float] | None = None) -> np.ndarray:
    """Mean of fn over s×s stratified points in each texel cell (cells clipped at the poles).

    ``theta_support = (θ_lo, θ_hi)``: fn is exactly 0 at every direction whose polar angle lies outside it (a
    cap of half-angle a about polar angle θ_c has support θ_c ± a, since the angle between two directions is at
    least the difference of their polar angles); only the rows whose cells meet it (one row of margin either
    side) are evaluated, the others are 0 — the same numbers, bit for bit, as evaluating every row."""
    out = np.zeros((height, width, 3), dtype=np.float64)
    e = latlong.row_cell_edges(height)
    lo, hi = 0, height
    if theta_support is not None:
        meets = np.flatnonzero((e[1:] >= theta_support[0]) & (e[:-1] <= theta_support[1]))
        if meets.size == 0:
            return out.astype(np.float32)
        lo, hi = max(int(meets[0]) - 1, 0), min(int(meets[-1]) + 2, height)
    ph = latlong.col_phi(width)
    dph = 2 * np.pi / width
    for a in range(s):
        # stratify in cos θ between the cell edges so samples are area-uniform
        c0, c1 = np.cos(e[lo:hi]), np.cos(e[lo + 1:hi + 1])
        ct = c0 + (c1 - c0) * (a + 0.5) / s
        th = np.arccos(np.clip(ct, -1, 1))
        for b in range(s):
            tt, pp = np.meshgrid(th, ph + ((b + 0.5) / s - 0.5) * dph, indexing="ij")
            out[lo:hi] += fn(latlong.spherical_to_direction(tt, pp))
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


def near_directional(height: int = NEAR_DIRECTIONAL_HEIGHT, half_angle_deg: float = NEAR_DIRECTIONAL_HALF_ANGLE_DEG,
                     elevation_deg: float = NEAR_DIRECTIONAL_ELEVATION_DEG) -> Environment:
    inside = cap(direction_from_elevation(elevation_deg, NEAR_DIRECTIONAL_AZIMUTH_DEG), half_angle_deg)
    fn = lambda d: inside(d) * np.array([1.0, 1.0, 1.0])  # noqa: E731
    polar = np.radians(90.0 - elevation_deg)
    support = (polar - np.radians(half_angle_deg), polar + np.radians(half_angle_deg))
    return Environment("near_directional", _cell_average(height, 2 * height, fn, 6, support),
                       description=f"{half_angle_deg:g}° disc on black: the directional worst case of SH9",
                       layout="procedural")


def sh9_basis(d: np.ndarray) -> np.ndarray:
    """The nine real SH basis functions of order ≤ 2 at unit directions d (..., 3) → (..., 9).

    R&H 2001 eq. 3 (no Condon–Shortley phase), written out here so the environment's definition does
    not depend on the model under test: Y00 = √(1/4π); Y1m1, Y10, Y11 = √(3/4π)·(y, z, x);
    Y2m2, Y2m1, Y21 = √(15/4π)·(xy, yz, xz); Y20 = √(5/16π)(3z² − 1); Y22 = √(15/16π)(x² − y²)
    (0.282095, 0.488603, 1.092548, 0.315392, 0.546274 in the paper).
    """
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    k0, k1, k2 = np.sqrt(1 / (4 * np.pi)), np.sqrt(3 / (4 * np.pi)), np.sqrt(15 / (4 * np.pi))
    k20, k22 = np.sqrt(5 / (16 * np.pi)), np.sqrt(15 / (16 * np.pi))
    return np.stack([np.full_like(x, k0), k1 * y, k1 * z, k1 * x, k2 * x * y, k2 * y * z,
                     k20 * (3 * z * z - 1), k2 * x * z, k22 * (x * x - y * y)], axis=-1)


def bandlimited(height: int = 128) -> Environment:
    def fn(d: np.ndarray) -> np.ndarray:
        return sh9_basis(d) @ BANDLIMITED_SH
    rad = _point_sampled(height, 2 * height, fn)
    assert rad.min() > 0.1, "band-limited environment must stay positive"
    return Environment("bandlimited", rad, description="positive order-2 SH function (SH9 exact)",
                       layout="procedural", tags=("closed_form",))


def sunsky(elevation_deg: float, height: int = 512, supersample: int = 4) -> Environment:
    """Mitsuba ``sunsky`` baked to a lat-long map (cell-averaged so the sun's energy is kept)."""
    import mitsuba as mi

    backend = init()
    if not backend.is_vectorized:  # the scalar fallback evaluates one direction at a time
        height, supersample = min(height, 64), 1
    w = direction_from_elevation(elevation_deg, 45.0)
    # the sky's zenith follows to_world (z → +y); sun_direction is taken in world space (measured:
    # the baked sun lands on this vector, tests/reference/test_procedural.py)
    emitter = mi.load_dict({
        "type": "sunsky", "sun_direction": [float(v) for v in w], "turbidity": 3.0,
        "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90),
    })
    rad = _cell_average(height, 2 * height, lambda d: eval_emitter(emitter, d), supersample)
    return Environment(f"sunsky_{elevation_deg:g}deg", rad,
                       description=f"Mitsuba sunsky, sun at {elevation_deg:g}° elevation (physical units)",
                       layout="procedural", tags=("sunsky",))


def _builtin_makers(quick: bool) -> dict[str, Callable[[], Environment]]:
    k = 2 if quick else 1
    makers: dict[str, Callable[[], Environment]] = {
        "constant": constant, "two_tone": lambda: two_tone(256 // k), "bandlimited": bandlimited,
        "disc_on_sky": lambda: disc_on_sky(256 // k), "near_directional": near_directional}
    for e in SUN_ELEVATIONS_DEG:
        makers[f"sunsky_{e:g}deg"] = lambda e=e: sunsky(e, height=512 // k, supersample=4 // k)
    return makers


def builtin_environments(quick: bool = False) -> list[Environment]:
    """Every built-in environment (quick mode: smaller maps, except near_directional)."""
    return [make() for make in _builtin_makers(quick).values()]


def builtin_environment(name: str, quick: bool = False) -> Environment:
    """One built-in environment by name (``BUILTIN_NAMES``); unknown name → ValidateError."""

    makers = _builtin_makers(quick)
    if name not in makers:
        raise ValidateError(f"unknown built-in environment {name!r}; built-ins: {', '.join(makers)}")
    return makers[name]()


BUILTIN_NAMES = ("constant", "two_tone", "bandlimited", "disc_on_sky", "near_directional",
                 *(f"sunsky_{e:g}deg" for e in SUN_ELEVATIONS_DEG))
