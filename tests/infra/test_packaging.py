"""The package installs whole, and a checkout alone passes its tests.

* The wheel built from this tree holds every file under ``validate/`` that git tracks (shaders, pages, engine
  scripts, templates, tables, the engines' lock file): a file the code reads but the wheel lacks fails here.
* That wheel, installed into a fresh venv outside the checkout, runs experiments that read package data
  (``listings``: the seeds' shaders; ``hemisphere``) and its ``setup --check`` names what is missing.
* A copy of the checkout with no ``../shared`` beside it: ``make test`` points at no missing probes folder, and
  the tests whose input is a probe file pass there.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def _tracked(prefix: str) -> list[str]:
    if shutil.which("git") is None or not (REPO / ".git").exists():
        pytest.skip("not a git checkout: the tracked files are unknown")
    out = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard", prefix], cwd=REPO,
                         capture_output=True, text=True, check=True).stdout.split()
    return [f for f in out if (REPO / f).is_file()]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The wheel of this tree (``pip wheel . --no-deps``, built from a copy so the tree gets no build folder)."""
    src = tmp_path_factory.mktemp("src")
    for f in _tracked(".") + ["MANIFEST.in", "pyproject.toml", "README.md"]:
        if (REPO / f).is_file() and (f.startswith("validate/") or "/" not in f):
            (src / f).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(REPO / f, src / f)
    out = tmp_path_factory.mktemp("wheel")
    r = subprocess.run([sys.executable, "-m", "pip", "wheel", str(src), "--no-deps", "--no-build-isolation", "-q",
                        "-w", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    [whl] = out.glob("validate-*.whl")
    return whl


def missing_from(whl: Path, files: list[str]) -> list[str]:
    names = set(zipfile.ZipFile(whl).namelist())
    return sorted(f for f in files if f not in names)


def test_wheel_ships_every_file_under_validate(wheel: Path) -> None:
    files = [f for f in _tracked("validate") if "__pycache__" not in f and not f.endswith(".pyc")]
    data = [f for f in files if not f.endswith(".py")]
    assert {Path(f).suffix for f in data} >= {".glsl", ".frag", ".vert", ".mjs", ".html", ".j2", ".js", ".json"}
    assert missing_from(wheel, files) == []
    assert not [n for n in zipfile.ZipFile(wheel).namelist() if n.endswith(".pyc") or "__pycache__" in n]


def test_the_check_catches_an_unshipped_file(wheel: Path) -> None:
    """The comparison above names a file the wheel lacks (here one that cannot be in it)."""
    assert missing_from(wheel, ["validate/local_models/brdf/not_shipped.glsl"]) == [
        "validate/local_models/brdf/not_shipped.glsl"]


@pytest.fixture(scope="module")
def installed(wheel: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A fresh venv outside the checkout holding only the wheel; its dependencies are this interpreter's (a
    ``.pth`` line, so nothing downloads and the checkout's editable install is not seen)."""
    venv = tmp_path_factory.mktemp("venv")
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    py = venv / "bin" / "python"
    site = Path(subprocess.run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                               capture_output=True, text=True, check=True).stdout.strip())
    deps = [p for p in sys.path if p.endswith("site-packages")]
    (site / "_validate_deps.pth").write_text("\n".join(deps) + "\n")
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-index", "--target", str(site),
                    str(wheel)], check=True, capture_output=True)
    return py


def _run_installed(py: Path, cwd: Path, *args: str, **env: str) -> subprocess.CompletedProcess[str]:
    base = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VALIDATE_PROBES")}
    return subprocess.run([str(py), *args], cwd=cwd, capture_output=True, text=True, env={**base, **env},
                          timeout=600)


def test_installed_wheel_runs_outside_the_checkout(installed: Path, tmp_path: Path) -> None:
    r = _run_installed(installed, tmp_path, "-c", "import validate; print(validate.__file__)")
    assert r.returncode == 0 and not r.stdout.strip().startswith(str(REPO)), r.stdout + r.stderr
    r = _run_installed(installed, tmp_path, "-m", "validate", "run", "listings", "hemisphere", "--quick",
                       "--no-progress", "--strict", "--out", str(tmp_path / "out"))
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert "listings:" in r.stdout and "hemisphere:" in r.stdout and (tmp_path / "out" / "results.json").is_file()


def test_installed_setup_check_names_missing_engines(installed: Path, tmp_path: Path) -> None:
    r = _run_installed(installed, tmp_path, "-m", "validate", "setup", "--engines", "--check",
                       VALIDATE_HOME=str(tmp_path / "home"))
    assert r.returncode == 1, r.stdout + r.stderr
    line = next(x for x in r.stdout.splitlines() if " engines " in x)
    assert "MISSING" in line and "three absent (pinned" in line and str(tmp_path / "home") in line
    assert not (tmp_path / "home").exists()  # --check installs nothing


def test_checkout_without_shared_passes_its_probe_tests(tmp_path: Path) -> None:
    """``make test`` of a checkout with no ``../shared`` beside it: no VALIDATE_PROBES pointing at a missing folder,
    and the tests whose input is a probe file (the CLI's refusals) pass in it."""
    if shutil.which("make") is None:
        pytest.skip("make not found")
    clone = tmp_path / "checkout"  # tmp_path/shared does not exist
    for f in _tracked("."):
        (clone / f).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(REPO / f, clone / f)
    env = {k: v for k, v in os.environ.items() if k not in ("VALIDATE_PROBES", "PROBES", "MAKEFLAGS")}
    dry = subprocess.run(["make", "-n", "test", "report"], cwd=clone, capture_output=True, text=True, env=env)
    assert dry.returncode == 0, dry.stderr
    runs = [x for x in dry.stdout.splitlines() if "-m pytest" in x or "-m validate all" in x]
    assert len(runs) == 2 and not any("probes" in x.lower() for x in runs), runs
    r = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "tests/infra/test_cli.py",
                        "-k", "probe"], cwd=clone, capture_output=True, text=True,
                       env={**env, "PYTHONPATH": str(clone)}, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:]
    assert " passed" in r.stdout.splitlines()[-1] and "failed" not in r.stdout.splitlines()[-1]
