"""A :class:`~validate.scenes.render_scenes.RenderScene` as a glTF 2.0 binary (``.glb``) any engine loads [1].

What the file holds, and how each part maps from the scene (conventions: :mod:`validate.scenes.render_scenes`):

* World: glTF's frame is the scene's — right-handed, +y up, metres; no root transform.
* Geometry: the sphere of radius 1 at the origin as a UV sphere of ``EXPORT_SEGMENTS`` (longitude, latitude)
  with exact unit normals at the vertices (``NORMAL`` = ``POSITION``), or the plane z = 0, half-size
  ``PLANE_HALF_SIZE``, normal +z. Triangles wind counter-clockwise seen from outside (glTF's front face [1,
  3.7.2.1]). The truth traces the analytic sphere; the chord of a 256-segment ring lies at most
  1 − cos(π/256) = 7.5e-5 inside it (0.2 % of a 64² pixel), so the mesh does not enter the budgets.
* Material: ``pbrMetallicRoughness`` — ``baseColorFactor`` (linear, alpha 1), ``metallicFactor``,
  ``roughnessFactor``; no textures. A material without the dielectric specular layer (``specular = 0``, the
  Lambertian scenes) carries ``KHR_materials_specular`` with ``specularFactor = 0`` [2].
* Lights: ``KHR_lights_punctual`` [3] in its own units, which are the scene's — directional: ``intensity`` in lux,
  the node's −z axis the direction the light travels; point: candela at the node's translation; spot: candela on
  the axis (node −z), ``innerConeAngle``/``outerConeAngle`` in radians from the axis, KHR's reference falloff (the
  truth's, ``SpotLight.profile = "gltf"``). No ``range`` (infinite: the inverse square law with no window).
  A hemisphere light is not a punctual light: it leaves as the scene's environment (:mod:`.manifest`).
* Camera: one ``orthographic`` camera at ``CAMERA_POSITION`` looking down −z (glTF cameras look along their
  local −z), ``xmag = ymag = HALF_EXTENT`` (glTF's xmag is the half width), square aspect.
* The environment is not in the file (glTF has no ratified image-based-light extension); the manifest names its
  equirect file and orientation.

References
----------
[1] Khronos, glTF 2.0 Specification (3.5 cameras, 3.7 meshes, 3.9 materials, 4.4 GLB).
[2] Khronos, KHR_materials_specular (specularFactor scales F0 and F90 of the dielectric layer).
[3] Khronos, KHR_lights_punctual ("directional: lux", "point and spot: candela", "Inner and Outer Cone Angles").
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

from ..errors import ValidateError
from .render_scenes import (
    CAMERA_POSITION,
    HALF_EXTENT,
    PLANE_HALF_SIZE,
    DirectionalLight,
    HemisphereLight,
    PointLight,
    RenderScene,
    SpotLight,
)

EXPORT_SEGMENTS = (256, 128)  # (longitude, latitude) of the exported UV sphere (module docstring: chord 7.5e-5)
CAMERA_ZNEAR, CAMERA_ZFAR = 0.01, 100.0  # the camera is 5 m from the origin; everything lies within 4–6 m
GENERATOR = "validate scenes export"
_FLOAT, _UINT32 = 5126, 5125  # glTF componentType
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963


def sphere_mesh(segments: tuple[int, int] = EXPORT_SEGMENTS) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(positions (V, 3) float32, normals (V, 3) float32, indices (T, 3) uint32) of the unit UV sphere: ring i at
    θ = π i/n_lat from +y, column j at φ = 2π j/n_lon, p = (sin θ sin φ, cos θ, sin θ cos φ) (a seam column is
    duplicated; no triangle is degenerate), counter-clockwise seen from outside."""
    n_lon, n_lat = segments
    if n_lon < 3 or n_lat < 2:
        raise ValidateError(f"sphere mesh: segments {segments}: need at least (3, 2)")
    th = np.linspace(0.0, np.pi, n_lat + 1)[:, None]
    ph = np.linspace(0.0, 2.0 * np.pi, n_lon + 1)[None, :]
    p = np.stack(np.broadcast_arrays(np.sin(th) * np.sin(ph), np.cos(th), np.sin(th) * np.cos(ph)), axis=-1)
    p = p.reshape(-1, 3)
    idx = np.arange((n_lat + 1) * (n_lon + 1)).reshape(n_lat + 1, n_lon + 1)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]  # a-d on ring i, b-c on ring i + 1
    upper = np.stack([a, b, c], axis=-1)[:-1].reshape(-1, 3)  # on the last band b and c are the south pole
    lower = np.stack([a, c, d], axis=-1)[1:].reshape(-1, 3)  # on the first band a and d are the north pole
    tri = _outward(p, np.concatenate([upper, lower]))
    return p.astype(np.float32), p.astype(np.float32), tri.astype(np.uint32)


def _outward(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """``tri`` with every triangle wound counter-clockwise seen from outside (normal · centroid > 0)."""
    v0, v1, v2 = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    flip = (np.cross(v1 - v0, v2 - v0) * (v0 + v1 + v2)).sum(-1) < 0
    out = tri.copy()
    out[flip] = out[flip][:, [0, 2, 1]]
    return out


def plane_mesh(half_size: float = PLANE_HALF_SIZE) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The square z = 0 of ``half_size``, normal +z, two triangles counter-clockwise seen from +z."""
    s = half_size
    p = np.array([[-s, -s, 0.0], [s, -s, 0.0], [s, s, 0.0], [-s, s, 0.0]], np.float32)
    n = np.tile(np.array([0.0, 0.0, 1.0], np.float32), (4, 1))
    return p, n, np.array([[0, 1, 2], [0, 2, 3]], np.uint32)


def quaternion_to(direction: np.ndarray) -> list[float]:
    """glTF rotation [x, y, z, w] turning the node's −z onto the unit ``direction`` (shortest arc; half a turn
    about +y when ``direction`` is +z)."""
    a = np.array([0.0, 0.0, -1.0])
    b = np.asarray(direction, np.float64) / np.linalg.norm(direction)
    c = float(a @ b)
    if c < -1.0 + 1e-12:
        return [0.0, 1.0, 0.0, 0.0]
    axis = np.cross(a, b)
    w = 1.0 + c
    q = np.array([*axis, w])
    q /= np.linalg.norm(q)
    return [float(v) for v in q]


def rotate(q: list[float], v: np.ndarray) -> np.ndarray:
    """``v`` rotated by the unit quaternion ``q`` = [x, y, z, w] (for reading a file back)."""
    u, w = np.asarray(q[:3], np.float64), float(q[3])
    v = np.asarray(v, np.float64)
    return v + 2.0 * w * np.cross(u, v) + 2.0 * np.cross(u, np.cross(u, v))


def khr_light(li: Any) -> dict[str, Any]:
    """The ``KHR_lights_punctual`` light object of a scene light (its units are KHR's: module docstring)."""
    base = {"color": [float(c) for c in li.color], "intensity": float(li.intensity)}
    if isinstance(li, DirectionalLight):
        return {"type": "directional", **base}
    if isinstance(li, PointLight):
        return {"type": "point", **base}
    if isinstance(li, SpotLight):
        if li.profile != "gltf":
            raise ValidateError(f"spot light: profile {li.profile!r}: glTF files carry KHR's falloff only")
        return {"type": "spot", **base, "spot": {"innerConeAngle": math.radians(li.inner_deg),
                                                 "outerConeAngle": math.radians(li.outer_deg)}}
    raise ValidateError(f"{type(li).__name__}: not a KHR_lights_punctual light")


def light_node(li: Any, k: int) -> dict[str, Any]:
    """The node that places light ``k``: rotation (directional, spot) and translation (point, spot)."""
    node: dict[str, Any] = {"name": f"light{k}", "extensions": {"KHR_lights_punctual": {"light": k}}}
    if isinstance(li, (DirectionalLight, SpotLight)):
        node["rotation"] = quaternion_to(li.unit_direction())
    if isinstance(li, (PointLight, SpotLight)):
        node["translation"] = [float(v) for v in li.position]
    return node


def punctual_lights(scene: RenderScene) -> list[Any]:
    """The scene's lights that are KHR punctual lights (a hemisphere light leaves as the environment)."""
    out = []
    for li in scene.lights:
        if isinstance(li, HemisphereLight):
            continue
        if not isinstance(li, (DirectionalLight, PointLight, SpotLight)):
            raise ValidateError(f"{scene.name}: {type(li).__name__} has no glTF 2.0 counterpart")
        out.append(li)
    return out


def scene_gltf(scene: RenderScene, segments: tuple[int, int] = EXPORT_SEGMENTS) -> Any:
    """The :class:`pygltflib.GLTF2` of ``scene`` (module docstring), its binary buffer attached."""
    import pygltflib as g

    pos, nrm, tri = sphere_mesh(segments) if scene.geometry == "sphere" else plane_mesh()
    blobs = [pos.tobytes(), nrm.tobytes(), tri.tobytes()]
    offsets = np.cumsum([0, *(len(b) for b in blobs)])
    m = scene.material
    ext_used: list[str] = []
    mat_ext: dict[str, Any] = {}
    if m.specular != 1.0:
        mat_ext["KHR_materials_specular"] = {"specularFactor": float(m.specular)}
        ext_used.append("KHR_materials_specular")
    lights = punctual_lights(scene)
    if lights:
        ext_used.append("KHR_lights_punctual")
    nodes = [g.Node(name=scene.geometry, mesh=0),
             g.Node(name="camera", camera=0, translation=[float(v) for v in CAMERA_POSITION])]
    nodes += [g.Node(**light_node(li, k)) for k, li in enumerate(lights)]
    doc = g.GLTF2(
        asset=g.Asset(version="2.0", generator=GENERATOR),
        scene=0,
        scenes=[g.Scene(name=scene.name, nodes=list(range(len(nodes))))],
        nodes=nodes,
        meshes=[g.Mesh(name=scene.geometry, primitives=[g.Primitive(
            attributes=g.Attributes(POSITION=0, NORMAL=1), indices=2, material=0, mode=4)])],
        materials=[g.Material(name="material", pbrMetallicRoughness=g.PbrMetallicRoughness(
            baseColorFactor=[*(float(c) for c in m.base_color), 1.0], metallicFactor=float(m.metallic),
            roughnessFactor=float(m.roughness)), doubleSided=False, extensions=mat_ext)],
        cameras=[g.Camera(type="orthographic", orthographic=g.Orthographic(
            xmag=HALF_EXTENT, ymag=HALF_EXTENT, znear=CAMERA_ZNEAR, zfar=CAMERA_ZFAR))],
        accessors=[
            g.Accessor(bufferView=0, componentType=_FLOAT, count=len(pos), type="VEC3",
                       min=pos.min(axis=0).tolist(), max=pos.max(axis=0).tolist()),
            g.Accessor(bufferView=1, componentType=_FLOAT, count=len(nrm), type="VEC3"),
            g.Accessor(bufferView=2, componentType=_UINT32, count=int(tri.size), type="SCALAR")],
        bufferViews=[g.BufferView(buffer=0, byteOffset=int(offsets[0]), byteLength=len(blobs[0]), target=_ARRAY_BUFFER),
                     g.BufferView(buffer=0, byteOffset=int(offsets[1]), byteLength=len(blobs[1]), target=_ARRAY_BUFFER),
                     g.BufferView(buffer=0, byteOffset=int(offsets[2]), byteLength=len(blobs[2]),
                                  target=_ELEMENT_ARRAY_BUFFER)],
        buffers=[g.Buffer(byteLength=int(offsets[-1]))],
        extensionsUsed=ext_used,
        extensions={"KHR_lights_punctual": {"lights": [khr_light(li) for li in lights]}} if lights else {},
    )
    doc.set_binary_blob(b"".join(blobs))
    return doc


def glb_bytes(scene: RenderScene, segments: tuple[int, int] = EXPORT_SEGMENTS) -> bytes:
    """The ``.glb`` of ``scene`` (:func:`scene_gltf`)."""
    return b"".join(bytes(p) for p in scene_gltf(scene, segments).save_to_bytes())


def check_glb(path: Any) -> Any:
    """Read ``path`` as a glTF 2.0 binary and return its :class:`pygltflib.GLTF2`; one line naming the file and the
    problem when it is missing or malformed (GLB header [1, 4.4]: magic ``glTF``, version 2, the stated length;
    a JSON chunk that parses; ``asset.version`` 2.x; the scene's mesh, camera and buffer present)."""
    import struct
    from pathlib import Path

    import pygltflib

    p = Path(path)
    try:
        data = p.read_bytes()
    except FileNotFoundError:
        raise ValidateError(f"{p}: no such file") from None
    except OSError as exc:
        raise ValidateError(f"{p}: cannot read ({exc.strerror or exc})") from None
    if len(data) < 20 or data[:4] != b"glTF":
        raise ValidateError(f"{p}: not a glTF binary (no 'glTF' magic)")
    version, length = struct.unpack_from("<II", data, 4)
    if version != 2 or length != len(data):
        raise ValidateError(f"{p}: malformed GLB header (version {version}, length {length} of {len(data)} bytes)")
    chunk_len, chunk_type = struct.unpack_from("<II", data, 12)
    try:
        if chunk_type != 0x4E4F534A:  # "JSON"
            raise ValueError("the first chunk is not JSON")
        json.loads(data[20:20 + chunk_len].decode("utf-8"))
        doc = pygltflib.GLTF2.load_from_bytes(data)
    except Exception as exc:  # pygltflib and json raise many kinds; one line either way
        first = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        raise ValidateError(f"{p}: malformed glTF ({first[:160]})") from None
    if doc is None or doc.asset is None or not str(doc.asset.version).startswith("2."):
        version = getattr(getattr(doc, "asset", None), "version", None)
        raise ValidateError(f"{p}: not glTF 2.x (asset.version {version})")
    if not doc.meshes or not doc.cameras or not doc.buffers:
        raise ValidateError(f"{p}: no mesh, camera or buffer: not a scene exported by validate")
    return doc
