"""Reproduce Ramamoorthi & Hanrahan 2001, Table 1 (SH9 of Grace Cathedral and Eucalyptus Grove).

The probe files are the captures R&H used but at another exposure, so one scale per probe is fitted
(validate.metrics.published.fit_exposure); ../shared/reference/README.md gives ≈ 3.19× (grace) and
≈ 9.97× (rnl). The table is in R&H's ``prefilter`` frame (+z towards the angular map's centre), our
environments in Mitsuba's (−z forward, y up): the two differ by z → −z, which flips the sign of the
coefficients odd in z: L10 (z), L2,−1 (yz) and L21 (xz).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from validate.local_models import sh
from validate.metrics.published import PUBLISHED_TOLERANCE, fit_exposure
from validate.scenes.probes import published_row, read_aliases, read_published_sh9

pytestmark = pytest.mark.probes

PROBES = {"grace_probe": ("grace", 3.19), "rnl_probe": ("eucalyptus_grove", 9.97)}
# README.md quotes the scales to 3 digits; ±1 % also absorbs the table's own rounding (2 decimals in
# the paper). Measured: grace 3.1903, rnl 9.9684.
SCALE_REL_TOL = 0.01
Z_FLIP = np.array([1, 1, -1, 1, 1, -1, 1, -1, 1], dtype=np.float64)[:, None]  # z → −z on L00…L22
# R&H's prefilter puts pixel (i, j) at u = (j − w/2)/(w/2), v = (w/2 − i)/(w/2) — the pixel's corner,
# not its centre (j + ½) — a half-pixel (0.18° at w = 1000) shift of every sample against our
# conversion, plus our resampling to 512 rows. Measured max |ΔL| / max L00: grace 5.7e-3, rnl 3.2e-3.
# With pixel centres (the same rule otherwise) the difference drops to 1.6e-4 / 4.1e-5.
HALF_PIXEL_TOL = 1e-2
CENTRED_TOL = 5e-4


@pytest.fixture(scope="module")
def table(reference_dir: Path) -> dict[str, np.ndarray]:
    published = read_published_sh9(reference_dir / "sh9_coefficients.csv")
    if not published:
        pytest.skip(f"sh9_coefficients.csv not found in {reference_dir}: set VALIDATE_REFERENCE")
    return {k: np.array([v[name] for name in sh.SH9_NAMES]) for k, v in published.items()}


def test_aliases(reference_dir: Path) -> None:
    aliases = read_aliases(reference_dir / "probe_aliases.csv")
    for stem, (row, _) in PROBES.items():
        assert aliases[stem][0] == row


@pytest.mark.parametrize("stem", list(PROBES))
def test_rh2001_table_reproduced(load_probe, table, stem: str) -> None:
    """SH9 by R&H's own rule (project_angular_rh2001) ≈ s · Table 1, max |c/s − t| ≤ 0.01 (the issue's
    threshold; measured 0.0022 grace, 0.0004 rnl)."""
    row, scale = PROBES[stem]
    env = load_probe(f"{stem}.hdr")
    assert published_row(env) == row  # recognised as one of the paper's probes
    fit = fit_exposure(sh.project_angular_rh2001(env.angular, 2), table[row], row)
    assert abs(fit.scale / scale - 1) < SCALE_REL_TOL, fit
    assert fit.max_deviation <= PUBLISHED_TOLERANCE, fit


def test_latlong_copy_is_not_a_published_probe(load_probe) -> None:
    assert published_row(load_probe("grace_probe_latlong.exr")) is None


def _rh2001_centred(angular: np.ndarray) -> np.ndarray:
    """R&H's angular-map rule with pixel centres (j + ½, i + ½): dω = (2π/w)² sinc θ, +z at the centre."""
    w = angular.shape[0]
    i, j = np.meshgrid(np.arange(w) + 0.5, np.arange(w) + 0.5, indexing="ij")
    u, v = (j - w / 2) / (w / 2), (w / 2 - i) / (w / 2)
    r = np.sqrt(u * u + v * v)
    inside = r <= 1.0
    theta, phi = np.pi * r[inside], np.arctan2(v[inside], u[inside])
    d = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1)
    dw = (2 * np.pi / w) ** 2 * np.sinc(theta / np.pi)
    return sh.project_samples(d, dw, angular[inside].astype(np.float64), 2)


@pytest.mark.parametrize("stem", list(PROBES))
def test_rh2001_frame_is_z_mirror_of_ours(load_probe, stem: str) -> None:
    env = load_probe(f"{stem}.hdr")
    ours = sh.project_environment(env.radiance, 2)  # Mitsuba lat-long, −z forward
    norm = np.abs(ours[0]).max()
    rh = sh.project_angular_rh2001(env.angular, 2)
    assert np.abs(Z_FLIP * rh - ours).max() / norm < HALF_PIXEL_TOL
    assert np.abs(Z_FLIP * _rh2001_centred(env.angular) - ours).max() / norm < CENTRED_TOL
    # and the flip matters: without it the z-odd coefficients disagree by far more
    assert np.abs(rh - ours).max() / norm > 10 * HALF_PIXEL_TOL
