"""The public pytest API ``validate.testing`` and the example that uses it (examples/test_my_model.py).

Thresholds: two-tone and band-limited lighting are represented exactly by SH9 (two-tone E is linear
in cos β; band-limited is order ≤ 2), so the built-in ``sh9`` technique's error there is quadrature
noise, measured ≤ 2·10⁻⁵ Φ — tested against the experiment's own 0.1 % exactness threshold. A
handedness bug (x → −x) on the x-asymmetric disc_on_sky is off by > 5 % Φ (measured 20 %).
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from validate import testing
from validate.errors import ValidateError
from validate.experiments.sh9.claims import BANDLIMITED_EXACT
from validate.local_models.irradiance import sh_truncated

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "test_my_model.py"
# the deliberately wrong variant of the example: its lat-long directions built z-up (a convention bug)
CORRECT_LINE = "    d = np.stack([np.sin(p) * np.sin(t), np.cos(t), -np.cos(p) * np.sin(t)], axis=-1)"
WRONG_LINE = "    d = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)"
HANDEDNESS_ERROR = 0.05  # a mirrored model on disc_on_sky errs by more than this (measured 0.2)


def mirrored_sh9(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return sh_truncated.sh9(radiance, normals * np.array([-1.0, 1.0, 1.0]))


@pytest.fixture(scope="module")
def exact_result() -> testing.CheckResult:
    return testing.check_irradiance("sh9", environments=("two_tone", "bandlimited"), normals=500)


def test_check_irradiance_measures_every_metric_per_environment(exact_result) -> None:
    r = exact_result
    assert r.technique == "sh9" and r.family == "irradiance"
    assert set(r.environments) == {"two_tone", "bandlimited"}
    assert set(r.metrics) == {"flux_luminance", "flux_rgb", "relative", "peak"}
    assert r.flux_luminance.max + r.flux_luminance.max_uncertainty < BANDLIMITED_EXACT
    assert r["bandlimited"].flux_rgb.max < BANDLIMITED_EXACT
    worst = max(r["two_tone"].flux_luminance.max, r["bandlimited"].flux_luminance.max)
    assert r.flux_luminance.max == worst  # r.<metric> is the worst environment
    assert 0 < r.flux_luminance.max_uncertainty < BANDLIMITED_EXACT  # the reference's, propagated
    assert "two_tone.flux_luminance" in repr(r)
    with pytest.raises(AttributeError, match="no metric"):
        _ = r.not_a_metric


def test_a_wrong_model_is_caught() -> None:
    r = testing.check_irradiance(mirrored_sh9, environments=("disc_on_sky",), normals=500)
    assert r.technique == "mirrored_sh9"
    assert r.flux_luminance.max > HANDEDNESS_ERROR


def test_contract_violations_name_the_technique() -> None:
    with pytest.raises(ValidateError, match=r"technique 'bad_shape' \(irradiance\): returned shape"):
        testing.check_irradiance(lambda rad, n: np.zeros((len(n), 2)), environments=("constant",), normals=64,
                                 name="bad_shape")
    with pytest.raises(ValidateError, match="non-finite"):
        testing.check_irradiance(lambda rad, n: np.full((len(n), 3), np.nan), environments=("constant",), normals=64)
    with pytest.raises(ValidateError, match="normals"):
        testing.check_irradiance(sh_truncated.sh9, normals=3)


def test_missing_probe_skips_or_errors(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("VALIDATE_PROBES", str(tmp_path))
    with pytest.raises(testing.MissingProbe, match=r"no_such_probe: light probe not found .*VALIDATE_PROBES"):
        testing.check_irradiance(sh_truncated.sh9, environments=("no_such_probe",), missing="error")
    with pytest.raises(pytest.skip.Exception, match="no_such_probe"):
        testing.check_irradiance(sh_truncated.sh9, environments=("no_such_probe",))
    with pytest.raises(testing.MissingProbe, match="probe file not found"):
        testing.find_probe(str(tmp_path / "absent.exr"))


def _pytest(args: list[str], cwd: Path, probes_dir: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, VALIDATE_PROBES=str(probes_dir))
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *args], cwd=cwd,
                          env=env, capture_output=True, text=True, timeout=600)


@pytest.mark.probes
def test_example_passes_from_the_checkout(probes_dir: Path) -> None:
    """``python -m pytest examples/`` from the repository root, as a user would run it."""
    out = _pytest(["examples/"], REPO, probes_dir)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "1 passed" in out.stdout


@pytest.mark.probes
def test_example_fails_on_a_wrong_model(tmp_path: Path, probes_dir: Path) -> None:
    """The same example with the lat-long directions built z-up (a convention bug) must fail."""
    source = EXAMPLE.read_text()
    assert CORRECT_LINE in source, "the example changed: update CORRECT_LINE"
    (tmp_path / "test_wrong_model.py").write_text(source.replace(CORRECT_LINE, WRONG_LINE))
    out = _pytest(["test_wrong_model.py"], tmp_path, probes_dir)
    assert out.returncode == 1, out.stdout + out.stderr
    assert "1 failed" in out.stdout and "flux_luminance" in out.stdout


def test_example_is_self_contained() -> None:
    """The example imports only numpy and validate.testing (it must run outside this repository)."""
    tree = ast.parse(EXAMPLE.read_text())
    modules = {n.module if isinstance(n, ast.ImportFrom) else n.names[0].name
               for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom))}
    assert modules == {"__future__", "numpy", "validate.testing"}


CHECKS = {"check_specular": "ibl", "check_arealight": "arealights", "check_shadow": "shadows", "check_brdf": "brdfs",
          "check_uberlight": "uberlight"}


@pytest.mark.parametrize("name", sorted(CHECKS))
def test_every_family_check_is_its_experiments_check_module(name: str) -> None:
    """validate.testing imports each experiment's ``check`` module directly: the public function is that
    module's function (the same object — behind the thin wrapper that also accepts a ``.glsl`` path — no
    module-name strings)."""
    import importlib

    check = importlib.import_module(f"validate.experiments.{CHECKS[name]}.check")
    assert name in testing.__all__ and getattr(testing, name).__wrapped__ is getattr(check, name)


def test_nothing_below_testing_imports_it() -> None:
    """No module of the validate package other than the CLI imports validate.testing (no loop back up)."""
    for path in (REPO / "validate").rglob("*.py"):
        if path.parent.name in ("testing", "cli"):
            continue
        tree = ast.parse(path.read_text())
        for n in ast.walk(tree):
            if isinstance(n, ast.ImportFrom):
                mod = "." * n.level + (n.module or "")
                assert not mod.endswith("testing") and "testing" not in [a.name for a in n.names if n.level], path
            elif isinstance(n, ast.Import):
                assert all(a.name != "validate.testing" for a in n.names), path
