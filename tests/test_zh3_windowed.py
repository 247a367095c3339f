"""ZH3 (stored, hallucinated), windowed SH9 and L1 Geomerics (validate.local_models.zh3, .windowed_sh).

Checked against properties that hold exactly (small lat-long maps; QUADRATURE_TOL is
the texel quadrature's leak into the coefficients): a radiance that is zonal about its own L1 axis up to
order 2 is represented exactly by ZH3 with the stored coefficient, so zh3_stored = sh9 there;
constant lighting gives E = πL for every technique; Geomerics' reconstruction has the exact mean R0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from validate.local_models import irradiance, sh, windowed_sh, zh3
from validate.scenes import latlong

# relative: texel quadrature of the SH projection on these small maps (32–64 rows) leaks ~10⁻⁴ into
# the coefficients (measured ≤ 2.7·10⁻⁴), plus float32 drjit evaluation
QUADRATURE_TOL = 1e-3


def zonal_map(axis: np.ndarray, height: int = 64) -> np.ndarray:
    """L(ω) = 1 + 0.5 t + 0.3 (3t² − 1), t = axis·ω: zonal about axis, order ≤ 2, positive."""
    d = latlong.texel_directions(height, 2 * height)
    t = d @ axis
    return np.repeat((1 + 0.5 * t + 0.3 * (3 * t * t - 1))[..., None], 3, axis=-1).astype(np.float32)


def test_zh3_stored_is_exact_for_zonal_lighting_about_the_l1_axis() -> None:
    axis = np.array([0.48, 0.6, -0.64])
    axis /= np.linalg.norm(axis)
    rad = zonal_map(axis)
    n = latlong.fibonacci_sphere(300)
    e_sh9 = sh.sh9(rad, n)
    e_zh3 = zh3.zh3_stored(rad, n)
    assert np.abs(e_zh3 - e_sh9).max() < QUADRATURE_TOL * np.abs(e_sh9).max()
    assert np.allclose(zh3.zonal_axis(sh.project_environment(rad, 2)), axis, atol=QUADRATURE_TOL)
    # power: hallucinating the zonal coefficient instead of storing it differs by far more
    assert np.abs(zh3.zh3_hallucinated(rad, n) - e_sh9).max() > 10 * QUADRATURE_TOL * np.abs(e_sh9).max()


@pytest.mark.parametrize("name", ["zh3_stored", "zh3_hallucinated", "sh9_hanning", "sh9_lanczos", "sh1_geomerics"])
def test_constant_lighting_gives_pi_l(name: str) -> None:
    rad = np.full((32, 64, 3), 0.7, dtype=np.float32)
    n = latlong.fibonacci_sphere(100)
    e = irradiance.call(name, rad, n)
    assert np.abs(e / (math.pi * 0.7) - 1).max() < QUADRATURE_TOL


def test_windows_are_sloans() -> None:
    assert [windowed_sh.hanning(l) for l in range(3)] == pytest.approx([1.0, 0.75, 0.25])
    assert [windowed_sh.lanczos(l) for l in range(3)] == pytest.approx([1.0, 0.826993, 0.413497], abs=1e-6)


def test_geomerics_mean_and_directional_limit() -> None:
    """Mean over the sphere = R0 (the irradiance's mean); ρ = 1: E = 4 R0 ((1 + n·d)/2)³ — the true
    E = 1 at n = d and 0 at n = −d for a unit directional light (R0 = ¼)."""
    d = np.array([0.0, 0.0, 1.0])
    coeffs = sh.eval_basis_numpy(d[None], 1)[0][:, None] * np.ones(3)  # a unit directional light's L1 SH
    n = latlong.fibonacci_sphere(20000)
    e = windowed_sh.geomerics_l1(coeffs, n)
    assert abs(e[:, 0].mean() - 0.25) < 1e-3  # Fibonacci quadrature of a smooth function
    ends = windowed_sh.geomerics_l1(coeffs, np.array([d, -d]))
    assert ends[0, 0] == pytest.approx(1.0, abs=1e-9) and ends[1, 0] == pytest.approx(0.0, abs=1e-9)
