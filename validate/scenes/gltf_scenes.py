"""Scenes the suite authors as glTF files (perspective cameras, several meshes), judged through the glTF truth path.

The sphere and plane scenes of :mod:`.manifest` are the renders experiment's, rebuilt from Python on both sides.
These are authored as ``.glb`` files directly and their truth is whatever :func:`validate.scenes.gltf_import.read_gltf`
reads back from the file, traced by :func:`validate.reference.gltf_truth.render_gltf_truth` — the path a user's own
glTF takes — so the file is the whole scene (its digest is the file's content hash).

* ``calibration_mirror`` and ``calibration_lambert``: the orientation and units calibration. The environment
  ``calibration_markers.exr`` is a dim grey (:data:`BACKGROUND`) equirect with a bright disc of a distinct colour
  on each of ±x, ±y, ±z (:data:`MARKERS`, angular radius :data:`MARKER_RADIUS_DEG`) in the orientation of
  :mod:`.env_orientation`; the camera (perspective, at +z looking at the origin) sees a mirror sphere (metallic 1,
  roughness 0, base colour 1: it shows the environment's radiance unscaled, so the markers' places give the
  rotation and handedness) or a Lambertian one (base colour 0.8, ``KHR_materials_specular`` 0: the irradiance, so
  the overall scale). Each is a lone sphere, so the direct-lighting truth is the full light transport and an
  engine with image-based lighting and no occlusion term has nothing to miss; side by side in one file the
  spheres would shadow and mirror one another, which no engine without global illumination shows.
* ``metal_rough_spheres``: 3 × 3 spheres, metallic :data:`GRID_METALLIC` (rows, top to bottom) × roughness
  :data:`GRID_ROUGHNESS` (columns, left to right), one gold base colour, under the procedural sky
  ``sky.exr`` (:func:`sky_texels`), perspective. The spheres occlude part of one another's sky: the truth is
  direct lighting with that occlusion (what a path tracer's first bounce sees); an engine without environment
  occlusion is brighter on the sides that face a neighbour. Its image is twice the export's resolution a side
  (nine spheres need the pixels).
* ``shadow_directional``, ``shadow_point``, ``shadow_spot``: a box (:data:`BOX_HALF`, floating
  :data:`BOX_GAP` m above the ground) over a Lambertian ground plane (y = 0, half-size :data:`GROUND_HALF`),
  lit by one KHR punctual light each, no environment: hard shadows. Direct lighting only (the truth and an
  engine without global illumination agree on what is computed).
* ``textured_bumpy_sphere``: a sphere whose radius is modulated by a bump field, with UVs and tangents, and
  base-colour (checker), metallic-roughness (stripes) and normal (a bump pattern) textures made by the suite,
  under the sky, perspective.
* ``room_opening``: a closed room (:data:`ROOM_MIN`–:data:`ROOM_MAX`), every wall single-sided facing in
  (:func:`room_meshes`), Lambertian: white (:data:`WALL_ALBEDO`) but for the red left wall (:data:`RED_WALL`),
  lit by the sun :data:`ROOM_SUN` through a skylight (:data:`ROOM_OPENING`) onto the floor and the back wall, no
  environment, the camera in a corner. Most of what the camera sees is lit by light that bounced (and the red
  wall bleeds): the truth that decides is the full light transport, and the direct-only truth is judged beside it
  as a figure — the share an engine without global illumination misses (``AuthoredScene.also``).

Truth: Mitsuba ``path`` with ``max_depth = 2`` (``transport`` "direct"; the room: "full", max_depth −1 with
Russian roulette, :data:`validate.reference.gltf_truth.TRANSPORTS`) at the manifest's samples (``spp`` for
punctual lights, ``env_spp`` with an environment, × the scene's ``spp_factor``), the manifest's passes and seed.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .env_orientation import texel_direction
from .gltf_export import GENERATOR, khr_light, quaternion_to, sphere_mesh
from .render_scenes import DirectionalLight, PointLight, SpotLight

_FLOAT, _UINT32 = 5126, 5125
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963

ENV_SIZE = (64, 128)  # (H, W) of the authored environments; W a multiple of 4 (quarter turns are whole columns)
BACKGROUND = 0.05  # the calibration environment's grey radiance
MARKER_RADIANCE = 4.0
MARKER_RADIUS_DEG = 16.0
MARKERS: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "+x": ((1.0, 0.0, 0.0), (1.0, 0.1, 0.1)),  # red
    "-x": ((-1.0, 0.0, 0.0), (0.1, 1.0, 1.0)),  # cyan
    "+y": ((0.0, 1.0, 0.0), (0.1, 1.0, 0.1)),  # green
    "-y": ((0.0, -1.0, 0.0), (1.0, 0.1, 1.0)),  # magenta
    "+z": ((0.0, 0.0, 1.0), (0.1, 0.1, 1.0)),  # blue
    "-z": ((0.0, 0.0, -1.0), (1.0, 1.0, 0.1)),  # yellow
}
GRID_METALLIC = (1.0, 0.5, 0.0)
GRID_ROUGHNESS = (0.15, 0.5, 1.0)
GOLD = (1.0, 0.766, 0.336)
BOX_HALF, BOX_GAP, GROUND_HALF = 0.4, 0.3, 2.5
MIRROR_ROUGHNESS = 0.05  # alpha = 0.0025: a mirror to the 48-128 px images (exactly 0 gives the sampler NaNs)
SEGMENTS = (128, 64)  # the authored spheres' (longitude, latitude) segments
ROOM_MIN, ROOM_MAX = (-2.0, 0.0, -2.0), (2.0, 2.4, 2.0)  # the room's inside (x, y, z), metres
ROOM_OPENING = ((-1.0, 1.0), (-1.2, 0.4))  # the skylight in the ceiling: x range, z range
ROOM_SUN = DirectionalLight((-0.3, -1.0, -0.4), 5.0)  # through the skylight onto the floor and the back wall
WALL_ALBEDO, RED_WALL = (0.8, 0.8, 0.8), (0.8, 0.15, 0.1)  # white walls; the left wall (x = −2) red
# the full transport's noise: at 4 x the set's spp (64 x 8 passes, quick) the median relative standard error on the
# walls the sun does not reach is 16 % at 64² (p95 28 %), so an image without their bounced light is rejected there
ROOM_SPP_FACTOR = 4
ROOM_OVERLAP = 0.02  # each wall runs this far past the room's edges, so no ray slips between two meshes


def marker_texels(height: int = ENV_SIZE[0], width: int = ENV_SIZE[1]) -> np.ndarray:
    """(H, W, 3) calibration environment: :data:`BACKGROUND` grey with a disc of :data:`MARKER_RADIUS_DEG` around
    each axis in its colour × :data:`MARKER_RADIANCE` (texel directions: :mod:`.env_orientation`)."""
    i, j = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
    d = texel_direction(i, j, height, width)
    out = np.full((height, width, 3), BACKGROUND)
    cos_r = math.cos(math.radians(MARKER_RADIUS_DEG))
    for axis, colour in MARKERS.values():
        inside = d @ np.asarray(axis) > cos_r
        out[inside] = MARKER_RADIANCE * np.asarray(colour)
    return out


def sky_texels(height: int = ENV_SIZE[0], width: int = ENV_SIZE[1]) -> np.ndarray:
    """(H, W, 3) procedural sky: blue above the horizon brightening towards it, brown ground below, and a soft
    warm sun (a Gaussian lobe of 20° about (0.5, 0.6, 0.62)) — smooth, so a rough sphere's truth converges fast."""
    i, j = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
    d = texel_direction(i, j, height, width)
    up = d[..., 1:2]
    sky = np.where(up > 0, np.array([0.25, 0.45, 0.9]) * (1.0 - 0.6 * up) + 0.2, np.array([0.18, 0.14, 0.1]))
    sun = np.array([0.5, 0.6, 0.62])
    sun /= np.linalg.norm(sun)
    ang = np.arccos(np.clip(d @ sun, -1.0, 1.0))[..., None]
    return sky + np.array([3.0, 2.5, 1.8]) * np.exp(-0.5 * (ang / math.radians(20.0)) ** 2)


# ---------------------------------------------------------------- meshes


def box_mesh(half: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The cube [−half, half]³: 24 vertices (flat normals per face), 12 triangles counter-clockwise from outside."""
    pos, nrm, tri = [], [], []
    for axis in range(3):
        for sign in (1.0, -1.0):
            n = np.zeros(3)
            n[axis] = sign
            u = np.zeros(3)
            u[(axis + 1) % 3] = 1.0
            v = np.cross(n, u)
            k = len(pos)
            pos += [half * (n + a * u + b * v) for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
            nrm += [n] * 4
            tri += [[k, k + 1, k + 2], [k, k + 2, k + 3]]
    return np.asarray(pos, np.float32), np.asarray(nrm, np.float32), np.asarray(tri, np.uint32)


def ground_mesh(half: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The square y = 0 of ``half``, normal +y, counter-clockwise seen from above."""
    p = np.array([[-half, 0, half], [half, 0, half], [half, 0, -half], [-half, 0, -half]], np.float32)
    return p, np.tile(np.array([0, 1, 0], np.float32), (4, 1)), np.array([[0, 1, 2], [0, 2, 3]], np.uint32)


def rect_mesh(rects: list[tuple[int, float, float, tuple[float, float], tuple[float, float]]]
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Axis-aligned rectangles (axis, its value, the normal's sign, the ranges of the next two axes in cyclic order)
    as one mesh: flat normals along ±axis, each counter-clockwise seen from the side its normal points to."""
    pos, nrm, tri = [], [], []
    for axis, value, sign, (a0, a1), (b0, b1) in rects:
        ia, ib = (axis + 1) % 3, (axis + 2) % 3
        k = len(pos)
        corners = [(a0, b0), (a1, b0), (a1, b1), (a0, b1)]  # counter-clockwise about e_a × e_b = e_axis
        for a, b in corners if sign > 0 else corners[::-1]:
            p = np.zeros(3)
            p[axis], p[ia], p[ib] = value, a, b
            pos.append(p)
        n = np.zeros(3)
        n[axis] = sign
        nrm += [n] * 4
        tri += [[k, k + 1, k + 2], [k, k + 2, k + 3]]
    return np.asarray(pos, np.float32), np.asarray(nrm, np.float32), np.asarray(tri, np.uint32)


def room_meshes() -> tuple[list[tuple[int, float, float, tuple[float, float], tuple[float, float]]],
                           list[tuple[int, float, float, tuple[float, float], tuple[float, float]]]]:
    """(the white rectangles, the red one) of the closed room :data:`ROOM_MIN`–:data:`ROOM_MAX`, every normal
    inward: floor, the ceiling around the skylight :data:`ROOM_OPENING` (four pieces), the back (z min), front
    (z max) and right (x max) walls white, the left wall (x min) red."""
    (x0, y0, z0), (x1, y1, z1), e = ROOM_MIN, ROOM_MAX, ROOM_OVERLAP
    (hx0, hx1), (hz0, hz1) = ROOM_OPENING
    white = [(1, y0, 1.0, (z0 - e, z1 + e), (x0 - e, x1 + e)),  # floor (axis y: ranges z, x)
             (1, y1, -1.0, (z0 - e, z1 + e), (x0 - e, hx0)), (1, y1, -1.0, (z0 - e, z1 + e), (hx1, x1 + e)),
             (1, y1, -1.0, (z0 - e, hz0), (hx0, hx1)), (1, y1, -1.0, (hz1, z1 + e), (hx0, hx1)),  # ceiling
             (2, z0, 1.0, (x0 - e, x1 + e), (y0 - e, y1 + e)), (2, z1, -1.0, (x0 - e, x1 + e), (y0 - e, y1 + e)),
             (0, x1, -1.0, (y0 - e, y1 + e), (z0 - e, z1 + e))]  # back, front (axis z: x, y), right (axis x: y, z)
    red = [(0, x0, 1.0, (y0 - e, y1 + e), (z0 - e, z1 + e))]
    return white, red


def bump(p: np.ndarray) -> np.ndarray:
    """The bumpy sphere's radius at the unit directions ``p``: 1 + 0.06 sin(5 φ) sin(4 θ)-like ripples."""
    return 1.0 + 0.05 * np.sin(6.0 * p[..., 0]) * np.sin(6.0 * p[..., 1]) * np.sin(6.0 * p[..., 2] + 0.5)


def bumpy_sphere_mesh(segments: tuple[int, int] = SEGMENTS) -> dict[str, np.ndarray]:
    """UV sphere displaced by :func:`bump`: positions, normals (of the displaced surface, by finite differences on
    the grid), uv (u = φ/2π, v = θ/π), tangents (∂p/∂u normalised, w = 1) and triangles."""
    n_lon, n_lat = segments
    th = np.linspace(0.0, np.pi, n_lat + 1)[:, None]
    ph = np.linspace(0.0, 2.0 * np.pi, n_lon + 1)[None, :]

    def surf(t: np.ndarray, f: np.ndarray) -> np.ndarray:
        d = np.stack(np.broadcast_arrays(np.sin(t) * np.sin(f), np.cos(t), np.sin(t) * np.cos(f)), axis=-1)
        return d * bump(d)[..., None]

    p = surf(th, ph)
    e = 1e-4
    dth = surf(th + e, ph) - surf(th - e, ph)
    dph = surf(th, ph + e) - surf(th, ph - e)
    nrm = np.cross(dph, dth)
    ln = np.linalg.norm(nrm, axis=-1, keepdims=True)
    radial = p / np.linalg.norm(p, axis=-1, keepdims=True)
    nrm = np.where(ln > 1e-9, nrm / np.maximum(ln, 1e-30), radial)  # the poles: the radial direction
    nrm = np.where((nrm * radial).sum(-1, keepdims=True) < 0, -nrm, nrm)
    tan = dph / np.maximum(np.linalg.norm(dph, axis=-1, keepdims=True), 1e-30)
    tan = np.where(np.linalg.norm(dph, axis=-1, keepdims=True) > 1e-9, tan, np.array([1.0, 0.0, 0.0]))
    tan = tan - (tan * nrm).sum(-1, keepdims=True) * nrm
    tan /= np.maximum(np.linalg.norm(tan, axis=-1, keepdims=True), 1e-30)
    uv = np.stack(np.broadcast_arrays(ph / (2 * np.pi) + 0 * th, th / np.pi + 0 * ph), axis=-1)
    _, _, tri = sphere_mesh(segments)
    t4 = np.concatenate([tan, np.ones(tan.shape[:-1] + (1,))], axis=-1)
    return {"POSITION": p.reshape(-1, 3).astype(np.float32), "NORMAL": nrm.reshape(-1, 3).astype(np.float32),
            "TEXCOORD_0": uv.reshape(-1, 2).astype(np.float32), "TANGENT": t4.reshape(-1, 4).astype(np.float32),
            "indices": tri}


def textures(size: int = 64) -> dict[str, np.ndarray]:
    """The textured sphere's maps (uint8 RGB, row 0 at v = 0): a checker base colour (sRGB), metallic-roughness
    stripes (G roughness 0.3/0.8 by row band, B metallic 0/1 by column band) and a tangent-space normal map of
    bumps (+Y up)."""
    v, u = np.meshgrid((np.arange(size) + 0.5) / size, (np.arange(size) + 0.5) / size, indexing="ij")
    check = ((np.floor(u * 8) + np.floor(v * 4)) % 2)[..., None]
    base = np.where(check > 0, np.array([200, 60, 40]), np.array([230, 220, 200]))
    mr = np.zeros((size, size, 3))
    mr[..., 1] = np.where(np.floor(v * 4) % 2 > 0, 0.8, 0.3) * 255
    mr[..., 2] = np.where(np.floor(u * 4) % 2 > 0, 1.0, 0.0) * 255
    hx = 0.6 * np.cos(2 * np.pi * 12 * u) * np.sin(2 * np.pi * 6 * v)
    hy = 0.6 * np.sin(2 * np.pi * 12 * u) * np.cos(2 * np.pi * 6 * v)
    n = np.stack([-hx, -hy, np.ones_like(hx)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return {"base": base.astype(np.uint8), "mr": np.round(mr).astype(np.uint8),
            "normal": np.round((n * 0.5 + 0.5) * 255).astype(np.uint8)}


def png_bytes(rgb: np.ndarray) -> bytes:
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(rgb, "RGB").save(buf, format="PNG")
    return buf.getvalue()


# ---------------------------------------------------------------- a tiny glTF builder


@dataclass
class _Builder:
    """Accumulates buffer views, accessors, meshes, materials, images and nodes of one file."""

    blob: bytearray = field(default_factory=bytearray)
    views: list[Any] = field(default_factory=list)
    accessors: list[Any] = field(default_factory=list)
    meshes: list[Any] = field(default_factory=list)
    materials: list[Any] = field(default_factory=list)
    images: list[Any] = field(default_factory=list)
    textures: list[Any] = field(default_factory=list)
    nodes: list[Any] = field(default_factory=list)
    lights: list[dict[str, Any]] = field(default_factory=list)
    ext_used: set[str] = field(default_factory=set)

    def view(self, data: bytes, target: int | None) -> int:
        import pygltflib as g

        while len(self.blob) % 4:
            self.blob += b"\0"
        self.views.append(g.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=len(data), target=target))
        self.blob += data
        return len(self.views) - 1

    def accessor(self, arr: np.ndarray, kind: str) -> int:
        import pygltflib as g

        if kind == "indices":
            v = self.view(np.ascontiguousarray(arr, np.uint32).tobytes(), _ELEMENT_ARRAY_BUFFER)
            self.accessors.append(g.Accessor(bufferView=v, componentType=_UINT32, count=int(arr.size), type="SCALAR"))
        else:
            a = np.ascontiguousarray(arr, np.float32)
            v = self.view(a.tobytes(), _ARRAY_BUFFER)
            mm = {"min": a.min(axis=0).tolist(), "max": a.max(axis=0).tolist()} if kind == "POSITION" else {}
            self.accessors.append(g.Accessor(bufferView=v, componentType=_FLOAT, count=len(a),
                                             type=f"VEC{a.shape[1]}", **mm))
        return len(self.accessors) - 1

    def geometry(self, arrays: dict[str, np.ndarray]) -> dict[str, int]:
        return {k: self.accessor(a, k) for k, a in arrays.items()}

    def material(self, name: str, base: tuple[float, ...], metallic: float, roughness: float,
                 specular: float | None = None, **tex: int) -> int:
        import pygltflib as g

        ext = {}
        if specular is not None:
            ext["KHR_materials_specular"] = {"specularFactor": specular}
            self.ext_used.add("KHR_materials_specular")
        pbr = g.PbrMetallicRoughness(baseColorFactor=[*map(float, base), 1.0], metallicFactor=float(metallic),
                                     roughnessFactor=float(roughness))
        if "base_tex" in tex:
            pbr.baseColorTexture = g.TextureInfo(index=tex["base_tex"])
        if "mr_tex" in tex:
            pbr.metallicRoughnessTexture = g.TextureInfo(index=tex["mr_tex"])
        self.materials.append(g.Material(name=name, pbrMetallicRoughness=pbr, doubleSided=False, extensions=ext,
                                         normalTexture=(g.NormalMaterialTexture(index=tex["normal_tex"])
                                                        if "normal_tex" in tex else None)))
        return len(self.materials) - 1

    def texture(self, rgb: np.ndarray) -> int:
        import pygltflib as g

        v = self.view(png_bytes(rgb), None)
        self.images.append(g.Image(bufferView=v, mimeType="image/png"))
        self.textures.append(g.Texture(source=len(self.images) - 1, sampler=0))
        return len(self.textures) - 1

    def mesh_node(self, name: str, geom: dict[str, int], material: int, translation: tuple[float, ...] = (0, 0, 0),
                  scale: float = 1.0) -> None:
        import pygltflib as g

        attrs = g.Attributes(**{k: v for k, v in geom.items() if k != "indices"})
        self.meshes.append(g.Mesh(name=name, primitives=[g.Primitive(attributes=attrs, indices=geom["indices"],
                                                                     material=material, mode=4)]))
        self.nodes.append(g.Node(name=name, mesh=len(self.meshes) - 1, translation=[float(t) for t in translation],
                                 scale=[float(scale)] * 3))

    def light(self, li: Any) -> None:
        import pygltflib as g

        k = len(self.lights)
        self.lights.append(khr_light(li))
        self.ext_used.add("KHR_lights_punctual")
        node: dict[str, Any] = {"name": f"light{k}", "extensions": {"KHR_lights_punctual": {"light": k}}}
        if isinstance(li, (DirectionalLight, SpotLight)):
            node["rotation"] = quaternion_to(li.unit_direction())
        if isinstance(li, (PointLight, SpotLight)):
            node["translation"] = [float(v) for v in li.position]
        self.nodes.append(g.Node(**node))

    def glb(self, name: str, camera: dict[str, Any]) -> bytes:
        import pygltflib as g

        pos, target = np.asarray(camera["position"], float), np.asarray(camera["target"], float)
        self.nodes.append(g.Node(name="camera", camera=0, translation=pos.tolist(),
                                 rotation=look_rotation(target - pos)))
        doc = g.GLTF2(
            asset=g.Asset(version="2.0", generator=GENERATOR), scene=0,
            scenes=[g.Scene(name=name, nodes=list(range(len(self.nodes))))], nodes=self.nodes, meshes=self.meshes,
            materials=self.materials, accessors=self.accessors, bufferViews=self.views,
            buffers=[g.Buffer(byteLength=len(self.blob))],
            cameras=[g.Camera(type="perspective", perspective=g.Perspective(
                yfov=camera["yfov"], aspectRatio=camera["aspectRatio"], znear=camera["znear"]))],
            images=self.images, textures=self.textures,
            samplers=[g.Sampler(magFilter=9729, minFilter=9729, wrapS=10497, wrapT=10497)] if self.textures else [],
            extensionsUsed=sorted(self.ext_used),
            extensions={"KHR_lights_punctual": {"lights": self.lights}} if self.lights else {})
        doc.set_binary_blob(bytes(self.blob))
        return b"".join(bytes(p) for p in doc.save_to_bytes())


def look_rotation(forward: np.ndarray) -> list[float]:
    """glTF quaternion [x, y, z, w] of a camera whose −z looks along ``forward`` with +y up (no roll)."""
    f = np.asarray(forward, float) / np.linalg.norm(forward)
    right = np.cross(f, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, f)
    m = np.stack([right, up, -f], axis=1)  # columns: camera x, y, z in the world
    w = math.sqrt(max(0.0, 1.0 + m[0, 0] + m[1, 1] + m[2, 2])) / 2.0
    x = math.copysign(math.sqrt(max(0.0, 1.0 + m[0, 0] - m[1, 1] - m[2, 2])) / 2.0, m[2, 1] - m[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1.0 - m[0, 0] + m[1, 1] - m[2, 2])) / 2.0, m[0, 2] - m[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1.0 - m[0, 0] - m[1, 1] + m[2, 2])) / 2.0, m[1, 0] - m[0, 1])
    return [x, y, z, w]


# ---------------------------------------------------------------- the scenes


@dataclass(frozen=True)
class AuthoredScene:
    """One authored scene: its name, ``.glb`` bytes, camera (as the manifest states it), environment file stem
    (None without one), what it is for, and the caveat of its direct-lighting truth."""

    name: str
    glb: bytes
    camera: dict[str, Any]
    environment: str | None
    purpose: str
    truth_note: str
    lights: tuple[Any, ...] = ()
    image_scale: int = 1  # the image is image_scale x the export's resolution a side (small objects need pixels)
    transport: str = "direct"  # the deciding truth's (validate.reference.gltf_truth.TRANSPORTS)
    also: tuple[str, ...] = ()  # further truths the image is judged against, as figures (never deciding)
    spp_factor: int = 1  # its truth's samples per pass: the set's (env_spp with an environment, spp without) x this


def _camera(position: tuple[float, ...], target: tuple[float, ...], yfov: float) -> dict[str, Any]:
    return {"type": "perspective", "position": list(map(float, position)), "target": list(map(float, target)),
            "up": [0.0, 1.0, 0.0], "yfov": yfov, "aspectRatio": 1.0, "znear": 0.05}


LONE = "one sphere: direct lighting is the full light transport"


def authored_scenes() -> list[AuthoredScene]:
    """Every authored scene (module docstring)."""
    out = []
    sphere = dict(zip(("POSITION", "NORMAL", "indices"), sphere_mesh(SEGMENTS), strict=True))
    cam = _camera((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), 0.6)
    for name, mat in (("calibration_mirror", ("mirror", (1.0, 1.0, 1.0), 1.0, MIRROR_ROUGHNESS, None)),
                      ("calibration_lambert", ("lambert", (0.8, 0.8, 0.8), 0.0, 1.0, 0.0))):
        b = _Builder()
        b.mesh_node("sphere", b.geometry(sphere), b.material(*mat))
        out.append(AuthoredScene(name, b.glb(name, cam), cam, "calibration_markers",
                                 "orientation and units calibration: the markers' places give the environment's "
                                 "rotation and handedness, their radiance the overall scale", LONE))
    b = _Builder()
    geom = b.geometry(sphere)
    for r, metal in enumerate(GRID_METALLIC):
        for c, rough in enumerate(GRID_ROUGHNESS):
            b.mesh_node(f"sphere_m{metal:g}_r{rough:g}", geom, b.material(f"m{metal:g}_r{rough:g}", GOLD, metal, rough),
                        translation=(1.1 * (c - 1), 1.1 * (1 - r), 0.0), scale=0.45)
    cam = _camera((0.0, 0.0, 6.0), (0.0, 0.0, 0.0), 0.62)
    out.append(AuthoredScene("metal_rough_spheres", b.glb("metal_rough_spheres", cam), cam, "sky",
                             f"metallic {list(GRID_METALLIC)} (rows, top down) x roughness {list(GRID_ROUGHNESS)} "
                             "(columns, left to right) under a shared environment",
                             "direct lighting with the spheres' occlusion of one another's environment; an engine "
                             "without environment occlusion is brighter where a sphere faces its neighbour",
                             image_scale=2))
    lights = {"shadow_directional": DirectionalLight((0.3, -1.0, -0.25), 3.0),
              "shadow_point": PointLight((0.6, 2.2, 0.5), 12.0),
              "shadow_spot": SpotLight((0.7, 2.6, 0.6), (0.0, 0.0, 0.0), 25.0, inner_deg=20.0, outer_deg=32.0)}
    cam = _camera((0.0, 3.2, 4.2), (0.0, 0.3, 0.0), 0.75)
    for name, li in lights.items():
        b = _Builder()
        b.mesh_node("ground", b.geometry(dict(zip(("POSITION", "NORMAL", "indices"), ground_mesh(GROUND_HALF),
                                                  strict=True))), b.material("ground", (0.8, 0.8, 0.8), 0.0, 1.0, 0.0))
        b.mesh_node("box", b.geometry(dict(zip(("POSITION", "NORMAL", "indices"), box_mesh(BOX_HALF), strict=True))),
                    b.material("box", (0.7, 0.35, 0.2), 0.0, 0.5), translation=(0.0, BOX_GAP + BOX_HALF, 0.0))
        b.light(li)
        out.append(AuthoredScene(name, b.glb(name, cam), cam, None,
                                 f"hard shadows: a box over a plane under one {name.split('_')[1]} light",
                                 "direct lighting with shadows; the box's light bounced onto the ground is not in "
                                 "it (an engine without global illumination computes the same)", (li,)))
    b = _Builder()
    tex = {f"{k}_tex": b.texture(v) for k, v in textures().items()}
    b.mesh_node("bumpy_sphere", b.geometry(bumpy_sphere_mesh()),
                b.material("textured", (1.0, 1.0, 1.0), 1.0, 1.0, **tex))
    cam = _camera((0.0, 0.8, 4.0), (0.0, 0.0, 0.0), 0.62)
    out.append(AuthoredScene("textured_bumpy_sphere", b.glb("textured_bumpy_sphere", cam), cam, "sky",
                             "a mesh with curvature, UVs and tangents and the suite's base-colour, metallic-roughness "
                             "and normal textures", "direct lighting; the bumps shadow one another a little"))
    b = _Builder()
    white, red = room_meshes()
    for name, rects, albedo in (("white_walls", white, WALL_ALBEDO), ("red_wall", red, RED_WALL)):
        b.mesh_node(name, b.geometry(dict(zip(("POSITION", "NORMAL", "indices"), rect_mesh(rects), strict=True))),
                    b.material(name, albedo, 0.0, 1.0, 0.0))
    b.light(ROOM_SUN)
    cam = _camera((1.6, 1.5, 1.8), (-0.6, 0.3, -1.2), 1.1)
    out.append(AuthoredScene("room_opening", b.glb("room_opening", cam), cam, None,
                             "a closed Lambertian room (white, the left wall red) lit by the sun through a skylight: "
                             "the light that reaches the unlit walls and the red bleeding is global illumination",
                             "judged against the full light transport; the direct-only truth beside it gives the "
                             "share an engine without global illumination misses (a figure, not a failure)",
                             (ROOM_SUN,), transport="full", also=("direct",), spp_factor=ROOM_SPP_FACTOR))
    return out


ENVIRONMENTS = {"calibration_markers": marker_texels, "sky": sky_texels}
