"""Negative texels: float noise is clamped by default (and noted), larger negatives are refused.

The bounds are :data:`validate.scenes.loaders.NEGATIVE_NOISE_RELATIVE` (|min| ≤ 0.05 × the mean
luminance) and :data:`~validate.scenes.loaders.NEGATIVE_NOISE_SHARE` (≤ 0.5 % of the texels); their
derivation from the shared probes is in the loaders' module docstring.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.scenes import loaders
from validate.scenes.probes import load_probes

H, W = 16, 32  # the smallest lat-long map the loader accepts


def _write(path: Path, arr: np.ndarray) -> Path:
    import mitsuba as mi

    mi.Bitmap(np.ascontiguousarray(arr, np.float32)).write(str(path))
    return path


def test_noise_is_clamped_by_default_and_noted(tmp_path: Path) -> None:
    arr = np.ones((H, W, 3), np.float32)
    arr[3, 4, 2] = -0.04  # 0.04 × the mean luminance 1: inside the 0.05 bound; 1 of 512 texels
    env = loaders.load_environment(_write(tmp_path / "noisy.exr", arr))
    assert env.radiance.min() == 0.0 and env.radiance[3, 4, 2] == 0.0
    assert env.clamped_negative is not None
    n, low = env.clamped_negative
    assert n == 1 and low == pytest.approx(-0.04, rel=1e-6)
    assert any(note.startswith(loaders.CLAMP_NOTE) and "float noise" in note for note in env.notes)


@pytest.mark.parametrize("case", ["deep", "widespread"])
def test_beyond_noise_is_refused_unless_asked(tmp_path: Path, case: str) -> None:
    arr = np.ones((H, W, 3), np.float32)
    if case == "deep":
        arr[3, 4, 2] = -0.06  # 0.06 × the mean: just beyond the relative bound, one texel
    else:
        arr.reshape(-1, 3)[:4, 0] = -1e-4  # tiny values, but 4 of 512 texels = 0.78 % > 0.5 %
    path = _write(tmp_path / f"{case}.exr", arr)
    with pytest.raises(ValidateError) as err:
        loaders.load_environment(path)
    assert str(path) in str(err.value) and "beyond float noise" in str(err.value)
    env = loaders.load_environment(path, clamp_negative=True)
    assert env.radiance.min() == 0.0 and env.clamped_negative is not None
    assert "--clamp-negative" in env.notes[0]


def test_folder_skips_beyond_noise_with_reason(tmp_path: Path) -> None:
    good = np.ones((H, W, 3), np.float32)
    bad = good.copy()
    bad[0, 0, 0] = -1.0
    good[5, 5, 1] = -1e-6
    _write(tmp_path / "good.exr", good)
    _write(tmp_path / "bad.exr", bad)
    envs, skipped = load_probes(tmp_path, [], "auto", False, log=lambda s: None)
    assert [e.name for e in envs] == ["good"] and envs[0].clamped_negative is not None
    assert [s[0] for s in skipped] == ["bad.exr"] and "beyond float noise" in skipped[0][1]
    with pytest.raises(ValidateError):  # an explicit --probe file: an error, not a skip
        load_probes(None, [tmp_path / "bad.exr"], "auto", False)


@pytest.mark.probes
def test_shared_probes_at_most_two_refused(probes_dir: Path) -> None:
    """Of the shared probes only the two Uffizi copies (masked corners at −1) are refused by default;
    the Blender worlds' negatives (≤ 1.4·10⁻² × mean, ≤ 0.16 % of texels) are clamped."""
    refused, clamped = [], []
    for path in loaders_files(probes_dir):
        arr = loaders.read_image(path)
        try:
            _, _, c = loaders.check_texels(arr, path, False)
        except ValidateError:
            refused.append(path.stem)
            continue
        if c is not None:
            clamped.append(path.stem)
    assert len(refused) <= 2, refused
    assert set(refused) <= {"uffizi_probe-128", "uffizi_probe-128_latlong"}, refused
    assert all(name.startswith("blender_world_") for name in clamped), clamped


def loaders_files(directory: Path) -> list[Path]:
    from validate.scenes.probes import probe_files

    return probe_files(directory)


def test_clamp_is_recorded_in_results_json(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    """``meta.environments[<name>].clamped_negative`` = {"texels", "min"}, and the CLI prints the note."""
    import json

    from validate import cli
    from validate.experiments.base import EXPERIMENTS
    from validate.scenes import procedural

    probes = tmp_path / "probes"
    probes.mkdir()
    arr = np.ones((H, W, 3), np.float32)
    arr[3, 4, 2] = -0.04
    _write(probes / "noisy.exr", arr)
    monkeypatch.setattr(procedural, "builtin_environments", lambda quick=False: [procedural.constant(16)])
    plugin = Path(__file__).with_name("plugin_tiny.py")
    try:
        code = cli.main(["run", "tiny_io", "--no-progress", "--plugin", str(plugin), "--probes", str(probes),
                         "--out", str(tmp_path / "out")])
    finally:
        EXPERIMENTS.pop("tiny_io", None)
    assert code == 0, capsys.readouterr().err
    assert "noisy: clamped negative texels to 0 (float noise)" in capsys.readouterr().out
    meta = json.loads((tmp_path / "out" / "results.json").read_text())["meta"]
    clamp = meta["environments"]["noisy"]["clamped_negative"]
    assert clamp["texels"] == 1 and clamp["min"] == pytest.approx(-0.04, rel=1e-6)
    assert meta["skipped_inputs"] == []
