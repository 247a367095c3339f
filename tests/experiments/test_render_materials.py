"""(b) glTF materials of the ``renders`` experiment: scenes, references (i)/(ii) kept apart, the mix claim."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.scenes import render_scenes as rs

pytest.importorskip("mitsuba")

TEXELS = np.random.default_rng(0).random((16, 32, 3)) + 0.5  # a small non-constant lat-long probe


def test_material_models_validate_their_ranges() -> None:
    assert rs.Material(metallic=0.5, model="gltf").to_json()["model"] == "gltf"
    assert "model" not in rs.Material(metallic=1.0).to_json()  # the older scenes' cache keys are unchanged
    with pytest.raises(ValidateError, match="metallic"):
        rs.Material(metallic=0.5)  # the mapped model keeps metallic 0 or 1
    with pytest.raises(ValidateError, match="white metal"):
        rs.Material(metallic=0.5, model="multiscatter")
    with pytest.raises(ValidateError, match="model"):
        rs.Material(model="principled")


def test_scene_list_adds_the_material_grid() -> None:
    from validate.experiments.renders.compute import scene_list
    from validate.experiments.renders.settings import QUICK

    rows = [(sc, k) for sc, k in scene_list(QUICK, TEXELS) if k.name == "probe_material"]
    got = sorted((sc.material.metallic, sc.material.roughness) for sc, _ in rows)
    assert got == sorted((m, r) for m in QUICK.material_metallic for r in QUICK.material_roughness)
    names = [sc.name for sc, _ in scene_list(QUICK, TEXELS)]
    assert len(names) == len(set(names))


def test_reference_ii_at_intermediate_metalness_is_the_mix_of_dielectric_i_and_walk_ii() -> None:
    from validate.experiments.renders.compute import material_references
    from validate.experiments.renders.settings import Settings
    from validate.reference.render_reference import render_reference

    s = Settings(probe_spp=4, passes=4)
    [d0, half, one] = rs.probe_material_scenes(TEXELS, "t", 8, (0.5,), (0.0, 0.5, 1.0))
    refs = material_references(half, s)
    assert set(refs) == {"gltf", "multiscatter"} and set(material_references(d0, s)) == {"gltf"}
    walk = render_reference(replace(one, name="x", material=replace(one.material, model="multiscatter")), 4, 4, 0)
    diel = render_reference(d0, 4, 4, 0)
    h = refs["gltf"].hit
    np.testing.assert_allclose(refs["multiscatter"].mean[h], 0.5 * diel.mean[h] + 0.5 * walk.mean[h], rtol=1e-12)
    # (i) is glTF's single scattering: below (ii) for the rough white metal lobe
    assert refs["gltf"].mean[h].mean() < refs["multiscatter"].mean[h].mean()


def _fake(metallic: float, image: np.ndarray) -> object:
    from validate.experiments.renders.compute import EngineResult, SceneResult

    sc = rs.RenderScene(f"probe_gltf_m{metallic:g}_r0.5", rs.Material(metallic=metallic, roughness=0.5,
                                                                       model="gltf"), resolution=image.shape[0])
    mask = np.ones(image.shape[:2], bool)
    sr = SceneResult(sc, "probe_material", {"gltf": image}, {"gltf": (1.0, 0.0)}, mask,
                     {"gltf": np.zeros_like(image)})
    sr.engines["e"] = EngineResult(image, np.ones(image.shape[:2]), 0.0, 0.0, "test")
    return sr


def test_mix_claim_passes_for_a_linear_engine_and_fails_for_a_blended_f0_one() -> None:
    from validate.experiments.renders.claims import mix_claims
    from validate.experiments.renders.compute import Measurements
    from validate.experiments.renders.settings import QUICK

    rng = np.random.default_rng(1)
    i0, i1 = rng.random((8, 8, 3)) + 0.5, rng.random((8, 8, 3)) + 0.5
    linear = Measurements(QUICK, [_fake(0.0, i0), _fake(0.5, 0.5 * (i0 + i1)), _fake(1.0, i1)])
    [c] = mix_claims(linear)
    assert c.passed and c.power is not None and c.power.fails
    bent = Measurements(QUICK, [_fake(0.0, i0), _fake(0.5, 0.5 * (i0 + i1) * 0.98), _fake(1.0, i1)])  # 2 % lost
    [c] = mix_claims(bent)
    assert not c.passed


def test_furnace_at_intermediate_metalness_claim_and_its_power() -> None:
    from validate.experiments.renders.claims import FURNACE_ENERGY_TOL, furnace_material_claims
    from validate.experiments.renders.compute import EngineResult, Measurements, SceneResult
    from validate.experiments.renders.settings import QUICK

    [sc] = rs.furnace_material_scenes(8, (1.0,))
    assert sc.material.metallic == 0.5 and sc.material.model == "gltf"
    img = np.ones((8, 8, 3))
    sr = SceneResult(sc, "furnace_material", {"energy": img, "gltf": 0.7 * img},
                     {"energy": (1.0, 0.0), "gltf": (0.7, 1e-3)}, np.ones((8, 8), bool))
    for name, e in (("good", 1.0), ("lossy", 1.0 - 2 * FURNACE_ENERGY_TOL)):
        sr.engines[name] = EngineResult(e * img, np.ones((8, 8)), 0.0, 0.0, "test", energy=e)
    got = {c.id.split(".")[1]: c for c in furnace_material_claims(Measurements(QUICK, [sr]))}
    assert got["good"].passed and got["good"].power is not None and got["good"].power.fails
    assert not got["lossy"].passed
