"""Each engine's own panorama → cube path (issue 21 item 5), checked against facts the engine code does not
supply: the pixels of the panorama (Babylon samples, it does not average), the direction of a bright spot in
Mitsuba's lat-long convention (each engine's frame), Babylon's MAX_HDRI_VALUE = 4096 (its clamp, on the faces
it made itself) and the exact texel solid angle (the SH9 of those faces)."""

from __future__ import annotations

import numpy as np
import pytest

from validate.geometry import cube_texel_solid_angles
from validate.local_models.irradiance.engines import UNAVAILABLE, cube_faces, own_faces, worker
from validate.scenes import latlong

needs_node = pytest.mark.skipif(UNAVAILABLE is not None, reason=f"engines unavailable: {UNAVAILABLE}")
AXES = np.concatenate([np.eye(3), -np.eye(3)])
H, W, N = 128, 256, 32
FLOAT32_PHI = 1e-5  # float32 shader arithmetic, fraction of Φ (engines claims)


def _sun_map(direction: np.ndarray, value: float = 1e3, background: float = 1.0) -> np.ndarray:
    """A panorama of ``background`` with the pixel nearest to ``direction`` (Mitsuba's convention) at ``value``."""
    m = np.full((H, W, 3), background, np.float32)
    d = latlong.texel_directions(H, W)
    i, j = np.unravel_index(np.argmax(d @ direction), (H, W))
    m[i, j] = value
    return m


@needs_node
def test_babylon_samples_panorama_pixels_unaveraged() -> None:
    """Every texel of Babylon's own faces is one pixel of the panorama, exactly (nearest, no filtering)."""
    pano = np.random.default_rng(3).uniform(1.0, 2.0, (H, W, 3)).astype(np.float32)
    faces = own_faces.own_faces("babylon", pano, N)
    assert faces.shape == (6, N, N, 3)
    pixels = {tuple(p) for p in pano.reshape(-1, 3)}
    assert all(tuple(t) in pixels for t in faces.reshape(-1, 3))
    assert len({tuple(t) for t in faces.reshape(-1, 3)}) > 0.9 * 6 * N * N  # distinct pixels, not one repeated


def test_three_transcription_keeps_a_constant_and_interpolates() -> None:
    """Bilinear: a constant panorama stays constant; each texel lies within the panorama's range."""
    assert np.allclose(own_faces.three_equirect_faces(np.full((H, W, 3), 2.5, np.float32), N), 2.5)
    pano = np.random.default_rng(4).uniform(1.0, 2.0, (H, W, 3)).astype(np.float32)
    f = own_faces.three_equirect_faces(pano, N)
    assert f.min() >= 1.0 and f.max() <= 2.0 and len(np.unique(f)) > 0.9 * f.size


@needs_node
@pytest.mark.parametrize("engine", ["three", "babylon"])
def test_orientation_puts_the_sun_where_mitsuba_does(engine: str) -> None:
    """A lone bright pixel at a Mitsuba direction s: the engine's odd band (E(a) − E(−a))/2, asked at Aᵀa, points
    at s (within the pixel and texel sizes); A is a signed permutation."""
    a, fit = own_faces.orientation(engine, N)
    assert fit < 0.05 and np.allclose(np.abs(a) @ np.ones(3), 1) and abs(abs(np.linalg.det(a)) - 1) < 1e-12
    s = np.array([0.48, 0.6, -0.64])
    s /= np.linalg.norm(s)
    e = own_faces.own_irradiance(engine, _sun_map(s), AXES, N)[:, 0]
    g = (e[:3] - e[3:]) / 2
    assert np.degrees(np.arccos(g @ s / np.linalg.norm(g))) < 3.0  # texel 90°/32 ≈ 2.8°


@needs_node
def test_the_clamp_both_ways() -> None:
    """One panorama pixel of 10⁴ W/(m²·sr) that Babylon's nearest sampling hits near a face centre: Babylon's own
    faces hold 10⁴ (> 4096, clamped), the suite's texel-averaged faces hold about 10⁴ Ω_pixel/Ω_texel < 4096. The
    engine equals the exact SH9 of its own faces clipped to [0, 4096], and not of the unclipped ones."""
    pano = np.ones((H, W, 3), np.float32)
    idx = np.arange(H * W, dtype=np.float32).reshape(H, W)
    coded = np.repeat(idx[..., None], 3, axis=-1) + 1.0
    hit = own_faces.own_faces("babylon", coded, N)[0, N // 2, N // 2, 0] - 1.0  # the pixel Babylon takes there
    i, j = divmod(int(hit), W)
    pano[i, j] = 1e4
    own = own_faces.own_faces("babylon", pano, N)
    suite = cube_faces.render_faces(pano, N)
    assert own.max() == pytest.approx(1e4) and suite.max() < 4096.0
    omega_pixel = latlong.row_solid_angles(H, W)[i]
    assert suite.max() < 1e4 * omega_pixel / cube_texel_solid_angles(N).min()
    n = latlong.fibonacci_sphere(300)
    e = own_faces.own_irradiance("babylon", pano, n, N)
    flux = cube_faces.face_flux(own)
    wn = own_faces.to_engine_frame("babylon", n, N)
    clipped = cube_faces.render_sh9(cube_faces.project_faces_sh9(np.clip(own, 0, 4096)), wn)
    free = cube_faces.render_sh9(cube_faces.project_faces_sh9(own), wn)
    assert np.max(np.abs(e - clipped) / flux) < FLOAT32_PHI
    assert np.max(np.abs(e - free) / flux) > 100 * FLOAT32_PHI
    e_free = own_faces.own_irradiance("babylon", pano, n, N, clamp=False)
    assert np.max(np.abs(e_free - free) / flux) < FLOAT32_PHI


@needs_node
def test_three_own_faces_go_through_three() -> None:
    """three.js on the transcribed faces equals the exact SH9 of those faces within its weight bound ρ(N)·17/16."""
    from validate.experiments.engines.compute import three_weight_error

    pano = _sun_map(np.array([0.0, 0.8, 0.6]), value=50.0)
    n = latlong.fibonacci_sphere(300)
    faces = own_faces.own_faces("three", pano, N)
    e = own_faces.own_irradiance("three", pano, n, N)
    exact = cube_faces.render_sh9(cube_faces.project_faces_sh9(faces), own_faces.to_engine_frame("three", n, N))
    flux = cube_faces.face_flux(faces)
    assert np.max(np.abs(e - exact) / flux) < 17 / 16 * three_weight_error(N) + 1e-5
    assert worker.worker("three").proc is not None
