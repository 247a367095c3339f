"""Convention audit of the shipping engines (three.js, Babylon.js) run in Node, and the ``engines``
experiment's claims.

Each engine is fed hand-made cube faces so that every convention is checked against a fact derived
independently of the engine: the OpenGL cube-map table (face orientation, handedness), ∫ max(0, n·ω) dω
= π (the π normalisation), IEEE half precision (half-float faces), Babylon's MAX_HDRI_VALUE = 4096
(its clamp) and the exact texel solid angle (texel weighting). Tests that need Node and the npm packages
skip with the reason when they are absent; the availability tests run everywhere.
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.geometry import cube_texel_directions, cube_texel_solid_angles
from validate.local_models import irradiance
from validate.local_models.irradiance.engines import UNAVAILABLE, cube_faces, worker
from validate.scenes import latlong, procedural

needs_node = pytest.mark.skipif(UNAVAILABLE is not None, reason=f"engines unavailable: {UNAVAILABLE}")

PATHS = [("three", "getIrradianceAt"), ("babylon", "sh"), ("babylon", "polynomial")]
AXES = np.concatenate([np.eye(3), -np.eye(3)])  # +x, +y, +z, −x, −y, −z
N = 16
TEXEL = (3, 10)  # an off-centre, off-diagonal texel: any flip or transpose of a face moves it
FLOAT32_PHI = 1e-5  # float32 shader arithmetic / six-digit constants, fraction of Φ (see engines_claims)
K_MAX = 17 / 16  # max of the SH9 kernel 3/32 + x/2 + 15x²/32 on [−1, 1]
HALF_EPS = 2.0**-11  # IEEE half: unit roundoff


def _e(engine: str, path: str, faces: np.ndarray, normals: np.ndarray, **settings) -> np.ndarray:
    return worker.engine_irradiance(engine, path, faces, normals, worker.FaceSettings(size=faces.shape[1], **settings),
                                    faces=faces)


def _one_texel(face: int, i: int, j: int, value=1.0, n: int = N) -> np.ndarray:
    faces = np.zeros((6, n, n, 3), np.float32)
    faces[face, i, j] = value
    return faces


def _band0_weight(engine: str, path: str, faces: np.ndarray) -> float:
    """The solid angle the engine gives a lone unit texel: the mean of E over the six axes is the band-0
    term Σ w L / 4 (band 1 is odd, band 2 sums to zero over the axes)."""
    return float(4.0 * _e(engine, path, faces, AXES)[:, 0].mean())


# -- orientation and handedness ---------------------------------------------------------------------
@needs_node
@pytest.mark.parametrize(("engine", "path"), PATHS)
@pytest.mark.parametrize("face", range(6))
def test_bright_texel_lands_where_opengl_puts_it(engine: str, path: str, face: int) -> None:
    """One bright texel per face: the engine's odd band (E(a) − E(−a))/2 over the axes points at the
    texel's direction in OpenGL's cube-map table [Segal & Akeley, Table 8.19]."""
    e = _e(engine, path, _one_texel(face, *TEXEL), AXES)[:, 0]
    g = (e[:3] - e[3:]) / 2
    got = g / np.linalg.norm(g)
    want = cube_texel_directions(N)[face, TEXEL[0], TEXEL[1]]
    assert np.arccos(np.clip(got @ want, -1, 1)) < 1e-4
    flipped = cube_texel_directions(N)[face, N - 1 - TEXEL[0], TEXEL[1]]  # a row flip would land here
    assert np.arccos(np.clip(got @ flipped, -1, 1)) > 0.1


# -- the π normalisation ----------------------------------------------------------------------------
@needs_node
@pytest.mark.parametrize(("engine", "path"), PATHS)
def test_constant_environment_gives_pi(engine: str, path: str) -> None:
    """L = 1 everywhere: E = ∫ max(0, n·ω) dω = π (not 1: the engines' E/π is multiplied back)."""
    n = latlong.fibonacci_sphere(200)
    e = _e(engine, path, np.ones((6, N, N, 3), np.float32), n)
    tol = 1e-4 if path == "polynomial" else FLOAT32_PHI  # the polynomial's DC constant 0.886277 (5.6e-5 high)
    assert np.max(np.abs(e / np.pi - 1)) < tol
    assert np.max(np.abs(e / np.pi / np.pi - 1)) > 0.5  # E/π taken for E would fail


# -- texel weighting and resolution -----------------------------------------------------------------
@needs_node
def test_texel_weights_three_approximates_babylon_integrates() -> None:
    """Corner vs centre texel of +Z: three.js weights by r⁻³ at the texel centre, Babylon by the exact
    solid angle (atan2 area element). At N = 16 the two differ by 0.25 % at the corner."""
    corner, centre = (0, 0), (N // 2, N // 2)
    omega = cube_texel_solid_angles(N)
    c = (np.arange(N) + 0.5) / N * 2 - 1
    r3 = (1 + c[:, None] ** 2 + c[None, :] ** 2) ** 1.5
    exact = omega[corner] / omega[centre]
    approx = r3[centre] / r3[corner]
    three, babylon = (_band0_weight(e, p, _one_texel(4, *corner)) / _band0_weight(e, p, _one_texel(4, *centre))
                      for e, p in (("three", "getIrradianceAt"), ("babylon", "sh")))
    assert abs(three / approx - 1) < 1e-6
    assert abs(babylon / exact - 1) < 1e-6
    assert abs(approx / exact - 1) > 1e-3  # the two conventions are distinguishable at this size


@needs_node
@pytest.mark.parametrize("n", [16, 32, 64])
def test_three_departs_from_exact_sh9_within_the_weight_bound(n: int) -> None:
    """|E_three − E_SH9(faces)| ≤ ρ(N) · 17/16 · Φ (+ six-digit constants), ρ(N) = max |w/Ω − 1| ∝ N⁻²."""
    from validate.experiments.engines.compute import three_weight_error

    env = procedural.disc_on_sky(64)
    faces = cube_faces.render_faces(env.radiance, n)
    normals = latlong.fibonacci_sphere(500)
    e = _e("three", "getIrradianceAt", faces, normals)
    exact = cube_faces.render_sh9(cube_faces.project_faces_sh9(faces), normals)
    phi = cube_faces.face_flux(faces)
    dev = np.max(np.abs(e - exact) / phi)
    assert dev <= K_MAX * three_weight_error(n) + FLOAT32_PHI
    assert three_weight_error(2 * n) < three_weight_error(n) / 3.5  # N⁻² convergence


# -- half floats and the clamp ------------------------------------------------------------------------
@needs_node
def test_half_float_faces() -> None:
    """Half-float faces move three.js's E by ≤ 2⁻¹¹ · 17/16 Φ; a texel above 65504 becomes ∞ and the SH is
    not finite, while Babylon clamps the ∞ to 4096."""
    env = procedural.bandlimited()
    faces = cube_faces.render_faces(env.radiance, N)
    normals = latlong.fibonacci_sphere(300)
    e32 = _e("three", "getIrradianceAt", faces, normals)
    e16 = _e("three", "getIrradianceAt", faces, normals, dtype="float16")
    dev = np.max(np.abs(e16 - e32) / cube_faces.face_flux(faces))
    assert 0 < dev <= HALF_EPS * K_MAX
    hot = faces.copy()
    hot[2, 5, 5] = 1e5
    assert not np.isfinite(_e("three", "getIrradianceAt", hot, normals, dtype="float16")).all()
    assert np.isfinite(_e("babylon", "sh", hot, normals, dtype="float16")).all()


@needs_node
def test_babylon_clamps_each_channel_at_4096() -> None:
    """A texel of (10⁵, 10³, 10³) is read by Babylon as (4096, 10³, 10³): brightness and hue change;
    without the clamp (MAX_HDRI_VALUE = ∞) it is read as given, as three.js does."""
    normals = latlong.fibonacci_sphere(100)
    big = _one_texel(2, 5, 5, np.array([1e5, 1e3, 1e3]))
    at_limit = _one_texel(2, 5, 5, np.array([4096.0, 1e3, 1e3]))
    e_big, e_lim = _e("babylon", "sh", big, normals), _e("babylon", "sh", at_limit, normals)
    assert np.allclose(e_big, e_lim, rtol=1e-6, atol=0)
    free = _e("babylon", "sh", big, normals, clamp=False)
    three = _e("three", "getIrradianceAt", big, normals)
    w_b = _band0_weight("babylon", "sh", _one_texel(2, 5, 5))
    w_t = _band0_weight("three", "getIrradianceAt", _one_texel(2, 5, 5))
    assert free[:, 0].mean() / free[:, 1].mean() == pytest.approx(100.0, rel=1e-5)
    assert e_big[:, 0].mean() / e_big[:, 1].mean() == pytest.approx(4.096, rel=1e-5)
    assert three[:, 0].mean() / w_t == pytest.approx(free[:, 0].mean() / w_b, rel=1e-5)


# -- Babylon's polynomial path ------------------------------------------------------------------------
@needs_node
def test_polynomial_path_applies_the_lobe_twice() -> None:
    """useSphericalHarmonics = false: E = SH9 with band l scaled by A_l/π (1, 2/3, 1/4)."""
    from validate.experiments.engines.compute import DOUBLE_LOBE

    env = procedural.two_tone(64)
    faces = cube_faces.render_faces(env.radiance, N)
    normals = latlong.fibonacci_sphere(300)
    c = cube_faces.project_faces_sh9(faces)
    e = _e("babylon", "polynomial", faces, normals)
    phi = cube_faces.face_flux(faces)
    assert np.max(np.abs(e - cube_faces.render_sh9(c * DOUBLE_LOBE, normals)) / phi) < 5e-5
    assert np.max(np.abs(e - cube_faces.render_sh9(c, normals)) / phi) > 1e-2


# -- the faces ---------------------------------------------------------------------------------------
def test_faces_are_texel_averages_that_keep_the_flux() -> None:
    """Constant map → every texel L; a 0.5° disc keeps its flux (splatted exactly) and lands on the texel
    that contains its direction."""
    const = procedural.constant()
    faces = cube_faces.render_faces(const.radiance, N)
    assert np.allclose(faces, const.radiance[0, 0], rtol=1e-6)
    env = procedural.near_directional(256)
    faces = cube_faces.render_faces(env.radiance, 32)
    assert np.max(np.abs(cube_faces.face_flux(faces) / env.total_flux() - 1)) < 1e-4
    hot = np.unravel_index(np.argmax(faces[..., 1]), faces.shape[:3])
    rows, cols = np.nonzero(env.radiance[..., 1] == env.radiance[..., 1].max())
    sun = latlong.texel_directions(env.height, env.width)[rows[0], cols[0]]
    texel = cube_texel_directions(32)[hot]
    assert np.degrees(np.arccos(np.clip(sun @ texel, -1, 1))) < 90 / 32 * 1.5  # within one texel


# -- the registered techniques and the worker -------------------------------------------------------
@needs_node
def test_registered_techniques_follow_the_contract() -> None:
    env = procedural.two_tone(64)
    normals = latlong.fibonacci_sphere(50)
    names = [t.name for t in irradiance if t.meta.get("engine")]
    assert names == ["three_sh", "babylon_sh", "babylon_polynomial"]
    for name in names:
        assert irradiance.call(name, env.radiance, normals).shape == (50, 3)


@needs_node
def test_worker_errors_are_one_line() -> None:
    with pytest.raises(ValidateError, match=r"engine three: no projection under key nope"):
        worker.evaluate("three", "nope", "getIrradianceAt", np.zeros((1, 3)))
    w = worker.worker("babylon")
    with pytest.raises(ValidateError, match=r"engine babylon: expected"):
        w.request({"op": "project", "key": "bad", "size": 4, "type": "float32", "clamp": True}, b"\0" * 16)


def test_without_node_nothing_is_registered(tmp_path: Path) -> None:
    """No ``node`` on PATH: the techniques are not registered (the rest of the family is unchanged)."""
    env = {k: v for k, v in os.environ.items() if k != "VALIDATE_NODE"}
    env["PATH"] = str(tmp_path)
    code = ("from validate.local_models import irradiance\n"
            "from validate.local_models.irradiance.engines import UNAVAILABLE\n"
            "print(sorted(t.name for t in irradiance if t.meta.get('engine')), 'sh9' in irradiance)\n"
            "print(UNAVAILABLE)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                         cwd=Path(__file__).resolve().parents[2], timeout=120)
    assert out.returncode == 0, out.stderr
    first, reason = out.stdout.strip().splitlines()[:2]
    assert first == "[] True"
    assert "Node.js not found" in reason


def test_importing_starts_no_node_process() -> None:
    code = ("import validate.local_models, validate.experiments\nvalidate.experiments.discover()\n"
            "from validate.local_models.irradiance.engines import worker\nprint(len(worker._WORKERS))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=Path(__file__).resolve().parents[2], timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "0"


def test_missing_packages_are_named(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(worker, "node_executable", lambda: "/usr/bin/node")
    monkeypatch.setattr(worker, "package_dir", lambda engine: None)
    why = worker.unavailable_reason()
    assert "validate setup --engines" in why and "@babylonjs/core" in why


def test_experiment_skips_with_the_reason(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    from validate.experiments import run_experiment
    from validate.experiments.base import Context

    compute = importlib.import_module("validate.experiments.engines.compute")  # the package's `compute` is the function
    monkeypatch.setattr(compute, "UNAVAILABLE", "Node.js not found on PATH")
    ctx = Context(out_dir=tmp_path, quick=True, show_progress=False)
    ctx._env_cache["envs"] = ([procedural.two_tone(64), procedural.near_directional(256)], [])
    res = run_experiment("engines", ctx)
    assert res.data["skipped"] == "Node.js not found on PATH" and "Node.js not found" in res.summary
    assert [c.id for c in res.claims] == ["engines.faces.flux"]  # the faces need no Node
    assert res.claims[0].passed and res.claims[0].power.fails


# -- the experiment's claims --------------------------------------------------------------------------
@needs_node
def test_claims_pass_and_their_power_checks_fail() -> None:
    """On four built-ins (below the clamp): every claim passes and every perturbed claim fails."""
    from validate.experiments.engines.claims import claims
    from validate.experiments.engines.compute import Measurements, measure_environment, named_environments
    from validate.experiments.engines.report import findings
    from validate.experiments.engines.settings import Settings

    settings = Settings(normals=600, cells=32, face_size=worker.FACE_SIZE, sweep_sizes=(32,))
    envs = [procedural.constant(), procedural.two_tone(64), procedural.bandlimited(), procedural.disc_on_sky(64),
            procedural.near_directional(256)]
    m = Measurements(settings, {e.name: measure_environment(e, settings) for e in envs})
    m.named = named_environments(m.environments)
    cs = claims(m)
    ids = {c.id for c in cs}
    assert {"engines.faces.flux", "engines.three_sh.equals_faces_sh9", "engines.babylon_sh.equals_faces_sh9",
            "engines.babylon_polynomial.double_lobe", "engines.three_sh.bound.max",
            "engines.babylon_sh.pi_normalisation", "engines.three_sh.own_faces.equals_faces_sh9",
            "engines.babylon_sh.own_faces.equals_faces_sh9"} <= ids
    for c in cs:
        assert c.passed, (c.id, c.measured, c.threshold)
        assert c.power is not None and c.power.fails, (c.id, c.power)
        assert "issue" not in c.source.lower()
    assert any("lobe twice" in f for f in findings(m))
    assert sum("Issue 21 item 5" in f for f in findings(m)) == 2  # one per engine fed from its own faces
