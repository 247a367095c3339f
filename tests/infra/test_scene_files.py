"""``python -m validate scenes export``: the files read back with an outside loader and say what the scenes are.

Every ``.glb`` loads with pygltflib (and trimesh where installed); the manifest holds to its schema; the geometry,
material, lights (KHR units) and camera read back from the file equal the :class:`RenderScene`; the environment's
stated orientation is Mitsuba's ``envmap`` (measured with ``emitter.eval``); bad manifests are one line.
About 3 s (16² scenes; the sphere meshes are the same at every resolution).
"""

from __future__ import annotations

import json
import math
from dataclasses import fields
from pathlib import Path

import numpy as np
import pytest

from validate.cli import main
from validate.errors import ValidateError
from validate.scenes import render_scenes as rs
from validate.scenes.env_orientation import ORIENTATION, texel_direction, turned_texels
from validate.scenes.gltf_export import EXPORT_SEGMENTS, rotate, sphere_mesh
from validate.scenes.manifest import (
    MANIFEST_SCHEMA,
    PROBE_ROUGHNESS,
    SCHEMA,
    TRUTH_SAMPLES,
    check_manifest,
    load_manifest,
    manifest_scenes,
    schema_errors,
)

RES = 16
# the exported sphere's vertices lie on the unit sphere to float32 rounding (2⁻²⁴ relative, a few ulps summed)
FLOAT32_TOL = 1e-6


@pytest.fixture(scope="module")
def exported(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("scenes")
    assert main(["scenes", "export", str(out), "--set", "full", "--resolution", str(RES)]) == 0
    return out


def _buffer(doc, blob: bytes, accessor: int) -> np.ndarray:
    """An accessor's values (float32 VEC3 rows, or uint32 scalars) from the GLB's binary chunk."""
    a = doc.accessors[accessor]
    bv = doc.bufferViews[a.bufferView]
    dtype = {5126: np.float32, 5125: np.uint32}[a.componentType]
    n = {"VEC3": 3, "SCALAR": 1}[a.type]
    start = bv.byteOffset + (a.byteOffset or 0)
    arr = np.frombuffer(blob[start:start + a.count * n * 4], dtype)
    return arr.reshape(a.count, n) if n > 1 else arr


def test_every_glb_loads_and_matches_its_scene(exported: Path) -> None:
    import pygltflib

    doc = load_manifest(exported)
    assert doc["schema"] == SCHEMA and len(doc["scenes"]) == 14
    for entry, item in manifest_scenes(doc, exported):
        sc = item.scene
        g = pygltflib.GLTF2().load(str(exported / entry["glb"]))
        blob = g.binary_blob()
        assert g.asset.version == "2.0"
        pos, nrm = _buffer(g, blob, 0), _buffer(g, blob, 1)
        tri = _buffer(g, blob, 2).reshape(-1, 3)
        if sc.geometry == "sphere":  # radius 1 at the origin, exact normals, outward winding
            assert np.abs(np.linalg.norm(pos, axis=1) - 1.0).max() < FLOAT32_TOL
            lo, hi = pos.min(axis=0), pos.max(axis=0)  # the centre and the radius along each axis
            assert np.allclose((lo + hi) / 2, 0.0, atol=FLOAT32_TOL) and np.allclose(hi - lo, 2.0, atol=FLOAT32_TOL)
            assert np.array_equal(pos, nrm)
        else:
            assert np.allclose(pos[:, 2], 0.0) and np.abs(pos[:, :2]).max() == rs.PLANE_HALF_SIZE
            assert np.allclose(nrm, [0.0, 0.0, 1.0])
        v0, v1, v2 = (pos[tri[:, k]].astype(np.float64) for k in range(3))
        n_geo = np.cross(v1 - v0, v2 - v0)
        assert (np.linalg.norm(n_geo, axis=1) > 0).all()  # no degenerate triangle
        assert ((n_geo * (nrm[tri[:, 0]] + nrm[tri[:, 1]] + nrm[tri[:, 2]])).sum(1) > 0).all()  # CCW from outside
        pbr = g.materials[0].pbrMetallicRoughness
        assert pbr.baseColorFactor[:3] == list(sc.material.base_color)
        assert (pbr.metallicFactor, pbr.roughnessFactor) == (sc.material.metallic, sc.material.roughness)
        spec = (g.materials[0].extensions or {}).get("KHR_materials_specular", {}).get("specularFactor", 1.0)
        assert spec == sc.material.specular
        cam_node = next(n for n in g.nodes if n.camera is not None)
        cam = g.cameras[cam_node.camera]
        assert cam.type == "orthographic" and cam.orthographic.xmag == cam.orthographic.ymag == rs.HALF_EXTENT
        assert tuple(cam_node.translation) == rs.CAMERA_POSITION and cam_node.rotation is None  # looks down −z
        lights = (g.extensions or {}).get("KHR_lights_punctual", {}).get("lights", [])
        expected = [li for li in sc.lights if not isinstance(li, rs.HemisphereLight)]
        assert len(lights) == len(expected) == len(entry["lights"])
        for li, khr in zip(expected, lights, strict=True):
            node = next(n for n in g.nodes if (n.extensions or {}).get("KHR_lights_punctual", {}).get("light")
                        == lights.index(khr))
            assert khr["intensity"] == li.intensity  # lux (directional) and candela (point, spot): the scene's units
            if hasattr(li, "unit_direction"):  # the node's −z is the direction the light travels
                assert np.allclose(rotate(node.rotation, [0.0, 0.0, -1.0]), li.unit_direction(), atol=1e-12)
            if hasattr(li, "position"):
                assert tuple(node.translation) == tuple(li.position)
            if khr["type"] == "spot":
                assert math.degrees(khr["spot"]["innerConeAngle"]) == pytest.approx(li.inner_deg)
                assert math.degrees(khr["spot"]["outerConeAngle"]) == pytest.approx(li.outer_deg)
        env = entry["environment"]
        has_env = sc.environment is not None or any(isinstance(li, rs.HemisphereLight) for li in sc.lights)
        assert (env is not None) == has_env
        if env is not None:
            assert (exported / env["file"]).is_file()


def test_trimesh_reads_every_glb(exported: Path) -> None:
    trimesh = pytest.importorskip("trimesh")
    doc = json.loads((exported / "manifest.json").read_text())
    meshes = {e["glb"]: 1 for e in doc["scenes"]}  # a sphere or a plane; the authored scenes have one or more
    assert sorted(p.name for p in exported.glob("*.glb")) == sorted([*meshes, *(e["glb"] for e in doc["gltf_scenes"])])
    for p in sorted(exported.glob("*.glb")):
        n = len(trimesh.load(str(p), force="scene").geometry)
        assert n == meshes[p.name] if p.name in meshes else n >= 1, (p.name, n)


def test_environment_files_hold_the_truths_texels(exported: Path) -> None:
    from validate.judge.images import read_engine_image

    doc = load_manifest(exported)
    hemi = next(e for e in doc["scenes"] if e["name"] == "hemisphere_sphere")["environment"]
    img = read_engine_image(exported / hemi["file"], hemi["width"], hemi["height"])
    assert img.precision == "float" and np.array_equal(img.rgb, rs.HEMISPHERE.texels().astype(np.float32))
    furnace = next(e for e in doc["scenes"] if e["name"].startswith("furnace_metal"))["environment"]
    assert furnace["constant_radiance"] == [1.0, 1.0, 1.0]


def test_manifest_holds_to_its_schema_and_rejects_breaks(exported: Path) -> None:
    doc = json.loads((exported / "manifest.json").read_text())
    assert schema_errors(doc, MANIFEST_SCHEMA) == []
    assert json.loads((exported / "manifest.schema.json").read_text()) == MANIFEST_SCHEMA
    broken = json.loads(json.dumps(doc))
    broken["scenes"][0]["lights"] = [{"type": "area", "intensity": -1, "color": [1, 1]}]
    errs = schema_errors(broken, MANIFEST_SCHEMA)
    assert len(errs) == 3 and all(e.startswith("scenes[0].lights[0]") for e in errs)
    newer = dict(doc, schema="validate-scenes/2")
    with pytest.raises(ValidateError, match="newer than this suite reads"):
        check_manifest(newer, "m.json")
    with pytest.raises(ValidateError, match="not a scenes manifest"):
        check_manifest({"scenes": []}, "m.json")


def test_truth_samples_are_the_renders_settings() -> None:
    from validate.experiments.renders.settings import FULL, QUICK

    names = {f.name for f in fields(QUICK)}
    for set_name, s in (("quick", QUICK), ("full", FULL)):
        assert set(TRUTH_SAMPLES[set_name]) <= names
        assert {k: getattr(s, k) for k in TRUTH_SAMPLES[set_name]} == TRUTH_SAMPLES[set_name]


def test_probe_roughness_is_the_renders_settings() -> None:
    from validate.experiments.renders.settings import FULL, QUICK

    assert PROBE_ROUGHNESS == {"quick": QUICK.probe_roughness, "full": FULL.probe_roughness}


def test_stated_orientation_is_mitsubas_envmap() -> None:
    """A map whose texels hold their own (φ, θ): Mitsuba's envmap (the truth's emitter, on the node lattice) returns
    the azimuth and polar angle that ORIENTATION's directions say, so the stated centre, quarter and handedness are
    the truth's."""
    import drjit as dr
    import mitsuba as mi

    from validate.backend import init

    init()
    h, w = 16, 32
    i, j = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    t = np.stack([2 * np.pi * (j + 0.5) / w, np.pi * (i + 0.5) / h, np.ones((h, w))], axis=-1)
    em = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(np.ascontiguousarray(rs.mitsuba_envmap_nodes(t),
                                                                                  np.float32))})
    cases = {"centre_faces": math.pi, "quarter_width_faces": math.pi / 2, "three_quarter_width_faces": 1.5 * math.pi}
    d = np.array([ORIENTATION[k] for k in cases])
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = mi.Vector3f(*(mi.Float(-d[:, k]) for k in range(3)))  # envmap.eval looks along −wi
    v = em.eval(si)
    assert np.allclose(np.array(v[0]), list(cases.values()), atol=1e-5)  # φ
    assert np.allclose(np.array(v[1]), math.pi / 2, atol=1e-5)  # θ: on the horizon
    # and the formula the manifest states gives those directions at the texel coordinates it names
    assert np.allclose(texel_direction(h / 2 - 0.5, w / 2 - 0.5, h, w), ORIENTATION["centre_faces"], atol=1e-12)
    assert np.allclose(texel_direction(h / 2 - 0.5, w / 4 - 0.5, h, w), ORIENTATION["quarter_width_faces"],
                       atol=1e-12)
    assert np.allclose(texel_direction(-0.5, 0, h, w), ORIENTATION["top_row_faces"], atol=1e-12)


def test_turned_variants_move_texels_as_named() -> None:
    """A right-handed turn about +y by +90° takes what was at −z to −x (x' = x cos α + z sin α)."""
    h, w = 8, 16
    t = np.zeros((h, w, 3))
    t[h // 2, 0] = 1.0  # near −z on the horizon (φ = π/16)
    d_before = texel_direction(h // 2, 0, h, w)
    a = math.radians(90)
    rot = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])
    i, j = np.argwhere(turned_texels(t, "turned +90° about +y")[..., 0] == 1.0)[0]
    assert np.allclose(texel_direction(i, j, h, w), rot @ d_before, atol=1e-12)
    i, j = np.argwhere(turned_texels(t, "mirrored in x")[..., 0] == 1.0)[0]
    assert np.allclose(texel_direction(i, j, h, w), d_before * [-1, 1, 1], atol=1e-12)


def test_sphere_mesh_is_closed_and_exact_at_vertices() -> None:
    pos, nrm, tri = sphere_mesh(EXPORT_SEGMENTS)
    n_lon, n_lat = EXPORT_SEGMENTS
    assert len(tri) == 2 * n_lon * (n_lat - 1)  # every band two triangles per segment, the polar ones one


@pytest.mark.parametrize("argv,needle", [
    (["--resolution", "8"], "--resolution 8: need 16..1024"),
])
def test_export_bad_arguments_are_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str],
                                           needle: str) -> None:
    out = tmp_path / "scenes"
    assert main(["scenes", "export", str(out), *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0] and not out.exists()
