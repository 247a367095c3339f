"""A small reader of KTX 2.0 texture files: uncompressed float cube maps and 2D images (numpy).

What it reads (Khronos KTX 2.0 specification, §3 "File structure"): the 12-byte identifier, the header
(``vkFormat``, ``typeSize``, ``pixelWidth``, ``pixelHeight``, ``pixelDepth``, ``layerCount``, ``faceCount``,
``levelCount``, ``supercompressionScheme``: nine little-endian uint32 at byte 12), the index (data-format
descriptor, key/value and supercompression offsets: byte 48 to 80) and the level index at byte 80 (per level
``byteOffset``, ``byteLength``, ``uncompressedByteLength``: three uint64). Level 0 is the largest; inside a
level the images are stored layer by layer, face by face (+X, −X, +Y, −Y, +Z, −Z, the Vulkan cube order), each
row by row from the top, ``max(1, W >> level)`` texels wide (§3.9 "Level Images").

Formats read: ``VK_FORMAT_R32G32B32A32_SFLOAT`` (109), ``VK_FORMAT_R16G16B16A16_SFLOAT`` (97) and their
RGB (106, 90) and RG/R (103, 100; 83, 76) relatives. Not read (one-line error): supercompressed files
(Basis, zstd, zlib), block-compressed and integer formats, array textures and 3D textures. Pixel values are
returned as stored (float32); what they mean (radiance, irradiance, E/π) is the writer's convention.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ValidateError

IDENTIFIER = b"\xabKTX 20\xbb\r\n\x1a\n"
HEADER_BYTES = 80  # identifier (12) + header (36) + index (32): the level index starts here
LEVEL_ENTRY_BYTES = 24
# vkFormat → (numpy dtype, channels)
FORMATS: dict[int, tuple[str, int]] = {
    109: ("<f4", 4), 106: ("<f4", 3), 103: ("<f4", 2), 100: ("<f4", 1),
    97: ("<f2", 4), 90: ("<f2", 3), 83: ("<f2", 2), 76: ("<f2", 1),
}
FORMAT_NAMES = {109: "R32G32B32A32_SFLOAT", 106: "R32G32B32_SFLOAT", 103: "R32G32_SFLOAT", 100: "R32_SFLOAT",
                97: "R16G16B16A16_SFLOAT", 90: "R16G16B16_SFLOAT", 83: "R16G16_SFLOAT", 76: "R16_SFLOAT"}


@dataclass(frozen=True)
class Ktx2:
    """A KTX2 file's images: ``levels[k]`` is (faces, H_k, W_k, C) float32, level 0 the largest."""

    vk_format: int
    width: int
    height: int
    faces: int
    levels: tuple[np.ndarray, ...]

    @property
    def format_name(self) -> str:
        return FORMAT_NAMES.get(self.vk_format, str(self.vk_format))


def read_ktx2(path: str | Path) -> Ktx2:
    """The images of the KTX2 file at ``path`` (:class:`Ktx2`); a file it cannot read is one line
    ``<path>: <problem>`` (:class:`~validate.errors.ValidateError`)."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ValidateError(f"{path}: cannot read ({exc.strerror or exc})") from None
    return parse_ktx2(data, str(path))


def parse_ktx2(data: bytes, name: str = "KTX2 data") -> Ktx2:
    """:func:`read_ktx2` on bytes already read (``name`` heads the error messages)."""
    if len(data) < HEADER_BYTES:
        raise ValidateError(f"{name}: not a KTX2 file ({len(data)} bytes, shorter than the 80-byte header)")
    if data[:12] != IDENTIFIER:
        raise ValidateError(f"{name}: not a KTX2 file (bad identifier {data[:12]!r})")
    vk_format, _type_size, w, h, depth, layers, faces, levels, scheme = struct.unpack_from("<9I", data, 12)
    if scheme != 0:
        raise ValidateError(f"{name}: supercompression scheme {scheme} is not read (only uncompressed files)")
    if vk_format not in FORMATS:
        raise ValidateError(f"{name}: vkFormat {vk_format} is not read (float formats only: "
                            f"{', '.join(f'{k} {v}' for k, v in FORMAT_NAMES.items())})")
    if depth > 1 or layers > 1:
        raise ValidateError(f"{name}: 3D or array texture (depth {depth}, layers {layers}) is not read")
    if faces not in (1, 6) or w == 0 or (h == 0 and faces == 6) or (faces == 6 and w != h):
        raise ValidateError(f"{name}: {faces} face(s) of {w}×{h} texels (expected 1 image or 6 square faces)")
    h = max(h, 1)
    n_levels = max(levels, 1)
    if HEADER_BYTES + LEVEL_ENTRY_BYTES * n_levels > len(data):
        raise ValidateError(f"{name}: truncated level index ({n_levels} levels, {len(data)} bytes)")
    dtype, channels = FORMATS[vk_format]
    texel = np.dtype(dtype).itemsize * channels
    images = []
    for k in range(n_levels):
        offset, length, _ = struct.unpack_from("<3Q", data, HEADER_BYTES + LEVEL_ENTRY_BYTES * k)
        lw, lh = max(1, w >> k), max(1, h >> k)
        need = faces * lw * lh * texel
        if length != need:
            raise ValidateError(f"{name}: level {k} holds {length} bytes, expected {need} "
                                f"({faces} × {lw}×{lh} × {texel})")
        if offset + length > len(data):
            raise ValidateError(f"{name}: level {k} runs past the end of the file (bytes {offset}…{offset + length}"
                                f" of {len(data)})")
        arr = np.frombuffer(data, dtype=dtype, count=faces * lh * lw * channels, offset=offset)
        images.append(arr.reshape(faces, lh, lw, channels).astype(np.float32))
    return Ktx2(vk_format, w, h, faces, tuple(images))


__all__ = ["FORMATS", "FORMAT_NAMES", "Ktx2", "parse_ktx2", "read_ktx2"]
