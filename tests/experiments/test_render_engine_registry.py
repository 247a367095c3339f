"""Engines are registered modules (validate/local_models/render/registry.py) and scene kinds are objects
(validate/experiments/renders/kinds.py): what the folder declares, how a kind's name is looked up, and — the point of
the registry — an engine added in a file of its own gets report rows, results.json entries and claims with no edit
anywhere else, its images cached by (engine version, scene content).

The tiny engine below is written to a temporary folder and loaded as a ``--plugin`` is: it renders the closed-form
Lambertian sphere under the sun, ρE/π·max(0, n·l), plus independent noise far below the budget; a second one renders a
constant. No browser: one 16² scene, Mitsuba's reference at 4 × 4 samples.
"""

from __future__ import annotations

import importlib
import json
from pathlib import Path

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.local_models.render import registry

compute = importlib.import_module("validate.experiments.renders.compute")  # the package exports compute()
claims = importlib.import_module("validate.experiments.renders.claims")
report = importlib.import_module("validate.experiments.renders.report")

ENGINE_SOURCE = '''
"""A test engine: the exact Lambertian sphere under the sun plus noise (or a constant)."""
import numpy as np

from validate.local_models.render.engine import Engine, EngineRender

RENDERS = []  # scene names, one per render actually made (the cache test counts them)


class ClosedForm(Engine):
    def version(self):
        return "1.0"

    def render(self, scene):
        RENDERS.append(scene.name)
        hit = scene.hit_mask()
        n = np.nan_to_num(scene.surface_points())
        li = scene.lights[0]
        cos = np.clip(n @ -li.unit_direction(), 0.0, None)
        rho = np.asarray(scene.material.base_color)
        img = np.zeros(hit.shape + (4,), np.float32)
        if self.name == "test_constant":
            img[..., :3] = 0.5
        else:
            rng = np.random.default_rng(0)
            img[..., :3] = rho * li.intensity / np.pi * cos[..., None] + 1e-4 * rng.standard_normal(hit.shape + (3,))
        img[..., 3] = hit
        img[~hit] = 0.0
        return EngineRender(img, 1.0, 0.0, self.version())


ENGINE = ClosedForm(name="test_noisy", product="Test closed form", precision="float", supports=("directional",),
                    lacks={"environment": "no IBL in the test engine"})
VARIANTS = (ClosedForm(name="test_constant", product="Test constant", precision="float", supports=("directional",),
                       variant_of="test_noisy"),)
'''


@pytest.fixture()
def test_engines(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):  # noqa: ANN201 - the loaded module
    """The tiny engines loaded as a plug-in (as `--plugin FILE` does), the caches in a folder of the test's own."""
    from validate.run.plugins import load_plugin

    monkeypatch.setenv("VALIDATE_CACHE", str(tmp_path / "cache"))
    path = tmp_path / "closed_form_engine.py"
    path.write_text(ENGINE_SOURCE)
    load_plugin(str(path))
    yield registry.get("test_noisy")
    registry.unregister("test_noisy")
    registry.unregister("test_constant")


def test_the_folder_declares_the_hosted_and_blender_engines() -> None:
    names = registry.engine_modules()
    assert {"three", "babylon", "filament", "blender_cycles", "blender_eevee"} <= set(names)
    assert "blender_worker" not in names and "engine" not in names and "registry" not in names
    found = registry.engines()
    assert found["filament"].precision == "unorm8" and found["three"].precision == "float"
    assert found["babylon"].shadow_types == ("pcf", "pcss", "esm", "blur_esm")
    assert registry.product("babylon_cdf64_shipped") == "Babylon.js" and registry.product("nope") == "nope"
    assert found["three_probe"].variant_of == "three" and "hemisphere" in found["three_probe"].with_kinds
    with pytest.raises(ValidateError, match="not a registered engine"):
        registry.get("nope")


def test_discovery_reads_a_folder_without_importing_scripts(tmp_path: Path) -> None:
    (tmp_path / "mine.py").write_text("ENGINE = None\n")
    (tmp_path / "helper.py").write_text("X = 1\n")
    (tmp_path / "mine_worker.py").write_text("import bpy\nENGINE = 1\n")
    assert registry.engine_modules(tmp_path) == ["mine"]


def test_scene_kinds_are_looked_up_by_name() -> None:
    from validate.experiments.renders import kinds

    assert kinds.kind_of("spot") is kinds.SPOT and kinds.kind_of(kinds.RECT) is kinds.RECT
    assert kinds.SPOT.power is not kinds.DIRECTIONAL.power
    with pytest.raises(ValidateError, match="scene kind 'sunlight'"):
        kinds.kind_of("sunlight")
    from validate.experiments.renders.budgets import PROBE_BUDGET_REL

    b, _ = kinds.PROBE.budget(np.full(3, 2.0))
    assert np.allclose(b, 2.0 * PROBE_BUDGET_REL)
    assert "peak" in kinds.DIRECTIONAL.budget(np.ones(3))[1]


def test_an_engine_in_its_own_file_gets_rows_results_and_claims(test_engines) -> None:  # noqa: ANN001
    from validate.experiments.renders import images, kinds
    from validate.experiments.renders.settings import Settings
    from validate.scenes import render_scenes as rs

    s = Settings(resolution=16, spp=4, passes=4, engines=())  # the settings name no engine: the registry adds it
    assert kinds.run_engines(s) == ("test_noisy",)
    assert kinds.engine_names(kinds.DIRECTIONAL, s) == ["test_noisy"]  # its variant renders by name only
    scene = rs.lambert_sun_scene(16, s.sun_lux)
    sr = compute.measure_scene(scene, kinds.DIRECTIONAL, s)
    assert set(sr.engines) == {"test_noisy"}
    m = compute.Measurements(s, [sr])
    got = {c.id: c for c in claims.claims(m)}
    c = got["renders.test_noisy.lambert_directional.accepted"]
    assert c.passed and c.power is not None and c.power.fails  # × 1.02 is caught
    data = json.loads(json.dumps(report.data(m), default=float))
    row = data["scenes"]["lambert_directional"]
    assert row["kind"] == "directional" and "test_noisy" in row["engines"]
    assert row["engines"]["test_noisy"]["judgements"]["mitsuba"]["fraction_accepted"]["value"] >= 0.9975
    # a kind needing a feature the engine lacks: skipped with its stated reason, never silently dropped
    assert compute.skip_reason("test_noisy", kinds.PROBE) == "no IBL in the test engine"
    # the constant engine, asked for by name, is judged and fails the same claim
    sr_c = compute.measure_scene(scene, kinds.DIRECTIONAL, Settings(resolution=16, spp=4, passes=4,
                                                                      engines=("test_constant",)))
    bad = {c.id: c for c in claims.claims(compute.Measurements(s, [sr_c]))}
    assert not bad["renders.test_constant.lambert_directional.accepted"].passed
    # its images are cached by (engine version, scene content): rendering again renders nothing
    made = type(test_engines).render.__globals__["RENDERS"]  # the engine module's own count
    n = len(made)
    again = images.render("test_noisy", scene)
    assert len(made) == n
    np.testing.assert_array_equal(again.image[..., :3].astype(np.float64), sr.engines["test_noisy"].image)
    assert images.cached("test_noisy", scene) is not None
    assert images.cached("test_noisy", rs.lambert_sun_scene(16, 2 * s.sun_lux)) is None  # another scene: a miss
