"""The layers of ../shared/ARCHITECTURE.md hold: ``lint-imports`` (PyPI import-linter) keeps every contract of
``[tool.importlinter]`` in pyproject.toml (imports run down; a model never imports the reference, the reference
never imports a model). One subprocess, ~1 s: grimp parses the package's sources, nothing is imported."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
CONTRACT_IDS = ("layers", "models-vs-reference")


def _lint_imports() -> str:
    exe = shutil.which("lint-imports", path=str(Path(sys.executable).parent)) or shutil.which("lint-imports")
    if exe is None:
        pytest.fail("lint-imports not found: pip install import-linter (it is in the test extras of pyproject.toml)")
    return exe


def test_import_contracts_are_kept() -> None:
    proc = subprocess.run([_lint_imports(), "--no-cache"], cwd=REPO, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert f"Contracts: {len(CONTRACT_IDS)} kept, 0 broken." in proc.stdout


@pytest.mark.parametrize("contract", CONTRACT_IDS)
def test_each_contract_is_configured(contract: str) -> None:
    """Both contracts exist (a deleted contract would otherwise pass silently)."""
    tomllib = pytest.importorskip("tomllib")  # Python ≥ 3.11

    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["importlinter"]
    assert contract in {c["id"] for c in config["contracts"]}
