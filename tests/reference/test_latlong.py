"""The lat-long convention of :mod:`validate.scenes.latlong` is Mitsuba's ``envmap`` convention.

Measured against Mitsuba itself: an ``envmap`` built from a small random bitmap is evaluated with
``emitter.eval`` (through :func:`validate.scenes.mitsuba_eval.eval_emitter`) and compared with our
numpy :func:`~validate.scenes.latlong.bilinear_lookup`. A random 9×18 map makes any convention slip
(row i at iπ/(H−1) vs (i+½)π/H, a half-texel shift in φ, a mirrored axis) an O(1) difference.
"""

from __future__ import annotations

import mitsuba as mi
import numpy as np
import pytest

from validate.scenes import latlong
from validate.scenes.mitsuba_eval import eval_emitter

# Mitsuba evaluates in float32: directions are rounded to 2⁻²⁴ relative, φ = atan2(…) and the bilinear
# weights follow with errors ~1e-7·W; on values in [0, 1) we measured max |Δ| = 1.8e-6 (random
# directions) and 1.7e-6 (texel directions). 1e-5 is ~5× that and ~10⁵× below a convention slip.
MITSUBA_FLOAT32_TOL = 1e-5
# float64 geometry: sums of H·W positive terms and trigonometric round trips, ~1e-15 each.
FLOAT64_TOL = 1e-12


def _random_directions(n: int, seed: int) -> np.ndarray:
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


@pytest.fixture(scope="module")
def random_envmap() -> tuple[np.ndarray, object]:
    rad = np.random.default_rng(7).random((9, 18, 3)).astype(np.float32)
    return rad, mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(rad)})


def test_bilinear_lookup_matches_mitsuba_eval(random_envmap) -> None:
    rad, emitter = random_envmap
    d = _random_directions(4000, seed=1)
    ours = latlong.bilinear_lookup(rad.astype(np.float64), d)
    theirs = eval_emitter(emitter, d)
    assert np.abs(ours - theirs).max() < MITSUBA_FLOAT32_TOL


def test_texel_values_are_reproduced_at_texel_directions(random_envmap) -> None:
    """At θ_i = iπ/(H−1), φ_j = 2π(j+½)/W Mitsuba returns texel (i, j) exactly.

    Rows 0 and H−1 are the poles: all their samples are one direction, so only an interior row can
    reproduce a per-texel value (the pole rows are tested with constant rows below)."""
    rad, emitter = random_envmap
    d = latlong.texel_directions(*rad.shape[:2])[1:-1]
    assert np.abs(eval_emitter(emitter, d) - rad[1:-1]).max() < MITSUBA_FLOAT32_TOL
    assert np.abs(latlong.bilinear_lookup(rad, d) - rad[1:-1]).max() < FLOAT64_TOL


def test_pole_rows_are_zenith_and_nadir() -> None:
    rad = np.random.default_rng(3).random((9, 18, 3)).astype(np.float32)
    rad[0], rad[-1] = (0.9, 0.8, 0.7), (0.1, 0.2, 0.3)
    emitter = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(rad)})
    poles = np.array([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]])
    expected = np.array([[0.9, 0.8, 0.7], [0.1, 0.2, 0.3]])
    assert np.abs(eval_emitter(emitter, poles) - expected).max() < MITSUBA_FLOAT32_TOL
    assert np.abs(latlong.bilinear_lookup(rad, poles) - expected).max() < MITSUBA_FLOAT32_TOL


def test_axis_conventions() -> None:
    """y up; u = φ/2π = 0 is −z, u = ¼ is +x (module docstring)."""
    cases = [((0.0, 0.0), (0, 1, 0)), ((np.pi, 0.0), (0, -1, 0)), ((np.pi / 2, 0.0), (0, 0, -1)),
             ((np.pi / 2, np.pi / 2), (1, 0, 0)), ((np.pi / 2, np.pi), (0, 0, 1)),
             ((np.pi / 2, 1.5 * np.pi), (-1, 0, 0))]
    for (theta, phi), d in cases:
        got = latlong.spherical_to_direction(np.array(theta), np.array(phi))
        assert np.abs(got - np.array(d, dtype=float)).max() < FLOAT64_TOL, (theta, phi)


@pytest.mark.parametrize("shape", [(9, 18), (64, 128), (513, 1024)])
def test_texel_solid_angles_tile_the_sphere(shape: tuple[int, int]) -> None:
    dw = latlong.texel_solid_angles(*shape)
    assert dw.shape == shape
    assert (dw > 0).all()
    assert abs(dw.sum() - 4 * np.pi) < FLOAT64_TOL


def test_direction_spherical_round_trip() -> None:
    rng = np.random.default_rng(11)
    theta = rng.uniform(1e-3, np.pi - 1e-3, 5000)
    phi = rng.uniform(0.0, 2 * np.pi, 5000)
    d = latlong.spherical_to_direction(theta, phi)
    assert np.abs(np.linalg.norm(d, axis=-1) - 1).max() < FLOAT64_TOL
    t2, p2 = latlong.direction_to_spherical(d)
    assert np.abs(t2 - theta).max() < 1e-9  # arccos near θ ≈ 1e-3 loses ~1/sin θ of float64's 1e-16
    assert np.abs(np.angle(np.exp(1j * (p2 - phi)))).max() < 1e-9
    assert ((p2 >= 0) & (p2 < 2 * np.pi)).all()
    d2 = latlong.spherical_to_direction(*latlong.direction_to_spherical(d))
    assert np.abs(d2 - d).max() < FLOAT64_TOL


def test_fibonacci_normals_are_unit_and_uniform() -> None:
    n = 20001
    normals = latlong.fibonacci_sphere(n)
    assert normals.shape == (n, 3)
    assert np.abs(np.linalg.norm(normals, axis=1) - 1).max() < FLOAT64_TOL
    # A quasi-uniform set has mean ≈ 0 to O(1/n); measured |mean| ≤ 1.4e-6 at n = 4001.
    assert np.abs(normals.mean(axis=0)).max() < 1.0 / n
    # Spherical-cap discrepancy: the fraction inside a cap vs its area fraction (1 − cos α)/2. The
    # spherical Fibonacci lattice's cap discrepancy decays like n^(−3/4) (Aistleitner, Brauchart & Dick,
    # Discrete Comput. Geom. 48, 2012, numerical study); worst of 50 random caps measured 0.9·n^(−3/4).
    cap_tol = 2.0 * n ** -0.75
    rng = np.random.default_rng(5)
    for _ in range(50):
        axis = _random_directions(1, int(rng.integers(1 << 30)))[0]
        cos_a = rng.uniform(-1.0, 1.0)
        assert abs((normals @ axis > cos_a).mean() - (1 - cos_a) / 2) < cap_tol


def test_luminance_weights() -> None:
    """Rec. 709 weights sum to 1, so a grey (v, v, v) has luminance v."""
    assert latlong.luminance(np.array([1.0, 0.0, 0.0])) == pytest.approx(0.2126)
    assert latlong.luminance(np.array([0.0, 1.0, 0.0])) == pytest.approx(0.7152)
    assert latlong.luminance(np.array([0.0, 0.0, 1.0])) == pytest.approx(0.0722)
    assert latlong.luminance(np.full(3, 2.5)) == pytest.approx(2.5)


def test_row_sums_and_streamed_flux_equal_the_full_products() -> None:
    """The streamed helpers (row sums in blocks; Φ = Σ_i Ω_i Σ_j L_ij) equal the full-array forms."""
    from validate.scenes.environment import Environment

    rad = np.random.default_rng(5).uniform(0, 2, (33, 66, 3)).astype(np.float32)
    assert np.allclose(latlong.row_sums(rad, block_bytes=1000), rad.astype(np.float64).sum(axis=1), rtol=0,
                       atol=FLOAT64_TOL * 1e3)
    assert np.array_equal(latlong.row_solid_angles(33, 66), latlong.texel_solid_angles(33, 66)[:, 0])
    full = np.einsum("hwc,hw->c", rad.astype(np.float64), latlong.texel_solid_angles(33, 66))
    assert np.allclose(Environment("r", rad).total_flux(), full, rtol=FLOAT64_TOL, atol=0)
