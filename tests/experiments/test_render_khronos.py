"""Issue 37 item 2: the Khronos glTF Sample Viewer (npm @khronosgroup/gltf-viewer 1.1.0) as an engine.

Default run: the 8-bit gamma readback's decoding and its quantisation uncertainty (no browser), the furnace claim's
rounding bound, the engine declaration. ``slow`` (~15 s: browser, export, one render, the truth): the viewer renders
one exported scene (the point light over the Lambertian plane, 32²) through ``render_folder`` and the judge's own
functions judge it against Mitsuba with the readback's σ, and refuse it × 4π (skipped with the reason without
Chromium or the npm package).
"""

from __future__ import annotations

import dataclasses
import importlib

import numpy as np
import pytest

from validate.local_models.render import khronos_viewer as kv
from validate.local_models.render.engine import Engine

kcl = importlib.import_module("validate.experiments.renders.khronos.claims")


def test_decode_inverts_the_viewers_gamma_and_exposure() -> None:
    q = np.array([[[0, 128, 255, 255]]], np.uint8)
    out = kv.decode(q, 0.5)
    np.testing.assert_allclose(out[0, 0], [0.0, (128 / 255) ** 2.2 / 0.5, 2.0, 1.0], rtol=1e-12)


def test_readback_stderr_is_the_rounding_of_the_gamma_code() -> None:
    rng = np.random.default_rng(1)
    e = 0.5
    L = rng.uniform(1.90, 1.95, 400_000)  # a narrow band near full scale (e L ≈ 1): σ nearly constant over it
    code = 255 * (L * e) ** (1 / 2.2)
    err = (np.round(code) / 255) ** 2.2 / e - L
    assert kv.readback_stderr(np.array(1.925), e) == pytest.approx(err.std(), rel=0.02)
    # a wrong model (σ of a linear 8-bit code, as Filament's) is far off: the test can fail
    assert 1 / (255 * np.sqrt(12) * e) < 0.6 * err.std()


def test_furnace_bound_is_half_a_code_step_at_radiance_one() -> None:
    b = kcl.half_lsb_at_one(0.5)
    q = 255 * 0.5 ** (1 / 2.2)
    assert (((q + 0.5) / 255) ** 2.2 / 0.5 - 1) == pytest.approx(b, rel=1e-9) or \
        (1 - ((q - 0.5) / 255) ** 2.2 / 0.5) == pytest.approx(b, rel=1e-9)
    assert 1e-3 < b < 1e-2


def test_engine_is_declared() -> None:
    assert isinstance(kv.ENGINE, Engine) and kv.ENGINE.name == "khronos_viewer"
    assert kv.ENGINE.precision == "unorm8"
    v = kv.ENGINE.version()
    assert v is None or v == "1.1.0"


@pytest.mark.slow
def test_viewer_renders_an_exported_scene_and_the_judge_accepts_it(tmp_path) -> None:
    from validate.judge.folder import judge_against, truth_settings
    from validate.judge.images import read_engine_image
    from validate.scenes.manifest import export_scenes, load_manifest, manifest_scenes

    why = kv.ENGINE.unavailable()
    if why is not None:
        pytest.skip(f"{why.piece}: {why.why}")
    scenes = tmp_path / "scenes"
    export_scenes(scenes, "quick", 32)
    fr = kv.ENGINE.render_folder(scenes, ["point_plane"], tmp_path / "images")
    assert fr.version == "1.1.0" and set(fr.images) == {"point_plane"}
    manifest = load_manifest(scenes)
    item = dict((e["name"], it) for e, it in manifest_scenes(manifest, scenes / "manifest.json"))["point_plane"]
    img = read_engine_image(fr.images["point_plane"], 32, 32)
    img = dataclasses.replace(img, readback_stderr=kv.readback_stderr(img.rgb, fr.info["point_plane"]["exposure"]))
    js, _, _ = judge_against(item, img, truth_settings(manifest))
    assert js["mitsuba"].fraction_accepted >= 0.9975
    # power: lumens taken for candela (× 4π) is refused
    js4, _, _ = judge_against(item, dataclasses.replace(img, rgb=img.rgb * 4 * np.pi), truth_settings(manifest))
    assert js4["mitsuba"].fraction_accepted < 0.5


def test_without_the_package_the_part_says_why_and_renders_nothing(monkeypatch) -> None:
    import sys

    import validate.experiments.renders  # noqa: F401 - the package re-exports compute()
    from validate.experiments.renders.khronos.compute import compute_khronos
    from validate.experiments.renders.settings import QUICK

    monkeypatch.setattr(kv.paths, "installed_version", lambda package: None)
    why = kv.ENGINE.unavailable()
    assert why is not None and kv.PACKAGE in why.piece and why.fix == kv.FIX
    rc = sys.modules["validate.experiments.renders.compute"]

    class Scene:  # a parent scene of the name the settings list (nothing is traced: the part stops first)
        name = QUICK.khronos_scenes[0]

    class Result:
        scene = Scene()

    part = compute_khronos(None, QUICK, [Result()], rc.budget)
    assert part.skipped.startswith(f"npm {kv.PACKAGE}") and not part.scenes
    assert kcl.khronos_claims(part) == []
