"""Load environment maps from disk and convert them to Mitsuba's lat-long convention.

Supported files: OpenEXR (.exr), Radiance RGBE (.hdr, .pic), PFM (.pfm), read with ``mi.Bitmap``
(Mitsuba's own reader). Layouts, detected from the aspect ratio unless ``layout`` is given:

* ``latlong`` (2:1): used as is — the file is interpreted exactly as Mitsuba's ``envmap`` would.
* ``angular`` (1:1): Debevec light-probe angular map. Convention (``../shared/probes/SOURCES.md``,
  Debevec's prose): the image centre is −z (forward), +x right, +y up; for a direction d,
  r = acos(−d_z) / (π √(d_x² + d_y²)), image position (u, v) = (½ + ½ d_x r, ½ − ½ d_y r).
  Converted to a 2:1 lat-long map by bilinear resampling with 2×2 supersampling per texel.
* ``cross`` (3:4): HDRShop vertical cross, faces 3×4 of size F: row 0 col 1 = +y (up);
  row 1: cols 0, 1, 2 = −x, −z (forward), +x; row 2 col 1 = −y (down); row 3 col 1 = +z (back),
  stored upside down. Converted to lat-long (nearest face texel, bilinear within faces).

Validation (one-line :class:`ValidateError` naming the file): missing or unreadable file, NaN/Inf
texels, negative texels (unless ``clamp_negative``), an aspect ratio that is none of the above,
an all-zero map.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import ValidateError
from . import latlong
from .environment import Environment

EXTENSIONS = (".exr", ".hdr", ".pic", ".pfm")
LAYOUTS = ("auto", "latlong", "angular", "cross")


def read_image(path: Path) -> np.ndarray:
    """Read an HDR image as float32 RGB (H, W, 3) with Mitsuba's reader; one-line errors."""
    import mitsuba as mi

    from ..backend import init

    init()
    if not path.exists():
        raise ValidateError(f"{path}: no such file")
    if not path.is_file():
        raise ValidateError(f"{path}: not a regular file")
    if path.suffix.lower() not in EXTENSIONS:
        raise ValidateError(f"{path}: unsupported file type {path.suffix!r} (use .exr, .hdr or .pfm)")
    try:
        bmp = mi.Bitmap(str(path))
        channels = bmp.channel_count()
        if channels == 1:
            arr = np.array(bmp.convert(mi.Bitmap.PixelFormat.Y, mi.Struct.Type.Float32, srgb_gamma=False))
            arr = np.repeat(arr.reshape(arr.shape[0], arr.shape[1], 1), 3, axis=2)
        else:
            arr = np.array(bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False))
    except ValidateError:
        raise
    except Exception as exc:  # mitsuba raises RuntimeError with multi-line text
        first = str(exc).strip().splitlines()[-1] if str(exc).strip() else type(exc).__name__
        raise ValidateError(f"{path}: cannot read image ({first[:160]})") from None
    arr = np.ascontiguousarray(arr.reshape(arr.shape[0], arr.shape[1], 3), dtype=np.float32)
    if arr.size == 0:
        raise ValidateError(f"{path}: image is empty")
    return arr


def check_texels(arr: np.ndarray, path: Path | str, clamp_negative: bool) -> tuple[np.ndarray, list[str]]:
    """Reject NaN/Inf; reject (or clamp, and note) negative texels; reject all-zero maps."""
    notes: list[str] = []
    bad = ~np.isfinite(arr)
    if bad.any():
        n = int(bad.any(axis=-1).sum())
        raise ValidateError(f"{path}: {n} texel(s) are NaN or Inf")
    neg = arr < 0
    if neg.any():
        count = int(neg.any(axis=-1).sum())
        total = arr.shape[0] * arr.shape[1]
        msg = f"{count} of {total} texels negative ({100 * count / total:.2g} %, min {arr.min():.4g})"
        if not clamp_negative:
            raise ValidateError(f"{path}: {msg}; pass --clamp-negative to clamp them to 0")
        arr = np.maximum(arr, 0.0)
        notes.append(f"clamped negative texels to 0: {msg}")
    if not (arr > 0).any():
        raise ValidateError(f"{path}: every texel is zero")
    return arr, notes


def detect_layout(shape: tuple[int, ...], path: Path | str) -> str:
    h, w = shape[:2]
    if w == 2 * h:
        return "latlong"
    if w == h:
        return "angular"
    if 4 * w == 3 * h:
        return "cross"
    raise ValidateError(f"{path}: {w}×{h} is not 2:1 (lat-long), 1:1 (angular map) or 3:4 (vertical "
                        "cross); pass --layout to override")


def angular_to_latlong(angular: np.ndarray, height: int | None = None, supersample: int = 2) -> np.ndarray:
    """Resample a Debevec angular map (−z at the centre) to a lat-long map (H, 2H, 3)."""
    n = angular.shape[0]
    if height is None:
        height = int(min(512, max(32, 2 ** int(np.round(np.log2(n / 2))))))
    width = 2 * height
    out = np.zeros((height, width, 3), dtype=np.float64)
    th_c, ph_c = latlong.row_theta(height), latlong.col_phi(width)
    dth, dph = np.pi / (height - 1), 2 * np.pi / width
    offs = (np.arange(supersample) + 0.5) / supersample - 0.5
    for oy in offs:
        for ox in offs:
            th = np.clip(th_c + oy * dth, 0.0, np.pi)
            tt, pp = np.meshgrid(th, ph_c + ox * dph, indexing="ij")
            d = latlong.spherical_to_direction(tt, pp)
            out += sample_angular(angular, d)
    return (out / supersample**2).astype(np.float32)


def angular_direction_to_pixel(d: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Continuous pixel coordinates (x right, y down; pixel centres at k+½) of directions d."""
    rxy = np.sqrt(d[..., 0] ** 2 + d[..., 1] ** 2)
    r = np.where(rxy > 1e-12, np.arccos(np.clip(-d[..., 2], -1, 1)) / (np.pi * np.maximum(rxy, 1e-12)), 0.0)
    u = 0.5 + 0.5 * d[..., 0] * r
    v = 0.5 - 0.5 * d[..., 1] * r
    return u * n, v * n


def sample_angular(angular: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Bilinear lookup in an angular map at directions d (..., 3)."""
    n = angular.shape[0]
    x, y = angular_direction_to_pixel(d, n)
    return _bilinear_clamped(angular, x - 0.5, y - 0.5)


def _bilinear_clamped(img: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    h, w = img.shape[:2]
    x = np.clip(x, 0, w - 1)
    y = np.clip(y, 0, h - 1)
    x0 = np.clip(np.floor(x).astype(np.int64), 0, w - 2)
    y0 = np.clip(np.floor(y).astype(np.int64), 0, h - 2)
    fx = (x - x0)[..., None]
    fy = (y - y0)[..., None]
    top = img[y0, x0] * (1 - fx) + img[y0, x0 + 1] * fx
    bot = img[y0 + 1, x0] * (1 - fx) + img[y0 + 1, x0 + 1] * fx
    return top * (1 - fy) + bot * fy


# Vertical cross faces: (row, col) → (face forward axis, right axis, down axis) in world space.
_CROSS_FACES = {
    (0, 1): ((0, 1, 0), (1, 0, 0), (0, 0, -1)),   # +y, looking up: right +x, down −z
    (1, 0): ((-1, 0, 0), (0, 0, -1), (0, -1, 0)),  # −x
    (1, 1): ((0, 0, -1), (1, 0, 0), (0, -1, 0)),   # −z (forward)
    (1, 2): ((1, 0, 0), (0, 0, 1), (0, -1, 0)),    # +x
    (2, 1): ((0, -1, 0), (1, 0, 0), (0, 0, 1)),    # −y
    (3, 1): ((0, 0, 1), (1, 0, 0), (0, 1, 0)),     # +z (back), upside down
}


def cross_to_latlong(cross: np.ndarray, height: int | None = None) -> np.ndarray:
    """Resample an HDRShop vertical cross (3F wide, 4F tall) to a lat-long map (H, 2H, 3)."""
    f = cross.shape[1] // 3
    if height is None:
        height = int(min(512, 2 * f))
    d = latlong.texel_directions(height, 2 * height)
    out = np.zeros(d.shape[:2] + (3,), dtype=np.float32)
    best = np.full(d.shape[:2], -np.inf)
    for (row, col), (fwd, right, down) in _CROSS_FACES.items():
        fwd, right, down = (np.array(a, dtype=np.float64) for a in (fwd, right, down))
        proj = d @ fwd
        sel = (proj > best) & (proj > 0)
        if not sel.any():
            continue
        best = np.where(sel, proj, best)
        ds = d[sel]
        a = (ds @ right) / (ds @ fwd)
        b = (ds @ down) / (ds @ fwd)
        face = cross[row * f:(row + 1) * f, col * f:(col + 1) * f]
        out[sel] = _bilinear_clamped(face, (a + 1) * 0.5 * f - 0.5, (b + 1) * 0.5 * f - 0.5)
    return out


def latlong_to_cross(radiance: np.ndarray, face: int) -> np.ndarray:
    """Inverse of :func:`cross_to_latlong` (for tests and for users who want crosses)."""
    cross = np.zeros((4 * face, 3 * face, 3), dtype=np.float32)
    t = (np.arange(face) + 0.5) / face * 2 - 1
    bb, aa = np.meshgrid(t, t, indexing="ij")
    for (row, col), (fwd, right, down) in _CROSS_FACES.items():
        fwd, right, down = (np.array(x, dtype=np.float64) for x in (fwd, right, down))
        d = fwd + aa[..., None] * right + bb[..., None] * down
        d /= np.linalg.norm(d, axis=-1, keepdims=True)
        cross[row * face:(row + 1) * face, col * face:(col + 1) * face] = latlong.bilinear_lookup(radiance, d)
    return cross


def load_environment(path: str | Path, layout: str = "auto", clamp_negative: bool = False,
                     name: str | None = None) -> Environment:
    """Load one environment file (see the module docstring for layouts and validation)."""
    path = Path(path)
    if layout not in LAYOUTS:
        raise ValidateError(f"--layout {layout}: unknown layout; choose one of {', '.join(LAYOUTS)}")
    arr = read_image(path)
    arr, notes = check_texels(arr, path, clamp_negative)
    kind = detect_layout(arr.shape, path) if layout == "auto" else layout
    angular = None
    if kind == "latlong":
        if arr.shape[1] != 2 * arr.shape[0]:
            raise ValidateError(f"{path}: --layout latlong needs a 2:1 image, got {arr.shape[1]}×{arr.shape[0]}")
        radiance = arr
    elif kind == "angular":
        if arr.shape[0] != arr.shape[1]:
            raise ValidateError(f"{path}: --layout angular needs a square image, got {arr.shape[1]}×{arr.shape[0]}")
        angular = arr
        radiance = angular_to_latlong(arr)
        notes.append(f"angular map {arr.shape[1]}×{arr.shape[0]} resampled to lat-long "
                     f"{radiance.shape[1]}×{radiance.shape[0]}")
    else:
        if 4 * arr.shape[1] != 3 * arr.shape[0]:
            raise ValidateError(f"{path}: --layout cross needs a 3:4 image, got {arr.shape[1]}×{arr.shape[0]}")
        radiance = cross_to_latlong(arr)
        notes.append(f"vertical cross resampled to lat-long {radiance.shape[1]}×{radiance.shape[0]}")
    return Environment(name=name or path.stem, radiance=np.ascontiguousarray(radiance, np.float32),
                       kind="probe", description=f"{path.name} ({kind})", source=path, layout=kind,
                       angular=angular, notes=tuple(notes))
