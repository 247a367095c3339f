"""The ``blender`` experiment: Cycles against Mitsuba through the exported scenes, the importer's light units, and
what happens without Blender. The renders need Blender (``python -m validate setup --blender``): those tests skip
with the reason when it is absent; the others run anywhere (no Blender, no Mitsuba)."""

from __future__ import annotations

import ast
import importlib
import math

import pytest

from validate.local_models.render import blender as bl

compute_mod = importlib.import_module("validate.experiments.blender.compute")
settings_mod = importlib.import_module("validate.experiments.blender.settings")
claims_mod = importlib.import_module("validate.experiments.blender.claims")
VERSION, WHY = bl.available()
needs_blender = pytest.mark.skipif(VERSION is None, reason=f"Blender not installed ({WHY}): {bl.FIX}")


def test_the_worker_imports_nothing_of_the_suite() -> None:
    """Blender's interpreter has numpy < 2 and no validate: the worker may import only the standard library and bpy."""
    tree = ast.parse(bl.WORKER.read_text())
    names = {a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    names |= {n.module.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
    assert names <= {"__future__", "json", "math", "sys", "time", "bpy"}, names


def test_without_blender_the_experiment_is_not_run(tmp_path, monkeypatch) -> None:
    from validate.setup.install import check_blender

    monkeypatch.setenv("VALIDATE_HOME", str(tmp_path))
    bl.available.cache_clear()
    try:
        m = compute_mod.compute(None, settings_mod.QUICK)
    finally:
        bl.available.cache_clear()
    assert m.missing is not None and m.missing.fix == "python -m validate setup --blender"
    assert "blender_cycles" in m.missing.what and "blender_eevee" in m.missing.what
    assert claims_mod.claims(m) == [] and not check_blender().ok
    report = importlib.import_module("validate.experiments.blender.report")
    assert report.not_run(m) == [m.missing] and report.findings(m) == []


def test_blender_spot_is_the_importers_cone() -> None:
    """blend = 1 − 20/30; cos θ_b = cos 30° + (1 − cos 30°)·blend → θ_b = 24.40°."""
    from validate.scenes import render_scenes as rs

    [li] = compute_mod.blender_spot(rs.spot_scene(16)).lights
    assert li.profile == "smoothstep" and li.outer_deg == 30.0
    assert li.inner_deg == pytest.approx(math.degrees(math.acos(math.cos(math.radians(30)) * 2 / 3 + 1 / 3)))


@needs_blender
def test_cycles_agrees_with_mitsuba_and_a_one_percent_scale_fails(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("VALIDATE_CACHE", str(tmp_path / "cache"))
    s = settings_mod.Settings(scene_set="quick", kinds=("directional", "point"), passes=4, spp=4,
                              scenes=("lambert_directional", "point_plane"))
    m = compute_mod.compute(None, s)
    cs = claims_mod.claims(m)
    assert [c.id for c in cs] == ["blender.cycles.lambert_directional.agrees_with_mitsuba",
                                  "blender.cycles.point_plane.agrees_with_mitsuba"]
    assert all(c.passed and c.power.fails for c in cs)
    # the importer's units, measured in pixels: SPEC is 1/683 of COMPAT (1 W = 683 lm); RAW's point 1/(4π)
    assert m.conversion["SPEC"]["SUN"]["radiance_over_compat"] == pytest.approx(1 / 683, rel=1e-3)
    assert m.conversion["SPEC"]["POINT"]["radiance_over_compat"] == pytest.approx(1 / 683, rel=1e-3)
    assert m.conversion["RAW"]["POINT"]["radiance_over_compat"] == pytest.approx(1 / (4 * math.pi), rel=1e-3)
    assert m.conversion["COMPAT"]["POINT"]["blender_energy"] == pytest.approx(4 * math.pi * 3.0, rel=1e-6)
    # a warm run renders nothing
    again = compute_mod.compute(None, s)
    assert again.costs["rendered"] == 0 and again.scenes[0].energy == m.scenes[0].energy
