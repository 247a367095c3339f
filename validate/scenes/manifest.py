"""Scenes as files: ``python -m validate scenes export DIR`` writes, per render scene, ``<scene>.glb``
(:mod:`validate.scenes.gltf_export`), the environment as a float32 equirect OpenEXR where the scene has one, and
one ``manifest.json`` (schema ``validate-scenes/1``, :data:`MANIFEST_SCHEMA`, documented in docs/scenes.md) that
says per scene what to render and what to write back for ``python -m validate judge``.

The scene set (:func:`scene_set`) is the ``renders`` experiment's (``validate.experiments.renders.compute``
``scene_list``) minus what glTF cannot carry: the white furnace spheres (a), the Lambertian sphere under the sun,
the point light over the plane and beside the sphere, the spot over the plane (c), the hemisphere light (f); the
full set adds the white glTF spheres at metallic 0.5 in the furnace. With ``probes_dir`` (``--probes DIR``) the probe
scenes (b) join: white metal spheres over the set's roughness and the Lambertian sphere under ``rs.PROBE_FILE``
resampled to ``rs.PROBE_SIZE`` (its texels are the exported ``uffizi.exr``, which the judge reads back to rebuild
the scenes). Left out, with the reason in the manifest: the rectangular area lights (d) — KHR_lights_punctual has
directional, point and spot lights only — the probe scenes without ``--probes``, and the glTF material grid under
the probe (its multiscatter reference is a mix of two renders).

Beside them, ``gltf_scenes`` lists the scenes the suite authors as glTF files (:mod:`.gltf_scenes`: the
orientation and units calibration, spheres over metallic × roughness, a box's hard shadows under a directional,
a point and a spot light, a textured bumpy sphere, a room lit through a skylight), perspective, several meshes;
their truth is traced from the file itself through :mod:`validate.reference.gltf_truth` (the route of a user's own
glTF), and their digest is the file's. The key is an addition to schema 1 (a reader of the first version ignores
it), as is an entry's ``truth.also``: the truths the image is also judged against as figures, never deciding (the
room's direct-only truth beside its full transport).

Each scene names the references its truth is made of (:data:`REFERENCES`); the first is the one that decides
whether the scene passes. The truth is the renders experiment's: Mitsuba's ``path`` integrator with
``max_depth = 2`` — direct lighting only, which for a lone convex sphere or a lone plane is the full light
transport (nothing else is there to bounce light back), at the set's samples (:data:`TRUTH_SAMPLES`).
"""

from __future__ import annotations

import hashlib
import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..atomic import atomic_path, write_text
from ..errors import ValidateError
from . import render_scenes as rs
from .env_orientation import ORIENTATION
from .gltf_export import CAMERA_ZFAR, CAMERA_ZNEAR, EXPORT_SEGMENTS, glb_bytes, khr_light, punctual_lights
from .gltf_scenes import ENVIRONMENTS, AuthoredScene, authored_scenes

SCHEMA_NAME = "validate-scenes"
SCHEMA_VERSION = 1
SCHEMA = f"{SCHEMA_NAME}/{SCHEMA_VERSION}"
MANIFEST = "manifest.json"
SETS = ("quick", "full")
MIN_RESOLUTION, MAX_RESOLUTION = 16, 1024  # below 16² the sphere keeps too few pixels inside its 2-px edge mask
# the renders experiment's samples (validate/experiments/renders/settings.py QUICK and FULL; a test holds them equal)
TRUTH_SAMPLES = {"quick": {"spp": 16, "env_spp": 256, "probe_spp": 128, "passes": 8, "seed": 0},
                 "full": {"spp": 128, "env_spp": 1024, "probe_spp": 256, "passes": 8, "seed": 0}}
PROBE_ROUGHNESS = {"quick": (0.25, 0.5), "full": (0.1, 0.2, 0.25, 0.3, 0.5, 0.75, 1.0)}  # the settings' too
PROBE_NAME = "uffizi"
REFERENCES = {
    "energy": "exactly 1 per channel: a white, non-absorbing surface in a uniform radiance-1 furnace returns all "
              "of it (energy conservation, closed form)",
    "model": "Mitsuba roughconductor: glTF's single-scattering GGX metal exactly (its energy loss is the "
             "multiscatter deficit)",
    "mitsuba": "Mitsuba's path tracer on the scene as specified (KHR units, KHR's spot falloff)",
    "gltf": "Mitsuba with the suite's gltf_metallic_roughness BSDF: glTF 2.0 Appendix B as specified",
}
NOT_EXPORTED = {
    "rect_plane, rect_sphere": "rectangular area lights: glTF 2.0 has none (KHR_lights_punctual: directional, point, "
                               "spot)",
    "probe_gltf_*, probe_multiscatter_*": "the glTF material grid under the probe: its multiscatter reference mixes "
                                          "two renders; not exported yet",
}
NO_PROBE = {"probe_*": "the probe scenes need the probe file: export with --probes DIR"}
OUTPUT: dict[str, Any] = {
    "quantity": "linear radiance per channel (W/(sr m^2)) in glTF's units: 1 lux read as 1 W/m^2, 1 cd as 1 W/sr",
    "tone_mapping": "none", "exposure": "none (exposure 1, EV 0, no physical camera)", "bloom": "none",
    "vignette": "none", "dithering": "none", "antialiasing": "none (no MSAA, no TAA jitter, no FXAA)",
    "pixels": "pixel (i, j) (row i from the top, column j from the left) shows the ray through its centre: "
              "x = -xmag + (j + 1/2) 2 xmag / W, y = ymag - (i + 1/2) 2 ymag / H in camera space",
    "alpha": "coverage: 1 where the geometry covers the pixel, 0 where the background shows; the background "
             "itself is not judged (environment hidden from the camera)",
    "formats": ["exr (half or float, channels R G B [A])", "pfm (float, 3 channels; no alpha)"],
    "file": "<scene name>.exr or <scene name>.pfm in one folder",
    "row0": "top",
}


@dataclass(frozen=True)
class SetScene:
    """A scene of the exported set, the renders experiment's ``kind`` (which references its truth has) and the
    names of those references (:data:`REFERENCES`), the first deciding."""

    scene: rs.RenderScene
    kind: str
    references: tuple[str, ...]


def _kind_references(scene: rs.RenderScene, kind: str) -> tuple[str, ...]:
    if kind == "furnace":
        return ("energy", "model") if scene.material.metallic == 1.0 else ("energy",)
    if kind == "furnace_material":
        return ("energy", "gltf")
    return ("mitsuba",)


def scene_set(name: str = "quick", resolution: int = 64, probe: np.ndarray | None = None) -> list[SetScene]:
    """The exported scenes (module docstring) at ``resolution``; ``probe``: the (H, W, 3) probe texels, which add
    the probe scenes."""
    if name not in SETS:
        raise ValidateError(f"--set {name}: not one of {', '.join(SETS)}")
    if not MIN_RESOLUTION <= resolution <= MAX_RESOLUTION:
        raise ValidateError(f"--resolution {resolution}: need {MIN_RESOLUTION}..{MAX_RESOLUTION}")
    pairs = [(sc, "furnace") for sc in rs.furnace_scenes(resolution)]
    pairs += [(rs.lambert_sun_scene(resolution), "directional")]
    pairs += [(sc, "spot" if sc.name.startswith("spot") else "point") for sc in rs.punctual_scenes(resolution)]
    pairs += [(rs.hemisphere_scene(resolution), "hemisphere")]
    if name == "full":
        pairs += [(sc, "furnace_material") for sc in rs.furnace_material_scenes(resolution)]
    if probe is not None:
        pairs += [(sc, "probe") for sc in rs.probe_scenes(probe, PROBE_NAME, resolution, PROBE_ROUGHNESS[name],
                                                          (1.0,))]
        pairs += [(rs.probe_lambert_scene(probe, PROBE_NAME, resolution), "probe_lambert")]
    return [SetScene(sc, kind, _kind_references(sc, kind)) for sc, kind in pairs]


def scene_digest(scene: rs.RenderScene) -> str:
    """A short hash of everything the truth depends on (:meth:`RenderScene.key`)."""
    return hashlib.sha256(rs.describe(scene).encode()).hexdigest()[:16]


def environment_of(scene: rs.RenderScene) -> tuple[str, np.ndarray, list[float] | None] | None:
    """(file stem, (H, W, 3) equirect texels, the constant radiance or None) of the scene's environment: its
    ``Environment`` (a constant one as a 64 × 32 panorama) or its hemisphere light's map; None without one."""
    hemi = [li for li in scene.lights if isinstance(li, rs.HemisphereLight)]
    if hemi:
        return "hemisphere_light", hemi[0].texels(), None
    env = scene.environment
    if env is None:
        return None
    const = None if env.texels is not None else [float(v) for v in env.radiance]
    return env.name, rs.environment_texels(env), const


def exr_bytes(rgb: np.ndarray) -> bytes:
    """A float32 RGB OpenEXR (ZIP) of an (H, W, 3) image, row 0 = top."""
    import tempfile

    import OpenEXR

    with tempfile.TemporaryDirectory(prefix="validate-exr-") as d:
        path = Path(d) / "image.exr"
        header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
        with OpenEXR.File(header, {"RGB": np.ascontiguousarray(rgb, np.float32)}) as f:
            f.write(str(path))
        return path.read_bytes()


def read_exr_rgb(path: Path) -> np.ndarray:
    """(H, W, 3) float64 of an RGB OpenEXR (the exported environments); one-line errors."""
    import OpenEXR

    try:
        with OpenEXR.File(str(path), separate_channels=True) as f:
            ch = {k: np.asarray(v.pixels) for k, v in f.channels().items()}
        return np.stack([ch[c].astype(np.float64) for c in "RGB"], axis=-1)
    except KeyError as exc:
        raise ValidateError(f"{path}: no channel {exc}: need R, G, B") from None
    except Exception as exc:  # OpenEXR's own errors (missing, malformed)
        first = (str(exc).strip().splitlines() or [type(exc).__name__])[-1]
        raise ValidateError(f"{path}: cannot read OpenEXR ({first[:160]})") from None


def scene_entry(item: SetScene, env_file: str | None, env_shape: tuple[int, int] | None,
                constant: list[float] | None) -> dict[str, Any]:
    """The manifest's entry for one scene."""
    sc = item.scene
    r = sc.resolution
    return {
        "name": sc.name, "glb": f"{sc.name}.glb", "kind": item.kind, "digest": scene_digest(sc),
        "image": {"width": r, "height": r, "expected": f"{sc.name}.exr", "also_accepted": f"{sc.name}.pfm"},
        "camera": {"type": "orthographic", "position": list(rs.CAMERA_POSITION), "target": [0.0, 0.0, 0.0],
                   "up": [0.0, 1.0, 0.0], "xmag": rs.HALF_EXTENT, "ymag": rs.HALF_EXTENT, "znear": CAMERA_ZNEAR,
                   "zfar": CAMERA_ZFAR},
        "geometry": ({"type": "sphere", "centre": [0.0, 0.0, 0.0], "radius": 1.0,
                      "mesh_segments": list(EXPORT_SEGMENTS)} if sc.geometry == "sphere" else
                     {"type": "plane", "z": 0.0, "half_size": rs.PLANE_HALF_SIZE, "normal": [0.0, 0.0, 1.0]}),
        "material": sc.material.to_json(),
        "lights": [{**khr_light(li), **({"direction": li.unit_direction().tolist()} if hasattr(li, "unit_direction")
                                        else {}),
                    **({"position": [float(v) for v in li.position]} if hasattr(li, "position") else {})}
                   for li in punctual_lights(sc)],
        "environment": None if env_file is None else {
            "file": env_file, "width": env_shape[1], "height": env_shape[0], "intensity": 1.0,
            "constant_radiance": constant, "visible_to_camera": False, "orientation": "see conventions.environment"},
        "truth": {"transport": "direct", "equals_full_transport": True,
                  "why": "one bounce: a lone convex sphere or a lone plane sees only the lights and the environment",
                  "references": [{"name": k, "meaning": REFERENCES[k]} for k in item.references],
                  "judged_by": item.references[0]},
    }


GLTF_TRUTH_MEANING = ("Mitsuba's path tracer (max_depth 2) on the .glb as validate.scenes.gltf_import reads it back "
                      "(validate.reference.gltf_truth: glTF 2.0 Appendix B with its textures, KHR units, KHR's spot "
                      "falloff), the environment file in conventions.environment")
TRANSPORT_MEANING = {
    "direct": GLTF_TRUTH_MEANING,
    "full": "Mitsuba's path tracer with the full light transport (max_depth -1: unbounded, Russian roulette from "
            "depth 5: unbiased, no bounce left out) on the .glb as validate.scenes.gltf_import reads it back "
            "(validate.reference.gltf_truth), the environment file in conventions.environment",
}
ALSO_ROLE = {"direct": "a figure, not a verdict: the share of the full radiance the direct-only truth lacks (global "
                       "illumination, over the image and over the pixels the direct light does not reach), the share "
                       "the image misses, and whether it matches the direct-only truth"}
PERSPECTIVE_PIXELS = ("pixel (i, j) (row i from the top) shows the ray through its centre: NDC "
                      "x = 2 (j + 1/2) / W - 1, y = 1 - 2 (i + 1/2) / H, "
                      "camera-space direction (x aspectRatio tan(yfov/2), y tan(yfov/2), -1)")


def authored_entry(sc: AuthoredScene, resolution: int, samples: dict[str, int],
                   env_shape: tuple[int, int] | None) -> dict[str, Any]:
    """The manifest's entry for one scene authored as a glTF file (:mod:`.gltf_scenes`): square images of
    ``resolution`` × the scene's ``image_scale``, the truth traced from the file at ``env_spp`` with an
    environment, ``spp`` without (× the scene's ``spp_factor``), in the scene's transport; the truths it is
    also judged against, as figures, under ``truth.also`` (an addition to schema 1 that a reader ignores)."""
    spp = samples["env_spp" if sc.environment is not None else "spp"] * sc.spp_factor
    truth: dict[str, Any] = {
        "transport": sc.transport, "route": "gltf", "note": sc.truth_note, "spp": spp, "passes": samples["passes"],
        "seed": samples["seed"], "references": [{"name": "mitsuba", "meaning": TRANSPORT_MEANING[sc.transport]}],
        "judged_by": "mitsuba"}
    if sc.also:
        truth["also"] = [{"name": a, "transport": a, "spp": spp, "meaning": TRANSPORT_MEANING[a], "role": ALSO_ROLE[a]}
                         for a in sc.also]
    return {
        "name": sc.name, "glb": f"{sc.name}.glb", "digest": hashlib.sha256(sc.glb).hexdigest()[:16],
        "purpose": sc.purpose,
        "image": {"width": resolution * sc.image_scale, "height": resolution * sc.image_scale,
                  "expected": f"{sc.name}.exr",
                  "also_accepted": f"{sc.name}.pfm"},
        "camera": {**sc.camera, "pixels": PERSPECTIVE_PIXELS},
        "lights": [khr_light(li) for li in sc.lights],
        "environment": None if sc.environment is None else {
            "file": f"{sc.environment}.exr", "width": env_shape[1], "height": env_shape[0], "intensity": 1.0,
            "visible_to_camera": False, "orientation": "see conventions.environment"},
        "truth": truth,
    }


def load_probe(probes_dir: Path) -> np.ndarray:
    """``rs.PROBE_FILE`` of ``probes_dir`` resampled to ``rs.PROBE_SIZE`` (the renders experiment's probe)."""
    from .loaders import load_environment

    path = Path(probes_dir) / rs.PROBE_FILE
    if not path.is_file():
        raise ValidateError(f"{path}: no such file (--probes names the folder holding {rs.PROBE_FILE})")
    return rs.resample_probe(load_environment(path, "latlong", False).radiance)


def build_manifest(set_name: str, resolution: int,
                   probe: np.ndarray | None = None) -> tuple[dict[str, Any], dict[str, bytes]]:
    """The manifest and every file it names (name → bytes), nothing written; ``probe``: :func:`load_probe`."""
    items = scene_set(set_name, resolution, probe)
    files: dict[str, bytes] = {}
    envs: dict[str, str] = {}  # file → digest of its texels (one file per distinct environment)
    entries = []
    for item in items:
        env = environment_of(item.scene)
        env_file = shape = const = None
        if env is not None:
            stem, texels, const = env
            env_file = f"{stem}.exr"
            digest = hashlib.sha256(np.ascontiguousarray(texels, np.float32).tobytes()).hexdigest()
            if envs.setdefault(env_file, digest) != digest:
                raise ValidateError(f"{env_file}: two different environments of the same name")
            if env_file not in files:
                files[env_file] = exr_bytes(texels)
            shape = texels.shape[:2]
        files[f"{item.scene.name}.glb"] = glb_bytes(item.scene)
        entries.append(scene_entry(item, env_file, shape, const))
    authored = []
    for sc in authored_scenes():
        shape = None
        if sc.environment is not None:
            texels = ENVIRONMENTS[sc.environment]()
            files.setdefault(f"{sc.environment}.exr", exr_bytes(texels))
            shape = texels.shape[:2]
        files[f"{sc.name}.glb"] = sc.glb
        authored.append(authored_entry(sc, resolution, TRUTH_SAMPLES[set_name], shape))
    doc = {
        "schema": SCHEMA, "generator": "validate scenes export", "set": set_name, "resolution": resolution,
        "conventions": {
            "world": "glTF 2.0: right-handed, +y up, metres; the suite's scene frame is glTF's (no root transform)",
            "units": "KHR_lights_punctual: directional intensity in lux, point and spot in candela; the truth reads "
                     "photometric units as radiometric ones (1 cd = 1 W/sr), as KHR's sample renderers do",
            "environment": ORIENTATION},
        "output": OUTPUT, "truth_samples": TRUTH_SAMPLES[set_name], "scenes": entries, "gltf_scenes": authored,
        "probe": None if probe is None else {"file": f"{PROBE_NAME}.exr", "source": rs.PROBE_FILE,
                                             "resampled_to": list(rs.PROBE_SIZE)},
        "not_exported": [{"name": k, "reason": v} for k, v in {**NOT_EXPORTED,
                                                               **(NO_PROBE if probe is None else {})}.items()],
    }
    check_manifest(doc, MANIFEST)
    return doc, files


def export_scenes(out: Path, set_name: str = "quick", resolution: int = 64,
                  probes_dir: Path | None = None) -> dict[str, Any]:
    """Write every file of :func:`build_manifest` into ``out``, then ``manifest.json`` and
    ``manifest.schema.json`` (each atomically; all are built before the first is written)."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValidateError(f"{out}: exists and is not a folder")
    doc, files = build_manifest(set_name, resolution, None if probes_dir is None else load_probe(probes_dir))
    for name, data in files.items():
        with atomic_path(out / name) as tmp:
            tmp.write_bytes(data)
    write_text(out / "manifest.schema.json", json.dumps(MANIFEST_SCHEMA, indent=1) + "\n")
    write_text(out / MANIFEST, json.dumps(doc, indent=1, ensure_ascii=False) + "\n")
    return doc


# ---------------------------------------------------------------- the schema, and a reader that holds files to it

_VEC3 = {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3}
_GLB = {"type": "string", "pattern": r"^[A-Za-z0-9_.+-]+\.glb$"}
_DIGEST = {"type": "string", "pattern": "^[0-9a-f]{16}$"}
_IMAGE = {"type": "object", "required": ["width", "height", "expected"],
          "properties": {"width": {"type": "integer", "minimum": 1}, "height": {"type": "integer", "minimum": 1},
                         "expected": {"type": "string"}}}
_NAME = {"type": "string", "pattern": r"^[A-Za-z0-9_.+-]+$"}
MANIFEST_SCHEMA: dict[str, Any] = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "title": SCHEMA,
    "type": "object",
    "required": ["schema", "set", "resolution", "conventions", "output", "truth_samples", "scenes"],
    "properties": {
        "schema": {"type": "string", "const": SCHEMA},
        "set": {"type": "string", "enum": list(SETS)},
        "resolution": {"type": "integer", "minimum": MIN_RESOLUTION, "maximum": MAX_RESOLUTION},
        "conventions": {"type": "object", "required": ["world", "units", "environment"]},
        "output": {"type": "object", "required": ["quantity", "tone_mapping", "alpha", "formats", "row0"]},
        "truth_samples": {"type": "object", "required": ["spp", "env_spp", "passes", "seed"],
                          "properties": {k: {"type": "integer", "minimum": 0}
                                         for k in ("spp", "env_spp", "probe_spp", "passes", "seed")}},
        "scenes": {"type": "array", "minItems": 1, "items": {
            "type": "object",
            "required": ["name", "glb", "kind", "digest", "image", "camera", "material", "lights", "environment",
                         "truth"],
            "properties": {
                "name": _NAME, "glb": _GLB,
                "kind": {"type": "string"}, "digest": _DIGEST,
                "image": _IMAGE,
                "camera": {"type": "object", "required": ["type", "position", "target", "up", "xmag", "ymag"],
                           "properties": {"type": {"type": "string", "enum": ["orthographic"]},
                                          "position": _VEC3, "target": _VEC3, "up": _VEC3,
                                          "xmag": {"type": "number"}, "ymag": {"type": "number"}}},
                "material": {"type": "object", "required": ["baseColor", "metallic", "roughness"]},
                "lights": {"type": "array", "items": {
                    "type": "object", "required": ["type", "intensity", "color"],
                    "properties": {"type": {"type": "string", "enum": ["directional", "point", "spot"]},
                                   "intensity": {"type": "number", "minimum": 0}, "color": _VEC3}}},
                "environment": {"type": ["object", "null"], "required": ["file", "width", "height"],
                                "properties": {"file": {"type": "string", "pattern": r"^[A-Za-z0-9_.+-]+\.exr$"},
                                               "width": {"type": "integer", "minimum": 1},
                                               "height": {"type": "integer", "minimum": 1}}},
                "truth": {"type": "object", "required": ["transport", "references", "judged_by"],
                          "properties": {"transport": {"type": "string", "enum": ["direct", "full"]},
                                         "references": {"type": "array", "minItems": 1, "items": {
                                             "type": "object", "required": ["name", "meaning"],
                                             "properties": {"name": {"type": "string",
                                                                     "enum": list(REFERENCES)}}}},
                                         "judged_by": {"type": "string", "enum": list(REFERENCES)}}},
            }}},
        "gltf_scenes": {"type": "array", "items": {
            "type": "object", "required": ["name", "glb", "digest", "image", "camera", "environment", "truth"],
            "properties": {
                "name": _NAME, "glb": _GLB,
                "digest": _DIGEST,
                "image": _IMAGE,
                "camera": {"type": "object", "required": ["type", "position", "target", "up", "yfov", "aspectRatio"],
                           "properties": {"type": {"type": "string", "enum": ["perspective"]},
                                          "position": _VEC3, "target": _VEC3, "up": _VEC3,
                                          "yfov": {"type": "number", "minimum": 0}}},
                "environment": {"type": ["object", "null"], "required": ["file", "width", "height"],
                                "properties": {"file": {"type": "string", "pattern": r"^[A-Za-z0-9_.+-]+\.exr$"}}},
                "truth": {"type": "object", "required": ["transport", "route", "spp", "passes", "seed", "judged_by"],
                          "properties": {"transport": {"type": "string", "enum": ["direct", "full"]},
                                         "route": {"type": "string", "const": "gltf"},
                                         "spp": {"type": "integer", "minimum": 1},
                                         "passes": {"type": "integer", "minimum": 2},
                                         "seed": {"type": "integer", "minimum": 0},
                                         "judged_by": {"type": "string", "const": "mitsuba"},
                                         "also": {"type": "array", "items": {
                                             "type": "object", "required": ["name", "transport", "spp"],
                                             "properties": {"transport": {"type": "string", "enum": ["direct"]},
                                                            "spp": {"type": "integer", "minimum": 1}}}}}},
            }}},
        "probe": {"type": ["object", "null"], "required": ["file"],
                  "properties": {"file": {"type": "string", "pattern": r"^[A-Za-z0-9_.+-]+\.exr$"}}},
        "not_exported": {"type": "array"},
    },
}
_TYPES = {"object": dict, "array": list, "string": str, "number": (int, float), "integer": int, "null": type(None),
          "boolean": bool}


def schema_errors(value: Any, schema: dict[str, Any], where: str = "") -> list[str]:
    """The places where ``value`` breaks ``schema`` — the subset of JSON Schema that :data:`MANIFEST_SCHEMA` uses
    (type, const, enum, pattern, minimum, maximum, required, properties, items, minItems, maxItems); [] when none."""
    at = where or "(top)"
    types = schema.get("type")
    if types is not None:
        names = types if isinstance(types, list) else [types]
        ok = any(isinstance(value, _TYPES[t]) and not (t in ("number", "integer") and isinstance(value, bool))
                 for t in names)
        if not ok:
            return [f"{at}: expected {' or '.join(names)}, got {type(value).__name__}"]
        if value is None:
            return []
    if "const" in schema and value != schema["const"]:
        return [f"{at}: expected {schema['const']!r}, got {value!r}"]
    if "enum" in schema and value not in schema["enum"]:
        return [f"{at}: {value!r} not one of {schema['enum']}"]
    out: list[str] = []
    if isinstance(value, str) and "pattern" in schema and not re.search(schema["pattern"], value):
        out.append(f"{at}: {value!r} does not match {schema['pattern']}")
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if "minimum" in schema and value < schema["minimum"]:
            out.append(f"{at}: {value} below {schema['minimum']}")
        if "maximum" in schema and value > schema["maximum"]:
            out.append(f"{at}: {value} above {schema['maximum']}")
    if isinstance(value, dict):
        out += [f"{at}: missing {k!r}" for k in schema.get("required", ()) if k not in value]
        for k, sub in schema.get("properties", {}).items():
            if k in value:
                out += schema_errors(value[k], sub, f"{where}.{k}" if where else k)
    if isinstance(value, list):
        if len(value) < schema.get("minItems", 0):
            out.append(f"{at}: fewer than {schema['minItems']} items")
        if len(value) > schema.get("maxItems", len(value)):
            out.append(f"{at}: more than {schema['maxItems']} items")
        if "items" in schema:
            for i, v in enumerate(value):
                out += schema_errors(v, schema["items"], f"{at}[{i}]")
    return out


def check_manifest(doc: Any, path: Path | str) -> None:
    """Raise one line naming ``path`` and the first problem: not a manifest, a newer schema version than this
    suite reads, or a break of :data:`MANIFEST_SCHEMA`."""
    tag = doc.get("schema") if isinstance(doc, dict) else None
    m = re.fullmatch(rf"{SCHEMA_NAME}/(\d+)", tag) if isinstance(tag, str) else None
    if m is None:
        raise ValidateError(f"{path}: not a scenes manifest (no \"schema\": \"{SCHEMA}\")")
    if int(m.group(1)) > SCHEMA_VERSION:
        raise ValidateError(f"{path}: manifest schema {tag} is newer than this suite reads ({SCHEMA}); "
                            f"update validate")
    errors = schema_errors(doc, MANIFEST_SCHEMA)
    if errors:
        raise ValidateError(f"{path}: {errors[0]}" + (f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""))
    names = [s["name"] for s in doc["scenes"] + doc.get("gltf_scenes", [])]
    if len(set(names)) != len(names):
        raise ValidateError(f"{path}: a scene name appears twice")


def load_manifest(folder: Path) -> dict[str, Any]:
    """The checked manifest of a scenes folder (``folder`` or its ``manifest.json``)."""
    path = Path(folder)
    if path.is_dir():
        path = path / MANIFEST
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ValidateError(f"{path}: no such file (export the scenes: python -m validate scenes export DIR)") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValidateError(f"{path}: cannot read ({getattr(exc, 'strerror', None) or exc})") from None
    except ValueError as exc:
        raise ValidateError(f"{path}: not valid JSON ({exc})") from None
    check_manifest(doc, path)
    return doc


def manifest_scenes(doc: dict[str, Any], path: Path | str) -> list[tuple[dict[str, Any], SetScene]]:
    """Each manifest entry with the suite's scene of that name, rebuilt (:func:`scene_set` of the manifest's set and
    resolution, and the probe texels read back from the folder's probe file); an entry this suite does not have, or
    whose digest differs, is an error naming it."""
    probe = None
    if doc.get("probe"):
        folder = Path(path) if Path(path).is_dir() else Path(path).parent
        probe = read_exr_rgb(folder / doc["probe"]["file"])
    items = {it.scene.name: it for it in scene_set(doc["set"], doc["resolution"], probe)}
    out = []
    for e in doc["scenes"]:
        it = items.get(e["name"])
        if it is None:
            raise ValidateError(f"{path}: scene {e['name']!r} is not one of this suite's {doc['set']} scenes")
        if scene_digest(it.scene) != e["digest"]:
            raise ValidateError(f"{path}: scene {e['name']!r} differs from this suite's (digest {e['digest']} vs "
                                f"{scene_digest(it.scene)}): export the scenes again")
        out.append((e, it))
    return out
