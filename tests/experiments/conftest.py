"""Fixtures shared by the experiment tests."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest


@pytest.fixture
def grace_context(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, probes_dir: Path) -> Any:
    """A context whose only environment is the shared ``grace_probe`` (negative float noise clamped), with the
    reference cache in the test's own folder; skips when the probe is absent."""
    from validate.scenes.probes import load_probes

    monkeypatch.setenv("VALIDATE_CACHE", str(tmp_path / "cache"))
    envs, _ = load_probes(probes_dir, [], "auto", True, only_stems={"grace_probe"})
    if not envs:
        pytest.skip("shared probe grace_probe not found")

    class Ctx:
        def environments(self) -> tuple[list, list]:
            return envs, []

    return Ctx()
