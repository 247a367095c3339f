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
texels, negative texels beyond float noise (unless ``clamp_negative``), an aspect ratio that is none of
the above, an all-zero map, a map too small to integrate, and a map too large for the memory available.

Negative texels that are noise. Renderers and denoisers write slightly negative texels (reconstruction
filter undershoot, float rounding); radiance cannot be negative, so such texels are clamped to 0 by
default and the clamp is noted (:attr:`Environment.clamped_negative`, the report, ``results.json``).
They count as noise when both hold, with Ȳ the mean Rec. 709 luminance over the file's texels:

    |min texel value| ≤ NEGATIVE_NOISE_RELATIVE · Ȳ = 0.05 Ȳ   and   #negative ≤ NEGATIVE_NOISE_SHARE · #texels = 0.5 %

Then the clamp adds at most 0.05 × 0.005 = 2.5·10⁻⁴ of the texel-summed luminance, 40× below the
1 % average error R&H 2001 state for SH9, the tightest published tolerance the suite checks. Measured
on every file of ``../shared/probes`` with negative texels (share = #negative / #texels; Δ Φ_Y = the
clamp's change of the solid-angle luminance flux):

    file                          texels  share     min         |min|/Ȳ   ΔΦ_Y/Φ_Y
    blender_world_interior            1   1.9e-6   −2.3e-6      2.6e-6    3e-13
    blender_world_studio              3   5.7e-6   −6.6e-7      1.2e-6    8e-13
    blender_world_sunset              4   7.6e-6   −7.7e-4      1.8e-3    4e-10
    blender_world_courtyard           9   1.7e-5   −1.6e-4      2.9e-4    1.4e-9
    blender_world_night             250   4.8e-4   −1.7e-3      1.4e-2    5.9e-8
    blender_world_sunrise           358   6.8e-4   −7.0e-4      1.6e-3    1.7e-9
    blender_world_forest            826   1.6e-3   −2.2e-3      2.8e-3    1.7e-8
    uffizi_probe-128_latlong       7525   1.4e-2   −0.93        0.52      1.4e-3
    uffizi_probe-128 (angular)      982   6.0e-2   −1.00        2.1       (6.2e-3 texel-summed)

The Blender worlds (worst: night 1.4·10⁻², forest 0.16 %) pass both bounds with a margin of 3.6× and
3.2×; the two Uffizi copies, whose masked corners hold −1 (a capture artefact, not noise), fail both
(10× and 2.9× beyond), and stay refused: skipped with the reason in a ``--probes`` folder, an error for
``--probe``. ``--clamp-negative`` clamps any negative texels.

Minimum size. Every layout must put at least :data:`MIN_TEXELS_PER_PI` = 16 texels across 180°:
lat-long H ≥ 16 rows (W ≥ 32), angular N ≥ 32 (its radius N/2 spans θ ∈ [0, π]), cross faces F ≥ 8
(two faces span 180°). Why 16: the suite projects spherical harmonics up to degree l = 8 (the order
sweep of the ``sh9`` experiment); a degree-l harmonic has l periods around a great circle, so sampling
it needs more than l texels per π (Nyquist), and the bilinear interpolant Mitsuba reconstructs
between texels attenuates a mode sampled near Nyquist — 2l = 16 texels per π keeps every band the
suite measures resolved. Below H = 2 the lat-long convention θ_i = iπ/(H−1) does not even exist
(a 2×1 map divided by zero); a 1×1 file is an "angular" map of one texel.

Memory. Before a pixel is read, the header's size is compared with the memory available
(:func:`check_memory`): a map whose estimated peak exceeds it is refused with the one-line error
instead of being killed by the kernel half-way.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..backend import bitmap_io_threads, init
from ..errors import ValidateError
from . import latlong
from .environment import Environment

EXTENSIONS = (".exr", ".hdr", ".pic", ".pfm")
LAYOUTS = ("auto", "latlong", "angular", "cross")
NEGATIVE_NOISE_RELATIVE = 0.05  # |min| / mean luminance below which negatives are float noise (docstring)
NEGATIVE_NOISE_SHARE = 0.005  # at most this share of the texels (docstring: measured on the shared probes)
LUMINANCE = (0.2126, 0.7152, 0.0722)  # Rec. 709
MIN_TEXELS_PER_PI = 16  # 2 × the highest SH degree the suite projects (l = 8); see the module docstring
# Peak memory of a run per byte of the float32 RGB lat-long map. Measured (`run sh9 --quick --probe`,
# peak RSS, 1k → 8k maps): 1.02 GiB with a 24 MiB map, 1.52 GiB with 384 MiB, 4.97 GiB with 1.5 GiB —
# about 2.6× the map beyond a 1 GiB runtime (the reference and SH9 alone: 1.2×, `validate bench`; the
# rest is other techniques' full-size temporaries). 4× leaves room for experiments that build Mitsuba
# envmaps of the map (a bitmap copy plus its texture and sampling tables).
MAP_MEMORY_MULTIPLE = 4.0
RUNTIME_BYTES = 1 << 30


def read_header_size(path: Path) -> tuple[int, int] | None:
    """(height, width) from the file header without reading pixels (OpenEXR ``dataWindow``, Radiance
    ``-Y H +X W`` line, PFM ``W H`` line); None when the header is not understood (the reader then
    reports the problem)."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(1 << 16)
    except OSError:
        return None
    if head[:4] == b"v/1\x01":  # OpenEXR: attributes name\0 type\0 size value … until an empty name
        pos = 8
        while pos < len(head) and head[pos] != 0:
            end = head.find(b"\0", pos)
            tend = head.find(b"\0", end + 1)
            if end < 0 or tend < 0 or tend + 5 > len(head):
                return None
            name = head[pos:end]
            size = int.from_bytes(head[tend + 1:tend + 5], "little", signed=True)
            value = head[tend + 5:tend + 5 + size]
            if name == b"dataWindow" and len(value) == 16:
                x0, y0, x1, y1 = (int.from_bytes(value[i:i + 4], "little", signed=True) for i in range(0, 16, 4))
                return y1 - y0 + 1, x1 - x0 + 1
            pos = tend + 5 + size
        return None
    if head[:2] in (b"PF", b"Pf"):
        parts = head.split(None, 3)
        if len(parts) >= 3 and parts[1].isdigit() and parts[2].isdigit():
            return int(parts[2]), int(parts[1])
        return None
    if head[:2] == b"#?":  # Radiance: header lines, an empty line, then the resolution line
        blank = head.find(b"\n\n")
        if blank >= 0:
            line = head[blank + 2:].split(b"\n", 1)[0].split()
            if len(line) == 4 and line[1].isdigit() and line[3].isdigit():
                rows, cols = int(line[1]), int(line[3])
                return (rows, cols) if line[0].endswith(b"Y") else (cols, rows)
    return None


def available_memory() -> int | None:
    """Bytes this process may still allocate: ``MemAvailable`` (/proc/meminfo), lowered by a cgroup
    v2 ``memory.max`` limit when one is set; None where neither can be read."""
    avail = None
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                avail = int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        used = int(Path("/sys/fs/cgroup/memory.current").read_text().strip())
        if limit != "max":
            room = int(limit) - used
            avail = room if avail is None else min(avail, room)
    except (OSError, ValueError):
        pass
    return avail


def estimated_peak_bytes(height: int, width: int) -> int:
    """Estimated peak memory of validating one map of this size: MAP_MEMORY_MULTIPLE × the float32
    RGB lat-long map, plus the fixed runtime."""
    return int(MAP_MEMORY_MULTIPLE * height * width * 12) + RUNTIME_BYTES


def check_memory(path: Path, height: int, width: int, available: int | None = None) -> None:
    """Refuse (one line) a map whose estimated peak memory exceeds what is available."""
    available = available_memory() if available is None else available
    need = estimated_peak_bytes(height, width)
    if available is not None and need > available:
        gib = 1 << 30
        raise ValidateError(f"{path}: a {width}×{height} map needs about {need / gib:.1f} GiB "
                            f"({MAP_MEMORY_MULTIPLE:g}× its {height * width * 12 / gib:.2f} GiB float32 "
                            f"copy + runtime) but only {available / gib:.1f} GiB is available")


def check_min_size(shape: tuple[int, ...], kind: str, path: Path | str) -> None:
    """Raise when a map of ``kind`` puts fewer than MIN_TEXELS_PER_PI texels across 180°."""
    h, w = shape[:2]
    need = {"latlong": (MIN_TEXELS_PER_PI, 2 * MIN_TEXELS_PER_PI),
            "angular": (2 * MIN_TEXELS_PER_PI, 2 * MIN_TEXELS_PER_PI),
            "cross": (4 * MIN_TEXELS_PER_PI // 2, 3 * MIN_TEXELS_PER_PI // 2)}[kind]
    if h < need[0] or w < need[1]:
        raise ValidateError(f"{path}: {w}×{h} {kind} map is too small to integrate: needs at least "
                            f"{need[1]}×{need[0]} ({MIN_TEXELS_PER_PI} texels across 180°)")


def read_image(path: Path) -> np.ndarray:
    """Read an HDR image as float32 RGB (H, W, 3) with Mitsuba's reader; one-line errors."""
    import mitsuba as mi

    init()
    if not path.exists():
        raise ValidateError(f"{path}: no such file")
    if not path.is_file():
        raise ValidateError(f"{path}: not a regular file")
    if path.suffix.lower() not in EXTENSIONS:
        raise ValidateError(f"{path}: unsupported file type {path.suffix!r} (use .exr, .hdr or .pfm)")
    size = read_header_size(path)
    if size is not None:
        check_memory(path, *size)
    try:
        with bitmap_io_threads():
            bmp = mi.Bitmap(str(path))
            channels = bmp.channel_count()
            fmt = mi.Bitmap.PixelFormat.Y if channels == 1 else mi.Bitmap.PixelFormat.RGB
            if bmp.pixel_format() == fmt and bmp.component_format() == mi.Struct.Type.Float32:
                conv = bmp  # already float32 RGB (or Y): no converted copy of a large map
            else:
                conv = bmp.convert(fmt, mi.Struct.Type.Float32, srgb_gamma=False)
        del bmp  # the file's own pixels are no longer needed
        arr = np.asarray(conv)  # a view: no third copy
        if channels == 1:
            arr = np.repeat(arr.reshape(arr.shape[0], arr.shape[1], 1), 3, axis=2)
    except ValidateError:
        raise
    except Exception as exc:  # mitsuba raises RuntimeError with multi-line text
        first = str(exc).strip().splitlines()[-1] if str(exc).strip() else type(exc).__name__
        raise ValidateError(f"{path}: cannot read image ({first[:160]})") from None
    arr = np.ascontiguousarray(arr.reshape(arr.shape[0], arr.shape[1], 3), dtype=np.float32)
    if arr.size == 0:
        raise ValidateError(f"{path}: image is empty")
    return arr


ROW_BLOCK_BYTES = 64 << 20  # texel checks run over row blocks of ~64 MiB: no full-size temporaries


def _row_blocks(arr: np.ndarray) -> range:
    rows = max(1, ROW_BLOCK_BYTES // max(1, arr[0].nbytes))
    return range(0, arr.shape[0], rows)


def check_texels(arr: np.ndarray, path: Path | str, clamp_negative: bool
                 ) -> tuple[np.ndarray, list[str], tuple[int, float] | None]:
    """Reject NaN/Inf; clamp negative texels that are noise (module docstring) in place and note them,
    reject larger ones unless ``clamp_negative``; reject all-zero maps. Returns (array, notes, clamped)
    with clamped = (texels clamped, the lowest value before the clamp) or None. Streams over row
    blocks, so a large map needs no full-size temporary arrays."""
    notes: list[str] = []
    clamped: tuple[int, float] | None = None
    nonfinite = negative = 0
    lowest, positive, lum = np.inf, False, 0.0
    weights = np.asarray(LUMINANCE, dtype=np.float64)
    step = _row_blocks(arr).step
    for s in _row_blocks(arr):
        block = arr[s:s + step]
        nonfinite += int((~np.isfinite(block)).any(axis=-1).sum())
        neg = (block < 0).any(axis=-1)
        if neg.any():
            negative += int(neg.sum())
            lowest = min(lowest, float(block.min()))
        positive = positive or bool((block > 0).any())
        if not nonfinite:
            lum += float((block.reshape(-1, 3) @ weights).sum())
    if nonfinite:
        raise ValidateError(f"{path}: {nonfinite} texel(s) are NaN or Inf")
    if negative:
        total = arr.shape[0] * arr.shape[1]
        mean = lum / total
        noise = -lowest <= NEGATIVE_NOISE_RELATIVE * mean and negative <= NEGATIVE_NOISE_SHARE * total
        msg = f"{negative} of {total} texels negative ({100 * negative / total:.2g} %, min {lowest:.4g}"
        msg += f", {-lowest / mean:.2g} × the mean luminance)" if mean > 0 else ")"
        if not (noise or clamp_negative):
            raise ValidateError(f"{path}: {msg}; beyond float noise (|min| ≤ {NEGATIVE_NOISE_RELATIVE:g} × mean "
                                f"luminance and ≤ {100 * NEGATIVE_NOISE_SHARE:g} % of the texels); pass "
                                "--clamp-negative to clamp them to 0")
        if not arr.flags.writeable:
            arr = arr.copy()
        for s in _row_blocks(arr):
            np.maximum(arr[s:s + step], 0.0, out=arr[s:s + step])
        why = "float noise" if noise else "--clamp-negative"
        notes.append(f"{CLAMP_NOTE} ({why}): {msg}")
        clamped = (negative, lowest)
    if not positive:
        raise ValidateError(f"{path}: every texel is zero")
    return arr, notes, clamped


CLAMP_NOTE = "clamped negative texels to 0"


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
    kind = detect_layout(arr.shape, path) if layout == "auto" else layout
    arr, notes, clamped = check_texels(arr, path, clamp_negative)
    angular = None
    if kind == "latlong":
        if arr.shape[1] != 2 * arr.shape[0]:
            raise ValidateError(f"{path}: --layout latlong needs a 2:1 image, got {arr.shape[1]}×{arr.shape[0]}")
        check_min_size(arr.shape, "latlong", path)
        radiance = arr
    elif kind == "angular":
        if arr.shape[0] != arr.shape[1]:
            raise ValidateError(f"{path}: --layout angular needs a square image, got {arr.shape[1]}×{arr.shape[0]}")
        check_min_size(arr.shape, "angular", path)
        angular = arr
        radiance = angular_to_latlong(arr)
        notes.append(f"angular map {arr.shape[1]}×{arr.shape[0]} resampled to lat-long "
                     f"{radiance.shape[1]}×{radiance.shape[0]}")
    else:
        if 4 * arr.shape[1] != 3 * arr.shape[0]:
            raise ValidateError(f"{path}: --layout cross needs a 3:4 image, got {arr.shape[1]}×{arr.shape[0]}")
        check_min_size(arr.shape, "cross", path)
        radiance = cross_to_latlong(arr)
        notes.append(f"vertical cross resampled to lat-long {radiance.shape[1]}×{radiance.shape[0]}")
    return Environment(name=name or path.stem, radiance=np.ascontiguousarray(radiance, np.float32),
                       kind="probe", description=f"{path.name} ({kind})", source=path, layout=kind,
                       angular=angular, notes=tuple(notes), clamped_negative=clamped)
