"""Example: gate your own irradiance code on physics with ``validate.testing``.

Run from the checkout after set-up (``make test`` or ``scripts/setup.sh``)::

    .venv/bin/python -m pytest examples/

``my_sh9_irradiance`` stands for *your* model: here an order-2 spherical-harmonic irradiance written
from Ramamoorthi & Hanrahan 2001 (the projection L_lm = ∫ L Y_lm dω and the quadratic form of eq. 12)
in plain numpy, sharing no code with the suite. ``check_irradiance`` measures it against Mitsuba's ground
truth on a two-tone sky and on Debevec's Grace Cathedral probe (skipped, with the reason, when the
probe folder is absent: set ``VALIDATE_PROBES``).
"""

from __future__ import annotations

import numpy as np

from validate.testing import check_irradiance

# R&H 2001 eq. 12 constants.
C1, C2, C3, C4, C5 = 0.429043, 0.511664, 0.743125, 0.886227, 0.247708


def texel_directions_and_solid_angles(height: int, width: int) -> tuple[np.ndarray, np.ndarray]:
    """Directions (H, W, 3) and solid angles (H, W) of a lat-long map in Mitsuba's convention:
    y up, row i at θ = iπ/(H − 1), column j at φ = 2π(j + ½)/W, direction (sin φ sin θ, cos θ, −cos φ sin θ)."""
    theta = np.arange(height) * np.pi / (height - 1)
    phi = 2 * np.pi * (np.arange(width) + 0.5) / width
    t, p = np.meshgrid(theta, phi, indexing="ij")
    d = np.stack([np.sin(p) * np.sin(t), np.cos(t), -np.cos(p) * np.sin(t)], axis=-1)
    # each row stands for the band of θ halfway to its neighbours (clipped at the poles)
    edges = np.clip(np.concatenate([[0.0], (theta[:-1] + theta[1:]) / 2, [np.pi]]), 0, np.pi)
    band = np.cos(edges[:-1]) - np.cos(edges[1:])
    return d, np.repeat(band[:, None] * 2 * np.pi / width, width, axis=1)


def my_sh9_irradiance(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Order-2 SH irradiance: project the map on the 9 basis functions, then R&H's quadratic form."""
    d, dw = texel_directions_and_solid_angles(*radiance.shape[:2])
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    basis = [0.282095 + 0 * x, 0.488603 * y, 0.488603 * z, 0.488603 * x, 1.092548 * x * y, 1.092548 * y * z,
             0.315392 * (3 * z * z - 1), 1.092548 * x * z, 0.546274 * (x * x - y * y)]
    L = [np.einsum("hwc,hw->c", radiance.astype(np.float64), b * dw) for b in basis]
    L00, L1m1, L10, L11, L2m2, L2m1, L20, L21, L22 = L
    nx, ny, nz = (normals[:, i : i + 1] for i in range(3))
    return (C1 * L22 * (nx * nx - ny * ny) + C3 * L20 * nz * nz + C4 * L00 - C5 * L20
            + 2 * C1 * (L2m2 * nx * ny + L21 * nx * nz + L2m1 * ny * nz)
            + 2 * C2 * (L11 * nx + L1m1 * ny + L10 * nz))


def test_my_sh9_meets_the_papers_figures() -> None:
    r = check_irradiance(my_sh9_irradiance, environments=("two_tone", "grace_probe"))
    # R&H 2001: SH9 irradiance errs by < 1 % on average and < 5 % at worst, relative to the total flux.
    # Demand that the bound (value + the reference's uncertainty) clears, on the worst environment.
    assert r.flux_luminance.max + r.flux_luminance.max_uncertainty < 0.05, r
    assert r.flux_luminance.mean + r.flux_luminance.mean_uncertainty < 0.01, r
    # the per-environment view
    assert r["grace_probe"].flux_luminance.mean < 0.01, r
