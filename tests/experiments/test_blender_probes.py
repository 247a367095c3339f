"""The ``blender`` experiment's bpy-built probe scenes (validate/experiments/blender/probes.py): the glossy spheres'
one BSDF in Cycles and Mitsuba, the descriptions the worker builds, the soft-shadow sweep's Blender names, and that
all of it is opt-in. The render test needs Blender and runs under ``-m slow``."""

from __future__ import annotations

import importlib
import math
import os
from pathlib import Path

import numpy as np
import pytest

from validate.local_models.render import blender as bl

probes = importlib.import_module("validate.experiments.blender.probes")
world = importlib.import_module("validate.experiments.blender.world")
settings_mod = importlib.import_module("validate.experiments.blender.settings")
shadows = importlib.import_module("validate.experiments.blender.shadows")
compute_mod = importlib.import_module("validate.experiments.blender.compute")
claims_mod = importlib.import_module("validate.experiments.blender.claims")
VERSION, WHY = bl.available()
MIN_ACCEPTED_LIT = 0.99  # EEVEE's disc at 10⁻⁴ on the lit plane: measured 100 % of 2433 px


def test_probe_scenes_are_opt_in() -> None:
    """Without VALIDATE_EEVEE=1 the settings render no probe scene and no sweep (the default run unchanged)."""
    on = os.environ.get("VALIDATE_EEVEE") == "1"
    for s in (settings_mod.QUICK, settings_mod.FULL):
        assert bool(s.glossy_probe) == on and bool(s.volume_probe) == on and bool(s.shadow_sweep) == on


def test_glossy_description_is_cycles_single_scattering_ggx() -> None:
    gs = probes.GlossyScene(None, (15.0, 0.0), 0.3)  # the environment enters the job by its texture file
    d = probes.glossy_desc(gs, Path("/x.exr"))
    assert d["bsdf"] == {"type": "glossy", "roughness": 0.3, "distribution": "GGX"} and "probes" not in d
    assert d["camera"] == world.camera_matrix((15.0, 0.0)) and d["ortho_scale"] == world.ORTHO_SCALE
    [p] = probes.glossy_desc(gs, Path("/x.exr"), "sphere_probe")["probes"]
    assert p["type"] == "SPHERE" and p["hide_sphere"] and "parallax" not in p
    [far] = probes.glossy_desc(gs, Path("/x.exr"), "sphere_probe_far")["probes"]
    assert far == {**p, "parallax": probes.FAR_PARALLAX}
    # a reflected ray leaving the unit sphere turns by ≤ asin(1/D): under a tenth of half a texel of the world
    half_texel = 0.5 * 180.0 / (world.ENV_UPSAMPLE * 512)  # grace_probe: 512 rows over 180°
    assert math.degrees(math.asin(1.0 / probes.FAR_PARALLAX)) < 0.1 * half_texel
    assert probes.alpha(0.3) == pytest.approx(0.09) and probes.alpha(0.6) == pytest.approx(0.36)


def test_volume_description_bakes_only_in_its_variant() -> None:
    vs = probes.VolumeScene(None)
    assert "probes" not in probes.volume_desc(vs, Path("/x.exr"))
    [p] = probes.volume_desc(vs, Path("/x.exr"), "volume")["probes"]
    assert p["type"] == "VOLUME" and p["resolution"] == list(probes.VOLUME_RESOLUTION)
    # the probe's box (half extents × scale) holds the sphere and the plane beneath it
    assert all(s >= 1.0 for s in p["scale"]) and p["scale"][2] >= abs(probes.PLANE[0])
    # Cycles' second truth: bounces = Mitsuba's path length − 2 (max_depth 2 is direct light, Cycles' 0 bounces)
    c = probes.volume_desc(vs, Path("/x.exr"), "cycles")
    assert c["cycles"] == {"max_bounces": probes.VOLUME_DEPTH - 2, "diffuse_bounces": probes.VOLUME_DEPTH - 2}
    assert "probes" not in c and all("cycles" not in probes.volume_desc(vs, Path("/x.exr"), v)
                                      for v in probes.VOLUME_VARIANTS)


def test_the_lambertian_world_job_keeps_its_description() -> None:
    """The world-lit sphere's job gains no key (its cache entries stay valid)."""
    class Env:
        name = "e"

    from validate.local_models.render.blender_cycles import ENGINE

    j = world.job(world.WorldScene(Env(), (15.0, 0.0)), Path("/x.exr"), ENGINE, 64, 32, (0,), Path("/o"))
    assert set(j.scene) == {"kind", "segments", "rings", "albedo", "ortho_scale", "camera", "filter_px", "world",
                            "eevee", "env_exr"}


def test_shadow_sweep_names_blender_5s_light_settings() -> None:
    """Blender 5.0: ``shadow_filter_radius`` (PCF, default 1) and ``shadow_jitter_overblur`` (%, default 10) on the
    light; ``light_threshold`` (default 0.01) on the scene's EEVEE settings."""
    assert set(shadows.SWEEP) >= {"filter_0", "filter_3", "overblur_0", "overblur_40", "threshold_low"}
    for label, light in shadows.SWEEP.items():
        assert set(light) <= {"use_shadow_jitter", "shadow_filter_radius", "shadow_jitter_overblur"}
        assert light["use_shadow_jitter"] == (not label.startswith("filter"))
    assert shadows.SCENE == {"threshold_low": {"light_threshold": 1.0e-4}}
    assert set(settings_mod.FULL.shadow_sweep) <= set(shadows.SWEEP)
    sc = shadows.scene(16)
    assert "eevee" not in shadows.extras(sc, shadows.eevee_light("jitter_on"))  # the cached jobs keep their keys
    assert shadows.extras(sc, shadows.eevee_light("threshold_low"), shadows.SCENE["threshold_low"])["eevee"] == {
        "light_threshold": 1.0e-4}


def test_the_disc_light_is_an_area_disc_of_the_spots_intensity() -> None:
    """The disc's radiance I/(π r²) is an AREA light of power π I (P = π A L); the sphere keeps its radius."""
    disc, sphere = shadows.disc_scene(16), shadows.scene(16)
    ex = shadows.extras(disc)
    assert ex["area_disc"] == {"radius": disc.light_size, "power": pytest.approx(math.pi * disc.light.intensity)}
    assert "light_radius" not in ex and shadows.extras(sphere)["light_radius"] == sphere.light_size
    c, n, r, radiance = disc.emitter_disc()
    assert np.pi * (np.pi * r * r) * radiance == pytest.approx(ex["area_disc"]["power"])
    assert n @ (np.asarray(disc.light.target) - c) > 0  # it faces the plane
    assert disc.key() != sphere.key() and disc.name != sphere.name


def _lambda(a2: float, mu: float) -> float:
    t2 = (1.0 - mu * mu) / (mu * mu)
    return 0.5 * (math.sqrt(1.0 + a2 * t2) - 1.0)


def test_the_truths_bsdf_is_cycles_glossy_ggx() -> None:
    """Mitsuba's glTF BSDF at baseColor 1, metallic 1 evaluates Cycles' single-scattering GGX with F = 1:
    D(h) G₂ / (4 μ_i μ_o) · μ_o, G₂ = 1/(1 + Λ_i + Λ_o) (height-correlated), α = roughness²; Mitsuba's separable
    G₁G₁ (roughconductor) differs by 0.47 % at α = 0.36 and these angles, far beyond the tolerance."""
    pytest.importorskip("mitsuba")
    import drjit as dr
    import mitsuba as mi

    from validate.reference.gltf_bsdf import bsdf_dict

    r, th_i, th_o, dphi = 0.6, 1.1, 0.9, 2.5
    a = probes.alpha(r)
    bsdf = mi.load_dict(bsdf_dict((1.0, 1.0, 1.0), 1.0, r))
    wi = [math.sin(th_i), 0.0, math.cos(th_i)]
    wo = [math.sin(th_o) * math.cos(dphi), math.sin(th_o) * math.sin(dphi), math.cos(th_o)]
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = mi.Vector3f(*wi)
    got = float(np.array(bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(*wo))).ravel()[0])
    h = np.add(wi, wo)
    h /= np.linalg.norm(h)
    a2 = a * a
    d = a2 / (math.pi * (h[2] ** 2 * (a2 - 1.0) + 1.0) ** 2)
    mi_, mo = wi[2], wo[2]
    li, lo = _lambda(a2, mi_), _lambda(a2, mo)
    cycles = d / (1.0 + li + lo) / (4.0 * mi_ * mo) * mo
    separable = d / ((1.0 + li) * (1.0 + lo)) / (4.0 * mi_ * mo) * mo
    assert got == pytest.approx(cycles, rel=1e-4)
    assert abs(separable / cycles - 1.0) > 1e-3  # measured 0.47 % here: 47 × the tolerance


@pytest.mark.skipif(VERSION is None, reason=f"Blender not installed ({WHY}): {bl.FIX}")
@pytest.mark.slow
def test_cycles_agrees_with_mitsuba_on_a_glossy_sphere(grace_context) -> None:
    """Roughness 0.1 and 0.6 under grace_probe: Cycles and Mitsuba agree per pixel; a mirrored frame and a 1 % scale
    fail. At 0.1 the plain mean-z test failed (−0.139 against 0.072) as it did for Mitsuba against itself; the
    cross-fitted test passes (docs/experiments/blender.md, "The bias test, cross-fitted")."""
    s = settings_mod.Settings(scene_set="quick", kinds=(), scenes=("none",), glossy_probe="grace_probe",
                              glossy_roughness=(0.1, 0.6), glossy_variants=())
    m = compute_mod.compute(grace_context, s)
    cs = claims_mod.claims(m)
    assert [c.id.rsplit(".", 1)[1] for c in cs] == ["agrees_with_mitsuba", "unbiased_against_mitsuba"] * 2
    assert all(c.passed and c.power.fails for c in cs), [(c.measured, c.power) for c in cs]


@pytest.mark.skipif(VERSION is None, reason=f"Blender not installed ({WHY}): {bl.FIX}")
@pytest.mark.slow
def test_cycles_agrees_with_mitsuba_on_the_volume_scene(grace_context) -> None:
    """The volume probe's scene (a sphere on a plane, Lambert, 6 bounces in both): Cycles and Mitsuba agree per pixel
    and show no bias; the truth flipped upside down and Cycles × 1.01 fail (measured: 100 %, flipped 81.2 %; bias
    0.051, × 1.01 0.199, against 0.0625)."""
    s = settings_mod.Settings(scene_set="quick", kinds=(), scenes=("none",), volume_probe="grace_probe",
                              volume_variants=())
    m = compute_mod.compute(grace_context, s)
    cs = claims_mod.claims(m)
    assert [c.id for c in cs] == ["blender.cycles.volume_grace_probe.agrees_with_mitsuba",
                                  "blender.cycles.volume_grace_probe.unbiased_against_mitsuba"]
    assert all(c.passed and c.power.fails for c in cs), [(c.measured, c.power) for c in cs]
    assert m.volume["variants"] == {} and m.volume["cycles"]["frames"] == s.passes


@pytest.mark.skipif(VERSION is None, reason=f"Blender not installed ({WHY}): {bl.FIX}")
@pytest.mark.slow
def test_soft_shadows_cycles_agrees_and_eevees_light_threshold_fades(tmp_path, monkeypatch) -> None:
    """The sphere and the disc light past the occluder: Cycles agrees with Mitsuba per pixel (the truth mirrored fails:
    measured 12–13 %); EEVEE's lit plane is dark at its default light threshold (measured 0.974 / 0.632) and whole at
    10⁻⁴ (1.0002 / 1.0000)."""
    monkeypatch.setenv("VALIDATE_CACHE", str(tmp_path / "cache"))
    s = settings_mod.Settings(kinds=(), scenes=("none",), soft_shadows=True)
    m = compute_mod.compute(None, s)
    cs = claims_mod.claims(m)
    assert [c.id for c in cs] == ["blender.cycles.shadow_sphere_light.agrees_with_mitsuba",
                                  "blender.cycles.shadow_disc_light.agrees_with_mitsuba"]
    assert all(c.passed and c.power.fails for c in cs), [(c.measured, c.power) for c in cs]
    lit = {k: v["lit"]["ratio"] for k, v in m.shadows.items()}
    assert lit["eevee_jitter_on"] < 0.99 and lit["disc_eevee_jitter_on"] < 0.9
    assert abs(lit["disc_eevee_threshold_low"] - 1.0) < 0.005 and m.shadows["disc_eevee_threshold_low"]["lit"][
        "fraction_accepted"] > MIN_ACCEPTED_LIT
