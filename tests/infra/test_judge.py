"""``python -m validate judge``: images rendered anywhere against the exported scenes' Mitsuba truth.

The truth itself with independent noise (Mitsuba at another seed) passes; the truth × π fails and the scale is
named π; the hemisphere rendered upside down and a three-lobe environment turned 90° fail and the flip or turn is
named; the exact Lambert image shifted by half a pixel fails and the shift is named; bad input is one line, exit 2,
nothing written. 16² scenes at the quick samples: about 13 s on 2 cores with a cold reference cache.
"""

from __future__ import annotations

import json
import math
import shutil
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from validate.cli import main
from validate.experiments.renders.compute import references, truth
from validate.judge.folder import judge_folder, truth_settings
from validate.judge.images import write_exr, write_pfm
from validate.report.compare import compare, judgements_of
from validate.scenes import render_scenes as rs
from validate.scenes.env_orientation import turned_scene
from validate.scenes.manifest import load_manifest, manifest_scenes
from validate.testing import check_render_folder

RES = 16
SCENES = ("furnace_metal_r0.5", "lambert_directional", "point_plane", "hemisphere_sphere")


@pytest.fixture(scope="module")
def scenes_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("scenes")
    assert main(["scenes", "export", str(out), "--resolution", str(RES)]) == 0
    return out


def _truth_image(scenes_dir: Path, name: str, seed: int, variant: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The deciding reference of scene ``name`` traced at ``seed`` (independent of the judge's seed 0), and its
    hit mask as coverage; ``variant``: with the environment so turned."""
    doc = load_manifest(scenes_dir)
    s = replace(truth_settings(doc), seed=seed)
    [item] = [it for e, it in manifest_scenes(doc, scenes_dir) if e["name"] == name]
    sc = item.scene if variant is None else turned_scene(item.scene, variant)
    refs, hit = references(sc, item.kind, s)
    m, _, _ = truth(refs[item.references[0]], hit, s.passes)
    return np.nan_to_num(m, nan=0.0), hit.astype(np.float64)


@pytest.fixture(scope="module")
def truth_images(scenes_dir: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("truth_images")
    for name in SCENES:
        img, cov = _truth_image(scenes_dir, name, seed=1)
        write_exr(out / f"{name}.exr", img, cov, half=name != "point_plane")
    img, _ = _truth_image(scenes_dir, "spot_plane", seed=1)
    write_pfm(out / "spot_plane.pfm", img)  # PFM: no alpha, the plane covers every pixel
    (out / "notes.png").write_bytes(b"\x89PNG")  # names no scene: listed as extra
    return out


def test_the_truth_with_independent_noise_passes(truth_images: Path, scenes_dir: Path) -> None:
    r = check_render_folder(truth_images, engine="truth", scenes=scenes_dir)
    assert [s.name for s in r.scenes] == ["furnace_metal_r0.5", "lambert_directional", "point_plane",
                                          "spot_plane", "hemisphere_sphere"]
    assert r.failed == [], r.summary()
    assert {s.name: s.precision for s in r.scenes}["point_plane"] == "float"
    assert set(r.scenes[0].judgements) == {"energy", "model"}  # the furnace metal: both references judged
    assert "furnace_dielectric_r0.5" in r.missing and r.extra == ["notes.png"] and not r.passed


def test_truth_times_pi_fails_and_the_scale_is_named(truth_images: Path, scenes_dir: Path, tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    images = tmp_path / "images"
    images.mkdir()
    for name in ("lambert_directional", "point_plane"):
        img, cov = _truth_image(scenes_dir, name, seed=1)
        write_exr(images / f"{name}.exr", math.pi * img, cov, half=True)
    out = tmp_path / "out"
    assert main(["judge", str(images), "--engine", "pi_engine", "--scenes", str(scenes_dir), "--out", str(out),
                 "--strict"]) == 1
    printed = capsys.readouterr().out
    assert "lambert_directional: FAIL" in printed and "(= π); divided by it, it passes" in printed
    doc = json.loads((out / "results.json").read_text())
    for name in ("lambert_directional", "point_plane"):
        sc = doc["experiments"]["judge"]["scenes"][name]
        scale = sc["engines"]["pi_engine"]["diagnoses"]["scale"]
        assert not sc["passed"] and scale["named"] == "π" and scale["passes_when_divided"]
        assert abs(scale["factor"]["value"] - math.pi) < 3 * scale["factor"]["uncertainty"] + 1e-3 * math.pi
    assert (out / "index.html").read_text().count("<section>") == 2
    # compare reads the judgements: against a passing run of the same scenes the fractions accepted regress
    keys = judgements_of(doc)
    assert "judge/scenes/point_plane/engines/pi_engine/judgements/mitsuba/fraction_accepted" in keys


def test_compare_reads_two_judge_runs(truth_images: Path, scenes_dir: Path, tmp_path: Path) -> None:
    good, bad = tmp_path / "good", tmp_path / "bad"
    assert main(["judge", str(truth_images), "--engine", "e", "--scenes", str(scenes_dir), "--out", str(good)]) == 0
    images = tmp_path / "images"
    shutil.copytree(truth_images, images)
    img, cov = _truth_image(scenes_dir, "point_plane", seed=1)
    write_exr(images / "point_plane.exr", 1.05 * img, cov)
    assert main(["judge", str(images), "--engine", "e", "--scenes", str(scenes_dir), "--out", str(bad)]) == 0
    c = compare(good, bad)
    assert "judge/scenes/point_plane/engines/e/judgements/mitsuba/fraction_accepted" in {r.key for r in
                                                                                        c.regressions}


def test_hemisphere_upside_down_fails_and_the_flip_is_named(scenes_dir: Path, tmp_path: Path) -> None:
    img, cov = _truth_image(scenes_dir, "hemisphere_sphere", seed=1, variant="upside down")
    write_exr(tmp_path / "hemisphere_sphere.exr", img, cov, half=True)
    r = judge_folder(tmp_path, "flipped", scenes_dir)
    [sj] = r.scenes
    assert not sj.passed
    assert sj.diagnoses["environment"]["passes_with"] == ["upside down"]


def test_half_pixel_shift_fails_and_the_shift_is_named(scenes_dir: Path, tmp_path: Path) -> None:
    """The Lambertian sphere under the sun in closed form, ρE/π max(0, n·l) (Mitsuba's diffuse sphere under a
    directional emitter is exactly this, noise free), sampled half a pixel to the right of the pixel centres."""
    sc = rs.lambert_sun_scene(RES)
    x, y = sc.pixel_centres()
    dx = 2 * rs.HALF_EXTENT / RES

    def lambert(xx: np.ndarray, yy: np.ndarray) -> np.ndarray:
        n = np.stack([xx, yy, np.sqrt(np.clip(1 - xx**2 - yy**2, 0, None))], axis=-1)
        light = -sc.lights[0].unit_direction()
        return np.repeat((rs.SUN_LUX / np.pi * np.clip(n @ light, 0, None))[..., None], 3, axis=-1)

    exact = lambert(x, y)
    write_exr(tmp_path / "lambert_directional.exr", exact, sc.hit_mask().astype(float))
    assert judge_folder(tmp_path, "exact", scenes_dir).passed is False  # passes, but the other scenes are missing
    assert judge_folder(tmp_path, "exact", scenes_dir).failed == []
    write_exr(tmp_path / "lambert_directional.exr", lambert(x + dx / 2, y), sc.hit_mask().astype(float))
    [sj] = judge_folder(tmp_path, "shifted", scenes_dir).scenes
    assert not sj.passed
    assert sj.diagnoses["raster_shift"]["named"] == [0.0, 0.5]


def _bad_inputs(scenes_dir: Path, tmp_path: Path) -> dict[str, tuple[list[str], str]]:
    img = np.ones((RES, RES, 3))
    cases: dict[str, tuple[list[str], str]] = {}

    def folder(name: str) -> Path:
        p = tmp_path / name
        p.mkdir()
        return p

    p = folder("size")
    write_exr(p / "point_plane.exr", np.ones((RES + 1, RES, 3)))
    cases["size"] = ([str(p)], f"image is {RES}x{RES + 1}, the scene is {RES}x{RES}")
    p = folder("nan")
    bad = img.copy()
    bad[3, 4, 1] = np.nan
    write_exr(p / "point_plane.exr", bad)
    cases["nan"] = ([str(p)], "1 pixel(s) NaN or Inf (first at row, column (3, 4))")
    p = folder("negative")
    write_exr(p / "point_plane.exr", -img)
    cases["negative"] = ([str(p)], "negative")
    p = folder("png")
    (p / "point_plane.png").write_bytes(b"\x89PNG\r\n")
    cases["png"] = ([str(p)], "PNG holds display-referred")
    p = folder("engine")
    write_exr(p / "point_plane.exr", img)
    cases["engine"] = ([str(p), "--engine", "my engine/2"], "not an engine name")
    sc = folder("newer")
    for f in scenes_dir.iterdir():
        shutil.copy(f, sc / f.name)
    m = json.loads((sc / "manifest.json").read_text())
    (sc / "manifest.json").write_text(json.dumps(dict(m, schema="validate-scenes/2")))
    cases["newer"] = ([str(p), "--scenes", str(sc)], "manifest schema validate-scenes/2 is newer")
    sc = folder("malformed_manifest")
    (sc / "manifest.json").write_text("{not json")
    cases["malformed_manifest"] = ([str(p), "--scenes", str(sc)], "not valid JSON")
    sc = folder("malformed_glb")
    for f in scenes_dir.iterdir():
        shutil.copy(f, sc / f.name)
    (sc / "point_plane.glb").write_bytes((sc / "point_plane.glb").read_bytes()[:100])
    cases["malformed_glb"] = ([str(p), "--scenes", str(sc)], "point_plane.glb: malformed GLB header")
    return cases


def test_bad_input_is_one_line_exit_2_nothing_written(scenes_dir: Path, tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    for name, (argv, needle) in _bad_inputs(scenes_dir, tmp_path).items():
        out = tmp_path / f"out_{name}"
        args = ["judge", *argv]
        if "--engine" not in args:
            args += ["--engine", "e"]
        if "--scenes" not in args:
            args += ["--scenes", str(scenes_dir)]
        assert main([*args, "--out", str(out)]) == 2, name
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("validate: error: ") and needle in err[0], (name, err)
        assert not out.exists(), name


def test_environment_turned_90_degrees_fails_and_the_turn_is_named() -> None:
    """A white metal sphere (roughness 0.5) under an asymmetric map of three coloured lobes, as an engine that turns
    the environment +90° about +y renders it (the truth of the turned scene at another seed): it fails, and of the
    five variants only that turn passes."""
    from validate.experiments.renders.settings import QUICK
    from validate.judge.folder import diagnose, judge_against
    from validate.judge.images import EngineImage
    from validate.scenes.env_orientation import texel_direction
    from validate.scenes.manifest import SetScene

    h, w = 32, 64
    i, j = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    d = texel_direction(i, j, h, w)

    def lobe(axis: list[float]) -> np.ndarray:
        a = np.asarray(axis) / np.linalg.norm(axis)
        return 3.0 * np.exp(4.0 * (d @ a - 1.0))

    texels = 0.3 + np.stack([lobe([1, 0.2, 0]), lobe([0.3, 0.5, 0.8]), lobe([-0.5, 0.1, -0.8])], axis=-1)
    item = SetScene(rs.probe_scenes(texels, "three_lobes", RES, (0.5,), (1.0,))[0], "probe", ("mitsuba",))
    refs, hit = references(turned_scene(item.scene, "turned +90° about +y"), "probe", replace(QUICK, seed=1))
    m = np.nan_to_num(refs["mitsuba"].mean, nan=0.0)
    img = EngineImage(m, hit.astype(float), "float", np.zeros_like(m), True)
    js, truths, mask = judge_against(item, img, QUICK)
    assert js["mitsuba"].fraction_accepted < 0.5
    env = diagnose(item, img, QUICK, truths, mask)["environment"]
    assert env["passes_with"] == ["turned +90° about +y"] and len(env["tried"]) == 5


@pytest.mark.probes
def test_probe_scenes_through_the_files_and_a_turned_probe_is_named(probes_dir: Path, tmp_path: Path,
                                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """``--probes``: the probe scenes go out with ``uffizi.exr`` and come back rebuilt from it; the metal sphere
    rendered with the probe turned −90° about +y fails and that turn is named, through the command line."""
    scenes = tmp_path / "scenes"
    assert main(["scenes", "export", str(scenes), "--resolution", str(RES), "--probes", str(probes_dir)]) == 0
    doc = load_manifest(scenes)
    assert doc["probe"]["file"] == "uffizi.exr" and "probe_metal_r0.5" in [e["name"] for e in doc["scenes"]]
    images = tmp_path / "images"
    images.mkdir()
    img, cov = _truth_image(scenes, "probe_metal_r0.5", seed=1, variant="turned −90° about +y")
    write_exr(images / "probe_metal_r0.5.exr", img, cov, half=True)
    assert main(["judge", str(images), "--engine", "turned", "--scenes", str(scenes), "--out",
                 str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "probe_metal_r0.5: FAIL" in out and "with the environment turned −90° about +y" in out
