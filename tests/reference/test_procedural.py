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


def test_sh9_basis_is_rh2001_eq3() -> None:
    """The environment's own basis (independent of the model) has R&H 2001 eq. 3's constants, and
    equals the model's basis (validate.local_models.irradiance.sh) to float precision."""
    from validate.local_models.irradiance import sh

    d = latlong.fibonacci_sphere(200)
    y = procedural.sh9_basis(d)
    x_, y_, z_ = d.T
    six_decimals = 5e-7
    assert np.allclose(y[:, 0], 0.282095, atol=six_decimals)
    assert np.allclose(y[:, 1], 0.488603 * y_, atol=six_decimals)
    assert np.allclose(y[:, 6], 0.315392 * (3 * z_**2 - 1), atol=six_decimals)
    assert np.allclose(y[:, 8], 0.546274 * (x_**2 - y_**2), atol=six_decimals)
    assert np.abs(y - sh.eval_basis_numpy(d, 2)).max() < 1e-12


def test_near_directional_keeps_the_discs_flux() -> None:
    """Φ of the baked 0.5° disc = 2π(1 − cos α): measured 0.015 % short at 512 rows (the quick run uses
    512 rows too; at 256 rows the 6×6 stratified cell average loses 0.54 %). 0.05 % keeps the cap
    closed form (reference.closed_form.near_directional, 0.1 %) decidable."""
    env = procedural.builtin_environment("near_directional", quick=True)
    assert env.height == procedural.NEAR_DIRECTIONAL_HEIGHT
    alpha = np.radians(procedural.NEAR_DIRECTIONAL_HALF_ANGLE_DEG)
    assert np.allclose(env.total_flux() / (2 * np.pi * (1 - np.cos(alpha))), 1.0, atol=5e-4)


def test_builtin_environment_by_name() -> None:
    from validate.errors import ValidateError

    assert procedural.builtin_environment("constant").name == "constant"
    assert procedural.builtin_environment("two_tone", quick=True).height == 128
    with pytest.raises(ValidateError, match="unknown built-in environment 'nope'"):
        procedural.builtin_environment("nope")


def test_cell_average_on_the_caps_rows_equals_every_row() -> None:
    """The row restriction of a cap's cell average (theta_support) gives the same texels, bit for bit."""
    from validate.scenes.procedural import _cell_average, cap, direction_from_elevation

    for elevation, half in ((40.0, 3.0), (88.0, 5.0), (-30.0, 2.0)):
        inside = cap(direction_from_elevation(elevation, -60.0), half)
        polar = np.radians(90.0 - elevation)
        support = (polar - np.radians(half), polar + np.radians(half))
        full = _cell_average(64, 128, inside, 4)
        assert full.any() and np.array_equal(_cell_average(64, 128, inside, 4, support), full)
    # a wrong support (the cap's mirror image) loses the cap: the check can fail
    assert not _cell_average(64, 128, inside, 4, (np.pi - support[1], np.pi - support[0])).any()
