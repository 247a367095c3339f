"""Built-in environments are what their docstrings say (positions, positivity, flux)."""

from __future__ import annotations

import numpy as np
import pytest

from validate.scenes import latlong, procedural

# A baked sun is area-averaged into ~1-2 texels of a 256-row map (0.7° each): its brightest texel
# must lie within two texels of the intended direction.
SUN_POSITION_TOL_DEG = 1.5


@pytest.mark.parametrize("elevation", procedural.SUN_ELEVATIONS_DEG)
def test_sunsky_sun_and_zenith_are_where_intended(elevation: float) -> None:
    env = procedural.sunsky(elevation, height=256, supersample=2)
    y = latlong.luminance(env.radiance)
    i, j = np.unravel_index(np.argmax(y), y.shape)
    d = latlong.texel_directions(256, 512)[i, j]
    want = procedural.direction_from_elevation(elevation, 45.0)
    assert np.degrees(np.arccos(np.clip(d @ want, -1, 1))) < SUN_POSITION_TOL_DEG
    assert y[: 128].mean() > 0 and y[129:].max() == 0.0  # sky above the horizon, black ground below


def test_disc_and_near_directional_are_centred() -> None:
    for env, want, half in ((procedural.disc_on_sky(128), procedural.direction_from_elevation(35.0, 30.0), 4.0),
                            (procedural.near_directional(256), procedural.direction_from_elevation(40.0, -60.0), 0.5)):
        y = latlong.luminance(env.radiance) * latlong.texel_solid_angles(env.height, env.width)
        d = latlong.texel_directions(env.height, env.width)
        c = (y[..., None] * d).sum(axis=(0, 1))
        c /= np.linalg.norm(c)
        assert np.degrees(np.arccos(np.clip(c @ want, -1, 1))) < half + 1.0, env.name


def test_bandlimited_is_positive_and_matches_its_coefficients() -> None:
    env = procedural.bandlimited()
    assert env.radiance.min() > 0.1
    flux = env.total_flux()
    # Φ = ∫ Σ c_lm Y_lm = √(4π) c_00 (texel quadrature of a smooth function: ~1e-4 relative)
    assert np.allclose(flux, np.sqrt(4 * np.pi) * procedural.BANDLIMITED_SH[0], rtol=1e-3)
