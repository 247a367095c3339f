"""Khronos's glTF Validator (npm ``gltf-validator``) on every ``.glb`` of ``scenes export``: 0 errors.

Warnings, infos and hints are listed in the assertion message, not failed. The validator can fail: a file whose
POSITION accessor states a wrong ``max`` is reported (ACCESSOR_MAX_MISMATCH). Skipped, with the reason, without
Node.js or the package (``python -m validate setup --engines``). ~3 s.
"""

from __future__ import annotations

from pathlib import Path

import pygltflib
import pytest

from validate.cli import main
from validate.scenes.khronos_validator import unavailable, validate_files

WHY = unavailable()
pytestmark = pytest.mark.skipif(WHY is not None, reason=f"glTF Validator: {WHY}")


@pytest.fixture(scope="module")
def exported(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    out = tmp_path_factory.mktemp("scenes")
    assert main(["scenes", "export", str(out), "--resolution", "16", "--set", "full"]) == 0
    return sorted(out.glob("*.glb"))


def test_export_validate_runs_the_validator_on_every_file(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    assert main(["scenes", "export", str(tmp_path), "--resolution", "16", "--validate"]) == 0
    n = len(list(tmp_path.glob("*.glb")))
    out = capsys.readouterr().out
    assert f"glTF Validator: {n} of {n} files valid (0 errors)" in out and out.count(": 0 errors,") == n


def test_every_exported_scene_is_valid_by_the_standards_own_tool(exported: list[Path]) -> None:
    reports = validate_files(exported)
    assert len(reports) == len(exported) >= 11
    notes = [f"{Path(r['file']).name}: {m['code']} (severity {m['severity']}) {m['pointer']}: {m['message']}"
             for r in reports for m in r["messages"]]
    assert [r["numErrors"] for r in reports] == [0] * len(reports), "\n".join(notes)
    print("\n".join(notes) or "no warnings, infos or hints")


def test_the_validator_reports_a_broken_file(exported: list[Path], tmp_path: Path) -> None:
    doc = pygltflib.GLTF2.load(str(exported[0]))
    doc.accessors[0].max = [v + 0.5 for v in doc.accessors[0].max]
    bad = tmp_path / "bad.glb"
    doc.save(str(bad))
    [r] = validate_files([bad])
    assert r["numErrors"] >= 1 and "ACCESSOR_MAX_MISMATCH" in {m["code"] for m in r["messages"]}
