"""A user's glTF 2.0 file read into the suite's scene description (the other direction of :mod:`.gltf_export`).

:func:`read_gltf` turns a ``.glb`` or ``.gltf`` (pygltflib reads the JSON; buffers from the GLB chunk, data URIs or
files beside it) into a :class:`GltfScene`: world-space triangle meshes, their glTF metallic-roughness materials
with decoded textures, ``KHR_lights_punctual`` lights as the suite's own light objects
(:mod:`validate.scenes.render_scenes`: the same units, the same KHR spot falloff), and the first camera. The
Mitsuba truth of such a scene is :mod:`validate.reference.gltf_truth`.

What is read, and how [1]:

* Nodes of the default scene (``scene``, else scene 0), depth first; a node's world matrix is its parents' times
  its own (``matrix`` or T·R·S). Positions go to world space by it, normals by its inverse transpose, tangents by
  it (then orthogonalised); a negative determinant swaps the winding, so front faces stay counter-clockwise [1,
  3.7.4].
* Primitives: triangles (mode 4), strips (5) and fans (6) unrolled into triangles; ``POSITION``, ``NORMAL``
  (absent: flat shading, the face normals), ``TEXCOORD_0`` and ``TANGENT`` (xyz, w = the bitangent's sign);
  indices or none. Accessors of any component type, ``normalized`` integers decoded as [1, 3.11]
  (``KHR_mesh_quantization`` is therefore read too), any ``byteStride``.
* Materials: ``pbrMetallicRoughness`` (baseColorFactor × baseColorTexture, metallicFactor × B and
  roughnessFactor × G of metallicRoughnessTexture), ``normalTexture`` with its ``scale``, ``emissiveFactor`` ×
  ``emissiveTexture`` × ``KHR_materials_emissive_strength``, ``KHR_materials_specular`` (factor and colour
  factor), ``KHR_materials_ior``, ``doubleSided``. The default material is glTF's (white, metallic 1,
  roughness 1). Colour textures (base colour, emissive) are decoded from sRGB to linear per texel before any
  filtering, as a GPU's sRGB formats do; the others are linear. Samplers: wrapS and wrapT each of repeat,
  clamp-to-edge or mirrored repeat; magFilter nearest or linear (the default).
* ``KHR_lights_punctual``: directional (lux), point and spot (candela), colour × intensity, the light shining
  along its node's −z; spot cones in radians. The node's scale does not touch a light [2].
* The first camera met in the traversal: perspective (``yfov``, ``aspectRatio`` or the image's) or orthographic
  (``xmag``, ``ymag``), ``znear``; rays start on the near plane (:meth:`GltfScene.pixel_rays`).

Refused with one line naming the feature (the truth would be wrong, not approximate): extensions beyond
:data:`SUPPORTED_EXTENSIONS` (``KHR_materials_transmission``, ``_volume``, ``_clearcoat``, ``_sheen``, Draco …),
skins, morph targets, alpha modes other than OPAQUE, points and lines, ``TEXCOORD_1`` on a used texture,
``KHR_texture_transform``, sparse accessors, textures of the specular extension, an emissive texture whose
wrapS and wrapT differ. Noted (one line each, :attr:`GltfScene.notes`) and otherwise left out: the occlusion
texture (a path tracer computes occlusion), animations (the rest pose is traced), cameras after the first, a
light's ``range`` (KHR leaves its window to the engine; the truth is the inverse-square law), and
:data:`IGNORED_EXTENSIONS`. A malformed file (bad GLB, indices out of range, a missing buffer, NaN vertices,
an undecodable image) is one line naming the file and the problem.

References
----------
[1] Khronos, glTF 2.0 Specification (3.4 scenes and nodes, 3.5 cameras, 3.7 meshes, 3.8 textures, 3.9 materials,
    3.11 accessor data, 5.24 samplers).
[2] Khronos, KHR_lights_punctual ("Light Types", "Inner and Outer Cone Angles", "Range Property").
[3] Khronos, KHR_materials_specular, KHR_materials_ior, KHR_materials_emissive_strength.
"""

from __future__ import annotations

import base64
import hashlib
import io
import math
import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ValidateError
from .render_scenes import DirectionalLight, PointLight, SpotLight

SUPPORTED_EXTENSIONS = ("KHR_lights_punctual", "KHR_materials_specular", "KHR_materials_ior",
                        "KHR_materials_emissive_strength", "KHR_mesh_quantization")
IGNORED_EXTENSIONS = {"KHR_materials_variants": "the default material of each primitive is traced",
                      "KHR_xmp_json_ld": "metadata", "EXT_lights_image_based": "the environment comes from --env"}
COMPONENTS = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
WRAPS = {10497: "repeat", 33071: "clamp", 33648: "mirror"}
FILTERS = {9728: "nearest", 9729: "linear"}
DEFAULT_ZNEAR = 1e-3  # an orthographic camera must state znear; a perspective one may not (then rays start here)


@dataclass(frozen=True)
class Texture:
    """Decoded texels (H, W, C) float64, row 0 = the image's top (glTF's uv (0, 0) is its top-left corner), linear
    (sRGB decoded where the slot is a colour), the sampler's wraps (s, t) and magnification filter."""

    texels: np.ndarray = field(compare=False, hash=False)
    wrap: tuple[str, str] = ("repeat", "repeat")
    filter: str = "linear"
    digest: str = ""


@dataclass(frozen=True)
class GltfMaterial:
    """glTF metallic-roughness with its textures and the extensions read (module docstring)."""

    name: str = "default"
    base_color: tuple[float, float, float, float] = (1.0, 1.0, 1.0, 1.0)
    base_color_texture: Texture | None = None
    metallic: float = 1.0
    roughness: float = 1.0
    metallic_roughness_texture: Texture | None = None
    normal_texture: Texture | None = None
    normal_scale: float = 1.0
    emissive: tuple[float, float, float] = (0.0, 0.0, 0.0)
    emissive_texture: Texture | None = None
    emissive_strength: float = 1.0
    specular: float = 1.0
    specular_color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    ior: float = 1.5
    double_sided: bool = False

    def key(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for k, v in self.__dict__.items():
            out[k] = None if v is None else ({"digest": v.digest, "wrap": list(v.wrap), "filter": v.filter}
                                             if isinstance(v, Texture) else v)
        return out


@dataclass(frozen=True)
class MeshPart:
    """One primitive in world space: positions (V, 3), normals (V, 3) or None (flat), uvs (V, 2) or None, tangents
    (V, 4) (xyz world, w the bitangent's sign) or None, triangles (T, 3) counter-clockwise = front, a material
    index."""

    name: str
    positions: np.ndarray = field(compare=False)
    normals: np.ndarray | None = field(compare=False)
    uvs: np.ndarray | None = field(compare=False)
    tangents: np.ndarray | None = field(compare=False)
    triangles: np.ndarray = field(compare=False)
    material: int = -1


@dataclass(frozen=True)
class GltfCamera:
    """The camera: ``to_world`` (4, 4) (its local −z looks ahead, +y up), perspective ``yfov`` (radians) and
    ``aspect`` (None: the image's), or orthographic ``xmag``, ``ymag`` (half width and height); ``znear``."""

    type: str
    to_world: np.ndarray = field(compare=False)
    yfov: float = 0.0
    aspect: float | None = None
    xmag: float = 0.0
    ymag: float = 0.0
    znear: float = DEFAULT_ZNEAR

    def key(self) -> dict[str, Any]:
        return {"type": self.type, "to_world": np.round(self.to_world, 12).tolist(), "yfov": self.yfov,
                "aspect": self.aspect, "xmag": self.xmag, "ymag": self.ymag, "znear": self.znear}

    def default_aspect(self) -> float | None:
        """The aspect (width/height) the camera states: ``aspectRatio`` or xmag/ymag; None when it states none."""
        return self.aspect if self.type == "perspective" else self.xmag / self.ymag


@dataclass
class GltfScene:
    """A user's glTF as the suite describes a scene (module docstring); ``digest``: sha256 of the file's bytes and
    of every external file it names."""

    name: str
    path: Path
    digest: str
    meshes: list[MeshPart]
    materials: list[GltfMaterial]
    lights: list[Any]
    camera: GltfCamera
    notes: list[str] = field(default_factory=list)

    def material_of(self, part: MeshPart) -> GltfMaterial:
        return self.materials[part.material] if part.material >= 0 else GltfMaterial()

    def image_size(self, height: int | None = None, width: int | None = None) -> tuple[int, int]:
        """(width, height) in pixels: as given, the missing one from the camera's aspect (height 128 when neither
        is given; a perspective camera without ``aspectRatio`` is square then)."""
        aspect = self.camera.default_aspect() or 1.0
        if height is None and width is None:
            height = 128
        if height is None:
            height = max(1, round(width / aspect))
        if width is None:
            width = max(1, round(height * aspect))
        if not (1 <= width <= 8192 and 1 <= height <= 8192):
            raise ValidateError(f"{self.path}: image size {width}x{height}: need 1..8192 pixels a side")
        return int(width), int(height)

    def pixel_rays(self, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
        """(H·W, 3) world origins and unit directions of the pixel-centre rays, row-major, row 0 at the top: pixel
        (i, j) at NDC x = 2(j + ½)/W − 1, y = 1 − 2(i + ½)/H; perspective: camera-space direction (x a t, y t, −1)
        with t = tan(yfov/2), a = the aspect (``aspectRatio`` or W/H), starting where it crosses z = −znear;
        orthographic: origin (x xmag, y ymag, −znear), direction −z [1, 3.10.3]."""
        c = self.camera
        x = (2.0 * (np.arange(width) + 0.5) / width - 1.0)[None, :].repeat(height, 0).ravel()
        y = (1.0 - 2.0 * (np.arange(height) + 0.5) / height)[:, None].repeat(width, 1).ravel()
        if c.type == "perspective":
            t = math.tan(0.5 * c.yfov)
            a = c.aspect if c.aspect is not None else width / height
            d = np.stack([x * a * t, y * t, -np.ones_like(x)], axis=-1)
            o = d * c.znear
        else:
            o = np.stack([x * c.xmag, y * c.ymag, np.full_like(x, -c.znear)], axis=-1)
            d = np.broadcast_to([0.0, 0.0, -1.0], o.shape)
        m = c.to_world
        ow = o @ m[:3, :3].T + m[:3, 3]
        dw = d @ m[:3, :3].T
        return ow, dw / np.linalg.norm(dw, axis=-1, keepdims=True)

    def key(self) -> dict[str, Any]:
        """What the truth depends on besides the settings: the file's content hash (every byte it reads)."""
        return {"gltf": self.digest, "camera": self.camera.key()}


# ---------------------------------------------------------------- reading


class _Reader:
    """Reads one file; every problem is a :class:`ValidateError` naming it."""

    def __init__(self, path: Path) -> None:
        import pygltflib

        self.path = path
        self.hash = hashlib.sha256()
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            raise ValidateError(f"{path}: no such file") from None
        except OSError as exc:
            raise ValidateError(f"{path}: cannot read ({exc.strerror or exc})") from None
        self.hash.update(data)
        self.glb = data[:4] == b"glTF"
        try:
            if self.glb:
                version, length = struct.unpack_from("<II", data, 4) if len(data) >= 12 else (0, 0)
                if version != 2 or length != len(data):
                    raise ValueError(f"GLB header: version {version}, length {length} of {len(data)} bytes")
                doc = pygltflib.GLTF2.load_from_bytes(data)
            else:
                doc = pygltflib.GLTF2.from_json(data.decode("utf-8"))
        except Exception as exc:  # pygltflib, json and struct raise many kinds: one line either way
            first = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
            raise ValidateError(f"{path}: malformed glTF ({first[:160]})") from None
        if doc is None or doc.asset is None or not str(doc.asset.version).startswith("2."):
            version = getattr(getattr(doc, "asset", None), "version", None)
            raise ValidateError(f"{path}: not glTF 2.x (asset.version {version})")
        self.doc = doc
        self.buffers: dict[int, bytes] = {}
        self.images: dict[tuple[int, bool], np.ndarray] = {}
        self.notes: list[str] = []

    def fail(self, problem: str) -> ValidateError:
        return ValidateError(f"{self.path}: {problem}")

    def unsupported(self, what: str, why: str = "") -> ValidateError:
        return self.fail(f"{what} is not supported by the Mitsuba truth" + (f" ({why})" if why else ""))

    def _at(self, items: list[Any] | None, index: Any, what: str) -> Any:
        if not isinstance(index, int) or items is None or not 0 <= index < len(items):
            raise self.fail(f"{what} {index} does not exist")
        return items[index]

    # -------------------------------------------------------- bytes

    def _uri_bytes(self, uri: str, what: str) -> bytes:
        if uri.startswith("data:"):
            head, _, payload = uri.partition(",")
            if not head.endswith(";base64"):
                raise self.fail(f"{what}: a data URI that is not base64")
            try:
                return base64.b64decode(payload, validate=True)
            except ValueError:
                raise self.fail(f"{what}: a data URI whose base64 does not decode") from None
        from urllib.parse import unquote

        p = self.path.parent / unquote(uri)
        try:
            data = p.read_bytes()
        except OSError as exc:
            raise self.fail(f"{what}: {p}: cannot read ({exc.strerror or exc})") from None
        self.hash.update(data)
        return data

    def buffer(self, index: int) -> bytes:
        if index not in self.buffers:
            b = self._at(self.doc.buffers, index, "buffer")
            if b.uri is None:
                blob = self.doc.binary_blob() if self.glb and index == 0 else None
                if blob is None:
                    raise self.fail(f"buffer {index} has no uri and no GLB binary chunk")
                data = bytes(blob)
            else:
                data = self._uri_bytes(b.uri, f"buffer {index}")
            if len(data) < (b.byteLength or 0):
                raise self.fail(f"buffer {index}: {len(data)} bytes, byteLength says {b.byteLength}")
            self.buffers[index] = data
        return self.buffers[index]

    def view_bytes(self, index: int) -> tuple[bytes, int | None]:
        v = self._at(self.doc.bufferViews, index, "bufferView")
        data = self.buffer(v.buffer)
        start = v.byteOffset or 0
        if start + v.byteLength > len(data):
            raise self.fail(f"bufferView {index} runs past the end of buffer {v.buffer}")
        return data[start:start + v.byteLength], v.byteStride

    def accessor(self, index: int) -> np.ndarray:
        """(count, width) float64 (or the integer type for indices) of accessor ``index`` [1, 3.11]."""
        a = self._at(self.doc.accessors, index, "accessor")
        if a.sparse is not None:
            raise self.unsupported(f"accessor {index}: sparse storage")
        if a.componentType not in COMPONENTS or a.type not in WIDTHS:
            raise self.fail(f"accessor {index}: componentType {a.componentType}, type {a.type!r}")
        dt, width = np.dtype(COMPONENTS[a.componentType]).newbyteorder("<"), WIDTHS[a.type]
        count = int(a.count or 0)
        if a.bufferView is None:
            return np.zeros((count, width), dt)
        data, stride = self.view_bytes(a.bufferView)
        elem = dt.itemsize * width
        stride = stride or elem
        offset = a.byteOffset or 0
        if count and offset + stride * (count - 1) + elem > len(data):
            raise self.fail(f"accessor {index}: {count} elements run past the end of bufferView {a.bufferView}")
        raw = np.frombuffer(data, np.uint8, count=stride * (count - 1) + elem if count else 0, offset=offset)
        if count:
            rows = np.lib.stride_tricks.as_strided(raw, (count, elem), (stride, 1))
            out = np.ascontiguousarray(rows).view(dt).reshape(count, width)
        else:
            out = np.zeros((0, width), dt)
        if a.normalized and dt.kind in "iu":
            mx = float(np.iinfo(dt).max)
            return np.maximum(out.astype(np.float64) / mx, -1.0)
        return out

    def float_accessor(self, index: int, width: int, what: str) -> np.ndarray:
        v = self.accessor(index)
        if v.shape[1] != width:
            raise self.fail(f"{what}: accessor {index} has {v.shape[1]} components, need {width}")
        v = v.astype(np.float64)
        if not np.all(np.isfinite(v)):
            raise self.fail(f"{what}: accessor {index} holds NaN or Inf")
        return v

    # -------------------------------------------------------- images and textures

    def image(self, index: int, srgb: bool) -> np.ndarray:
        """(H, W, 4) float64 in [0, 1] of image ``index``, sRGB decoded to linear in RGB when ``srgb``."""
        if (index, srgb) in self.images:
            return self.images[(index, srgb)]
        from PIL import Image

        im = self._at(self.doc.images, index, "image")
        if im.bufferView is not None:
            data, _ = self.view_bytes(im.bufferView)
        elif im.uri:
            data = self._uri_bytes(im.uri, f"image {index}")
        else:
            raise self.fail(f"image {index} has neither uri nor bufferView")
        try:
            with Image.open(io.BytesIO(data)) as pil:
                fmt = pil.format
                if fmt not in ("PNG", "JPEG"):
                    raise self.unsupported(f"image {index} in {fmt or 'an unknown'} format", "glTF core: PNG, JPEG")
                if pil.mode in ("I;16", "I;16B", "I"):
                    arr = np.asarray(pil, np.float64) / 65535.0
                    arr = np.repeat(arr[..., None], 3, axis=-1)
                else:
                    arr = np.asarray(pil.convert("RGBA"), np.float64) / 255.0
        except ValidateError:
            raise
        except Exception as exc:  # PIL's many decoder errors
            raise self.fail(f"image {index} does not decode ({str(exc).splitlines()[0][:120] if str(exc) else exc})"
                            ) from None
        if arr.shape[-1] == 3:
            arr = np.concatenate([arr, np.ones(arr.shape[:2] + (1,))], axis=-1)
        if srgb:
            rgb = arr[..., :3]
            arr = np.concatenate([np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4),
                                  arr[..., 3:]], axis=-1)
        self.images[(index, srgb)] = arr
        return arr

    def texture(self, info: Any, slot: str, srgb: bool, channels: int) -> Texture | None:
        """The :class:`Texture` a material's texture reference names (None without one)."""
        if info is None:
            return None
        if (getattr(info, "texCoord", 0) or 0) != 0:
            raise self.unsupported(f"{slot}: TEXCOORD_{info.texCoord}", "only TEXCOORD_0 is traced")
        if "KHR_texture_transform" in (getattr(info, "extensions", None) or {}):
            raise self.unsupported(f"{slot}: KHR_texture_transform")
        tex = self._at(self.doc.textures, info.index, f"{slot}: texture")
        if tex.source is None:
            raise self.unsupported(f"{slot}: texture {info.index} without a core image source")
        wrap, filt = ("repeat", "repeat"), "linear"
        if tex.sampler is not None:
            s = self._at(self.doc.samplers, tex.sampler, "sampler")
            try:
                wrap = (WRAPS[s.wrapS if s.wrapS is not None else 10497], WRAPS[s.wrapT if s.wrapT is not None
                                                                                 else 10497])
            except KeyError:
                raise self.fail(f"sampler {tex.sampler}: wrap mode {s.wrapS}/{s.wrapT}") from None
            filt = FILTERS.get(s.magFilter, "linear") if s.magFilter is not None else "linear"
            if s.minFilter not in (None, 9728, 9729):
                self.note("a sampler's mipmapped minFilter: the truth samples every texture at the ray's hit point "
                          "(the magnification filter), not over a pixel's footprint")
        texels = self.image(tex.source, srgb)[..., :channels]
        texels = np.ascontiguousarray(texels)
        digest = hashlib.sha256(texels.astype(np.float32).tobytes() + str(texels.shape).encode()).hexdigest()[:24]
        return Texture(texels, wrap, filt, digest)

    def note(self, text: str) -> None:
        if text not in self.notes:
            self.notes.append(text)

    # -------------------------------------------------------- materials, lights, camera

    def check_extensions(self) -> None:
        for name in list(self.doc.extensionsRequired or []) + list(self.doc.extensionsUsed or []):
            if name in SUPPORTED_EXTENSIONS:
                continue
            if name in IGNORED_EXTENSIONS and name not in (self.doc.extensionsRequired or []):
                self.note(f"{name} ignored: {IGNORED_EXTENSIONS[name]}")
                continue
            raise self.unsupported(f"extension {name}")

    def material(self, index: int) -> GltfMaterial:
        m = self._at(self.doc.materials, index, "material")
        where = f"material {index} ({m.name})" if m.name else f"material {index}"
        if (m.alphaMode or "OPAQUE") != "OPAQUE":
            raise self.unsupported(f"{where}: alphaMode {m.alphaMode}", "the truth is opaque")
        ext = m.extensions or {}
        for name in ext:
            if name not in SUPPORTED_EXTENSIONS and name not in IGNORED_EXTENSIONS:
                raise self.unsupported(f"{where}: extension {name}")
        pbr = m.pbrMetallicRoughness
        kw: dict[str, Any] = {"name": m.name or f"material{index}", "double_sided": bool(m.doubleSided)}
        if pbr is not None:
            kw["base_color"] = tuple(float(v) for v in (pbr.baseColorFactor or (1.0, 1.0, 1.0, 1.0)))
            kw["metallic"] = float(1.0 if pbr.metallicFactor is None else pbr.metallicFactor)
            kw["roughness"] = float(1.0 if pbr.roughnessFactor is None else pbr.roughnessFactor)
            kw["base_color_texture"] = self.texture(pbr.baseColorTexture, f"{where}: baseColorTexture", True, 3)
            kw["metallic_roughness_texture"] = self.texture(pbr.metallicRoughnessTexture,
                                                            f"{where}: metallicRoughnessTexture", False, 3)
        if m.normalTexture is not None:
            kw["normal_texture"] = self.texture(m.normalTexture, f"{where}: normalTexture", False, 3)
            kw["normal_scale"] = float(m.normalTexture.scale if m.normalTexture.scale is not None else 1.0)
        if m.occlusionTexture is not None:
            self.note(f"{where}: occlusionTexture ignored (the path tracer computes occlusion itself)")
        kw["emissive"] = tuple(float(v) for v in (m.emissiveFactor or (0.0, 0.0, 0.0)))
        kw["emissive_texture"] = self.texture(m.emissiveTexture, f"{where}: emissiveTexture", True, 3)
        if kw["emissive_texture"] is not None and len(set(kw["emissive_texture"].wrap)) > 1:
            raise self.unsupported(f"{where}: emissiveTexture with wrapS != wrapT", "Mitsuba's emitter texture has "
                                   "one wrap mode")
        es = ext.get("KHR_materials_emissive_strength") or {}
        kw["emissive_strength"] = float(es.get("emissiveStrength", 1.0))
        sp = ext.get("KHR_materials_specular")
        if sp is not None:
            if sp.get("specularTexture") or sp.get("specularColorTexture"):
                raise self.unsupported(f"{where}: KHR_materials_specular textures")
            kw["specular"] = float(sp.get("specularFactor", 1.0))
            kw["specular_color"] = tuple(float(v) for v in sp.get("specularColorFactor", (1.0, 1.0, 1.0)))
        if "KHR_materials_ior" in ext:
            kw["ior"] = float(ext["KHR_materials_ior"].get("ior", 1.5))
        out = GltfMaterial(**kw)
        vals = [*out.base_color, out.metallic, out.roughness, out.specular]
        if len(out.base_color) != 4 or not all(0.0 <= v <= 1.0 for v in vals):
            raise self.fail(f"{where}: a factor outside [0, 1] (baseColor {list(out.base_color)}, metallic "
                            f"{out.metallic}, roughness {out.roughness}, specular {out.specular})")
        if min(out.emissive) < 0 or out.emissive_strength < 0 or min(out.specular_color) < 0 or not (
                out.ior == 0 or out.ior >= 1):
            raise self.fail(f"{where}: negative emission or specular colour, or ior {out.ior} below 1")
        return out

    def light(self, index: int, world: np.ndarray) -> Any:
        lights = ((self.doc.extensions or {}).get("KHR_lights_punctual") or {}).get("lights") or []
        li = self._at(lights, index, "KHR_lights_punctual light")
        color = tuple(float(c) for c in li.get("color", (1.0, 1.0, 1.0)))
        intensity = float(li.get("intensity", 1.0))
        if intensity < 0 or min(color) < 0 or len(color) != 3:
            raise self.fail(f"light {index}: negative intensity or colour")
        if li.get("range") is not None:
            self.note(f"light {index}: range {li['range']} ignored: the truth is the inverse-square law everywhere "
                      "(KHR leaves the window near the range to the engine)")
        pos = world[:3, 3].copy()
        d = world[:3, :3] @ np.array([0.0, 0.0, -1.0])
        n = np.linalg.norm(d)
        if not n > 0:
            raise self.fail(f"light {index}: its node's matrix is singular")
        d = d / n
        kind = li.get("type")
        if kind == "directional":
            return DirectionalLight(tuple(d.tolist()), intensity, color)
        if kind == "point":
            return PointLight(tuple(pos.tolist()), intensity, color)
        if kind == "spot":
            spot = li.get("spot") or {}
            inner, outer = float(spot.get("innerConeAngle", 0.0)), float(spot.get("outerConeAngle", math.pi / 4))
            if not 0.0 <= inner < outer <= math.pi / 2:
                raise self.fail(f"light {index}: spot cones inner {inner}, outer {outer}: need 0 <= inner < outer "
                                "<= pi/2")
            outer_deg = min(math.degrees(outer), 89.999)
            return SpotLight(tuple(pos.tolist()), tuple((pos + d).tolist()), intensity, math.degrees(inner),
                             outer_deg, color)
        raise self.fail(f"light {index}: type {kind!r} is not directional, point or spot")

    def camera(self, index: int, world: np.ndarray) -> GltfCamera:
        c = self._at(self.doc.cameras, index, "camera")
        m = world.copy()
        m[:3, :3] = m[:3, :3] / np.linalg.norm(m[:3, :3], axis=0, keepdims=True)  # the node's scale does not zoom
        if c.type == "perspective" and c.perspective is not None:
            p = c.perspective
            if not (p.yfov and 0 < p.yfov < math.pi) or (p.aspectRatio is not None and p.aspectRatio <= 0):
                raise self.fail(f"camera {index}: yfov {p.yfov}, aspectRatio {p.aspectRatio}")
            return GltfCamera("perspective", m, yfov=float(p.yfov), aspect=None if p.aspectRatio is None else
                              float(p.aspectRatio), znear=float(p.znear or DEFAULT_ZNEAR))
        if c.type == "orthographic" and c.orthographic is not None:
            o = c.orthographic
            if not (o.xmag and o.ymag) or o.znear is None or o.znear < 0:
                raise self.fail(f"camera {index}: orthographic xmag {o.xmag}, ymag {o.ymag}, znear {o.znear}")
            return GltfCamera("orthographic", m, xmag=abs(float(o.xmag)), ymag=abs(float(o.ymag)),
                              znear=float(o.znear))
        raise self.fail(f"camera {index}: type {c.type!r} without its parameters")

    # -------------------------------------------------------- meshes

    def primitive(self, mesh_index: int, k: int, prim: Any, world: np.ndarray) -> MeshPart:
        where = f"mesh {mesh_index} primitive {k}"
        if prim.targets:
            raise self.unsupported(f"{where}: morph targets")
        if prim.extensions:
            for name in prim.extensions:
                raise self.unsupported(f"{where}: extension {name}")
        attrs = prim.attributes
        if attrs.POSITION is None:
            raise self.fail(f"{where}: no POSITION")
        pos = self.float_accessor(attrs.POSITION, 3, f"{where} POSITION")
        nv = len(pos)
        mode = 4 if prim.mode is None else prim.mode
        idx = (np.arange(nv, dtype=np.int64) if prim.indices is None else
               self.accessor(prim.indices).astype(np.int64).ravel())
        if mode == 4:
            if len(idx) % 3:
                raise self.fail(f"{where}: {len(idx)} indices are not whole triangles")
            tri = idx.reshape(-1, 3)
        elif mode == 5:
            tri = np.array([idx[[i, i + 1, i + 2]] if i % 2 == 0 else idx[[i + 1, i, i + 2]]
                            for i in range(len(idx) - 2)], np.int64).reshape(-1, 3)
        elif mode == 6:
            tri = np.array([[idx[0], idx[i], idx[i + 1]] for i in range(1, len(idx) - 1)], np.int64).reshape(-1, 3)
        else:
            raise self.unsupported(f"{where}: mode {mode} (points or lines)", "the truth traces triangles")
        if tri.size and (tri.min() < 0 or tri.max() >= nv):
            raise self.fail(f"{where}: an index outside 0..{nv - 1}")
        nrm = self.float_accessor(attrs.NORMAL, 3, f"{where} NORMAL") if attrs.NORMAL is not None else None
        uv = self.float_accessor(attrs.TEXCOORD_0, 2, f"{where} TEXCOORD_0") if attrs.TEXCOORD_0 is not None \
            else None
        tan = self.float_accessor(attrs.TANGENT, 4, f"{where} TANGENT") if attrs.TANGENT is not None else None
        for what, arr in (("NORMAL", nrm), ("TEXCOORD_0", uv), ("TANGENT", tan)):
            if arr is not None and len(arr) != nv:
                raise self.fail(f"{where}: {what} has {len(arr)} elements, POSITION {nv}")
        if getattr(attrs, "JOINTS_0", None) is not None or getattr(attrs, "WEIGHTS_0", None) is not None:
            raise self.unsupported(f"{where}: skinning (JOINTS_0/WEIGHTS_0)")
        lin = world[:3, :3]
        wpos = pos @ lin.T + world[:3, 3]
        if np.linalg.det(lin) < 0:
            tri = tri[:, [0, 2, 1]]
        if nrm is not None:
            nrm = nrm @ np.linalg.inv(lin)
            ln = np.linalg.norm(nrm, axis=-1, keepdims=True)
            nrm = np.where(ln > 0, nrm / np.where(ln > 0, ln, 1.0), 0.0)
        if tan is not None:
            t = tan[:, :3] @ lin.T
            if nrm is not None:
                t = t - nrm * (t * nrm).sum(-1, keepdims=True)
            ln = np.linalg.norm(t, axis=-1, keepdims=True)
            tan = np.concatenate([np.where(ln > 0, t / np.where(ln > 0, ln, 1.0), 0.0),
                                  np.where(tan[:, 3:] < 0, -1.0, 1.0)], axis=-1)
        if prim.material is not None:
            self._at(self.doc.materials, prim.material, f"{where}: material")
        return MeshPart(f"mesh{mesh_index}_{k}", wpos, nrm, uv, tan, tri.astype(np.int64),
                        -1 if prim.material is None else int(prim.material))

    def walk(self) -> tuple[list[MeshPart], list[Any], GltfCamera | None]:
        doc = self.doc
        if doc.skins:
            raise self.unsupported("skins")
        if doc.animations:
            self.note("animations ignored: the rest pose is traced")
        scenes = doc.scenes or []
        root = doc.scene if doc.scene is not None else 0
        nodes = (self._at(scenes, root, "scene").nodes or []) if scenes else list(range(len(doc.nodes or [])))
        meshes: list[MeshPart] = []
        lights: list[Any] = []
        camera: GltfCamera | None = None
        stack = [(n, np.eye(4), 0) for n in reversed(nodes)]
        seen = 0
        while stack:
            ni, parent, depth = stack.pop()
            seen += 1
            if depth > 256 or seen > 1_000_000:
                raise self.fail("the node hierarchy has a cycle")
            node = self._at(doc.nodes, ni, "node")
            world = parent @ node_matrix(node)
            if node.skin is not None:
                raise self.unsupported(f"node {ni}: skinning")
            if node.mesh is not None:
                mesh = self._at(doc.meshes, node.mesh, "mesh")
                meshes += [self.primitive(node.mesh, k, p, world) for k, p in enumerate(mesh.primitives or [])]
            if node.camera is not None:
                if camera is None:
                    camera = self.camera(node.camera, world)
                else:
                    self.note("cameras after the first ignored")
            ext = (node.extensions or {}).get("KHR_lights_punctual")
            if ext is not None:
                lights.append(self.light(ext.get("light"), world))
            stack += [(c, world, depth + 1) for c in reversed(node.children or [])]
        return meshes, lights, camera


def node_matrix(node: Any) -> np.ndarray:
    """A node's local 4 × 4 matrix: ``matrix`` (column-major) or T · R · S [1, 3.5.2]."""
    if node.matrix is not None and list(node.matrix) != [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]:
        return np.asarray(node.matrix, np.float64).reshape(4, 4).T
    t = np.asarray(node.translation if node.translation is not None else (0.0, 0.0, 0.0), np.float64)
    x, y, z, w = (node.rotation if node.rotation is not None else (0.0, 0.0, 0.0, 1.0))
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    s = np.asarray(node.scale if node.scale is not None else (1.0, 1.0, 1.0), np.float64)
    m = np.eye(4)
    m[:3, :3] = r * s[None, :]
    m[:3, 3] = t
    return m


def read_gltf(path: Path | str) -> GltfScene:
    """The :class:`GltfScene` of a ``.glb``/``.gltf`` file (module docstring); one-line errors."""
    path = Path(path)
    r = _Reader(path)
    r.check_extensions()
    meshes, lights, camera = r.walk()
    if camera is None:
        raise r.fail("no camera in the scene: the truth renders the view of the first camera")
    if not meshes or not any(len(m.triangles) for m in meshes):
        raise r.fail("no triangle in the scene")
    materials = [r.material(i) for i in range(len(r.doc.materials or []))]
    used = {m.material for m in meshes}
    for i, mat in enumerate(materials):
        if i in used and (mat.normal_texture is not None or mat.base_color_texture is not None or
                          mat.metallic_roughness_texture is not None or mat.emissive_texture is not None):
            for part in meshes:
                if part.material == i and part.uvs is None:
                    raise r.fail(f"{part.name}: material {i} has a texture but the primitive has no TEXCOORD_0")
    return GltfScene(path.stem, path, r.hash.hexdigest(), meshes, materials, lights, camera, r.notes)
