"""Reproduce Ramamoorthi & Hanrahan 2001, Table 1 (SH9 of Grace Cathedral and Eucalyptus Grove).

The probe files are the captures R&H used but at another exposure, so one scale per probe is fitted
(validate.metrics.published.fit_exposure); validate/data/README.md (the shipped copy of the published
figures and their sources) gives ≈ 3.19× (grace) and ≈ 9.97× (rnl). The table is in R&H's ``prefilter``
frame (+z towards the angular map's centre), our environments in Mitsuba's (−z forward, y up): the two
differ by z → −z, which flips the sign of the coefficients odd in z: L10 (z), L2,−1 (yz) and L21 (xz).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from validate.local_models.irradiance import sh
from validate.metrics.published import PUBLISHED_TOLERANCE, fit_exposure
from validate.scenes.environment import Environment
from validate.scenes.probes import (
    package_reference_dir,
    published_row,
    published_status,
    read_aliases,
    read_published_sh9,
    reference_dir,
)

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


SHARED_REFERENCE = Path(__file__).resolve().parents[3] / "shared" / "reference"


def test_published_figures_ship_with_the_package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """From any folder, with VALIDATE_REFERENCE unset, the table and aliases come from validate/data."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("VALIDATE_REFERENCE", raising=False)
    assert reference_dir() == package_reference_dir()
    table = read_published_sh9()
    assert len(table) == 10 and all(len(v) == 9 for v in table.values())
    assert table["grace"]["L00"] == [0.78908, 0.4371, 0.54161]  # Rost, OpenGL Shading Language, Table 12.1
    assert read_aliases()["grace_probe"] == ("grace", "Grace Cathedral")
    assert (package_reference_dir() / "README.md").read_text().count("Ramamoorthi") >= 1


def test_shipped_copy_equals_the_shared_reference() -> None:
    if not SHARED_REFERENCE.is_dir():
        pytest.skip(f"{SHARED_REFERENCE} not present")
    for name in ("sh9_coefficients.csv", "probe_aliases.csv"):
        assert (package_reference_dir() / name).read_bytes() == (SHARED_REFERENCE / name).read_bytes(), name


def test_validate_reference_overrides(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "probe_aliases.csv").write_text("probe,debevec_file,name_in_table\nmine,my_probe,My Probe\n")
    monkeypatch.setenv("VALIDATE_REFERENCE", str(tmp_path))
    assert read_aliases() == {"my_probe": ("mine", "My Probe")}
    assert read_published_sh9() == {}  # no table there: nothing to compare, not an error


@pytest.mark.parametrize("filename, layout, why", [
    ("grace_probe.exr", "latlong", "latlong map, not the angular map"),
    ("grace_probe_latlong.exr", "latlong", "not the Debevec angular map grace_probe.hdr"),
    ("ict_grace_256x128.hdr", "latlong", "not the Debevec angular map grace_probe.hdr"),
    ("uffizi_probe-128.exr", "angular", "not the Debevec angular map uffizi_probe.hdr"),
])
def test_near_matches_say_why_they_are_not_compared(filename: str, layout: str, why: str) -> None:
    rad = np.ones((8, 16, 3), dtype=np.float32)
    env = Environment(Path(filename).stem, rad, kind="probe", source=Path("/probes") / filename, layout=layout,
                      angular=np.ones((8, 8, 3), dtype=np.float32) if layout == "angular" else None)
    key, reason = published_status(env)
    assert key is None and why in reason and filename in reason
    other = Environment("forest", rad, kind="probe", source=Path("/probes/forest_slope_1k.hdr"))
    assert published_status(other) == (None, None)


@pytest.fixture(scope="module")
def table() -> dict[str, np.ndarray]:
    """The shipped table (validate/data; VALIDATE_REFERENCE may point elsewhere)."""
    published = read_published_sh9()
    assert published, f"sh9_coefficients.csv missing from {reference_dir()}"
    return {k: np.array([v[name] for name in sh.SH9_NAMES]) for k, v in published.items()}


def test_aliases() -> None:
    aliases = read_aliases()
    for stem, (row, _) in PROBES.items():
        assert aliases[stem][0] == row


@pytest.mark.probes
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


@pytest.mark.probes
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


@pytest.mark.probes
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
