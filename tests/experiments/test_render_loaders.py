"""Issue 34 item 5: the hosted engines through their own glTF loaders (renders part (g), ``renders.loaders``).

Default run: the quantisation step an 8-bit readback states in its EXR reaches the judge's uncertainty (no
browser); which scenes an engine skips and why; three.js's ``GLTFLoader`` renders the exported Lambertian sphere
under a KHR directional light and ``validate judge`` passes it, while the image × 1.02 fails; Filament's gltfio
does too once its orthographic projection is corrected, and fails with gltfio's own (2/xmag). The engine cases
skip with the reason without Chromium or the npm engines.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from validate.judge import images
from validate.judge.folder import judge_folder
from validate.local_models.render import filament_gltf, gltf_page, three_gltf
from validate.metrics.pixel_z import MIN_ACCEPTED
from validate.scenes.manifest import export_scenes

SCENE = "lambert_directional"


def test_the_stated_quantisation_step_is_the_judges_uncertainty(tmp_path: Path) -> None:
    assert gltf_page.QUANTISATION_ATTRIBUTE == images.QUANTISATION_ATTRIBUTE
    rgba = np.zeros((4, 4, 4), np.float32)
    rgba[..., :3], rgba[..., 3] = 0.5, 1.0
    step = 1.0 / (255.0 * 1.7)
    gltf_page.write_exr_rgba(tmp_path / "q.exr", rgba, step)
    img = images.read_engine_image(tmp_path / "q.exr", 4, 4)
    assert img.precision == "unorm8"
    np.testing.assert_allclose(img.readback_stderr, step / math.sqrt(12.0), rtol=1e-6)  # ±½ step uniform
    gltf_page.write_exr_rgba(tmp_path / "f.exr", rgba)
    plain = images.read_engine_image(tmp_path / "f.exr", 4, 4)
    assert plain.precision == "float" and not plain.readback_stderr.any()


def test_an_engine_without_image_based_lighting_skips_the_environment_scenes_with_the_reason() -> None:
    furnace = {"lights": [], "environment": {"file": "white_furnace.exr"}, "camera": {"type": "orthographic"}}
    sun = {"lights": [{"type": "directional"}], "environment": None, "camera": {"type": "orthographic"}}
    assert gltf_page.scene_features(furnace) == {"environment"}
    assert filament_gltf.ENGINE.skip_reason(furnace) == filament_gltf.NO_IBL
    assert filament_gltf.ENGINE.skip_reason(sun) is None and three_gltf.ENGINE.skip_reason(furnace) is None


@pytest.fixture(scope="module")
def scenes_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("scenes")
    export_scenes(d, "quick", 64)
    return d


def _render_or_skip(engine, scenes_dir: Path, out: Path):
    from validate.gl.egl import GLUnavailable

    why = engine.unavailable()
    if why is not None:
        pytest.skip(f"{engine.name} cannot render here: {why.piece}: {why.why}")
    try:
        return engine.render_folder(scenes_dir, [SCENE], out)
    except GLUnavailable as exc:
        pytest.skip(f"{engine.name} cannot render here: {exc}")


def _accepted(images_dir: Path, engine: str, scenes_dir: Path) -> float:
    r = judge_folder(images_dir, engine, scenes_dir)
    (sj,) = [s for s in r.scenes if s.name == SCENE]
    return sj.judgements[sj.judged_by].fraction_accepted


def _scaled(src: Path, dst: Path, k: float) -> Path:
    img = images.read_engine_image(src / f"{SCENE}.exr", 64, 64)
    dst.mkdir()
    rgba = np.concatenate([img.rgb * k, img.coverage[..., None]], axis=-1).astype(np.float32)
    step = None if img.precision == "float" else float(img.readback_stderr.max() * math.sqrt(12.0) * k)
    gltf_page.write_exr_rgba(dst / f"{SCENE}.exr", rgba, step)
    return dst


def test_three_gltfloader_renders_the_exported_sphere_and_the_judge_passes_it(scenes_dir: Path,
                                                                             tmp_path: Path) -> None:
    r = _render_or_skip(three_gltf.ENGINE, scenes_dir, tmp_path / "three")
    assert list(r.images) == [SCENE] and r.info[SCENE]["lights"][0]["type"] == "DirectionalLight"
    assert _accepted(tmp_path / "three", "three_gltf", scenes_dir) >= MIN_ACCEPTED
    # power: a light 2 % off fails the same judge
    assert _accepted(_scaled(tmp_path / "three", tmp_path / "x102", 1.02), "three_gltf", scenes_dir) < MIN_ACCEPTED


def test_filament_gltfio_passes_with_gltfs_orthographic_projection_and_fails_with_its_own(scenes_dir: Path,
                                                                                       tmp_path: Path) -> None:
    _render_or_skip(filament_gltf.ENGINE, scenes_dir, tmp_path / "filament")
    assert _accepted(tmp_path / "filament", "filament_gltf", scenes_dir) >= MIN_ACCEPTED
    raw = replace(filament_gltf.ENGINE, options={**filament_gltf.ENGINE.options, "orthoHalfExtent": False})
    r = raw.render_folder(scenes_dir, [SCENE], tmp_path / "raw")
    assert json.loads(r.info[SCENE]["projection"])[0] == pytest.approx(2 / 1.1, rel=1e-6)  # gltfio: 2/xmag
    assert _accepted(tmp_path / "raw", "filament_gltf", scenes_dir) < 0.5


@pytest.mark.parametrize("module", ["validate.judge.folder", "validate.experiments.renders"])
def test_the_judge_and_the_renders_package_import_first_in_a_fresh_interpreter(module: str) -> None:
    """validate.judge.folder imports the renders package, whose loaders part uses the judge at call time only."""
    import subprocess
    import sys

    r = subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True, text=True, timeout=120,
                       cwd=Path(__file__).resolve().parents[2])
    assert r.returncode == 0, r.stderr[-2000:]
