"""An engine's image file as the judge reads it: linear radiance, coverage, and the readback's own uncertainty.

Accepted: OpenEXR (half or float channels R, G, B, optional A = coverage; OpenEXR's reader) and PFM (float,
``PF`` three channels, either byte order; rows stored bottom-up, turned to row 0 = top). A half-float value
carries its rounding as a standard uncertainty: half keeps 10 mantissa bits, so a value v is stored to
ulp(v) = 2^(⌊log₂ v⌋ − 10) and the rounding error is uniform over ±ulp/2, σ_q = ulp(v)/√12 (≤ 2.8e-4 v), added in
quadrature to the truth's standard error as the renders experiment does for Filament's 8-bit canvas.

Refused, with the reason: PNG, JPEG and Radiance .hdr (display-referred or 8-bit-mantissa values: the judge needs
linear radiance to a known precision), and every file whose pixels are NaN, infinite or negative, whose alpha lies
outside [0, 1], or whose size is not the scene's. Each refusal is one line naming the file.

An EXR whose values were read back from a quantised buffer (an 8-bit linear canvas: Filament's) states the step in
its header, ``validate_quantisation_step`` (radiance per step, a float attribute): rounding to nearest leaves an
error uniform over ±step/2, σ_q = step/√12 per value, added in quadrature as the renders experiment does for its
8-bit readback; the image's precision reads ``unorm8``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ValidateError

IMAGE_SUFFIXES = (".exr", ".pfm")
REFUSED_SUFFIXES = {".png": "PNG holds display-referred 8- or 16-bit values, not radiance",
                    ".jpg": "JPEG is 8-bit, display-referred and lossy", ".jpeg": "JPEG is 8-bit, display-referred "
                                                                                    "and lossy",
                    ".hdr": "Radiance RGBE keeps 8 mantissa bits per channel (0.4 % steps, above the budgets)",
                    ".tif": "TIFF is not read by the judge", ".tiff": "TIFF is not read by the judge"}
HALF_MANTISSA_BITS = 10
QUANTISATION_ATTRIBUTE = "validate_quantisation_step"  # EXR header: radiance per readback step (module docstring)


@dataclass
class EngineImage:
    """(H, W, 3) linear radiance, (H, W) coverage, the storage precision and the (H, W, 3) readback σ."""

    rgb: np.ndarray
    coverage: np.ndarray
    precision: str  # "half" | "float" | "unorm8" (a stated quantisation step)
    readback_stderr: np.ndarray
    alpha: bool  # whether the file had an alpha channel (else coverage = 1)


def half_stderr(v: np.ndarray) -> np.ndarray:
    """σ_q = ulp(v)/√12 of a half-float value (module docstring); subnormals keep the smallest step 2⁻²⁴."""
    a = np.abs(np.asarray(v, np.float64))
    e = np.floor(np.log2(np.maximum(a, 2.0**-14)))
    return np.ldexp(1.0, (e - HALF_MANTISSA_BITS).astype(int)) / math.sqrt(12.0)


def _read_exr(path: Path) -> tuple[np.ndarray, np.ndarray | None, str, float | None]:
    import OpenEXR

    try:
        with OpenEXR.File(str(path), separate_channels=True) as f:
            ch = {k: np.asarray(v.pixels) for k, v in f.channels().items()}
            step = f.header().get(QUANTISATION_ATTRIBUTE)
    except Exception as exc:  # OpenEXR raises RuntimeError/OSError with its own text
        first = (str(exc).strip().splitlines() or [type(exc).__name__])[-1]
        raise ValidateError(f"{path}: cannot read OpenEXR ({first[:160]})") from None
    missing = [c for c in "RGB" if c not in ch]
    if missing:
        raise ValidateError(f"{path}: no channel {', '.join(missing)} (channels: {', '.join(sorted(ch)) or 'none'}; "
                            f"need R, G, B and optionally A)")
    dtypes = {ch[c].dtype for c in "RGB"}
    if not dtypes <= {np.dtype(np.float16), np.dtype(np.float32)}:
        raise ValidateError(f"{path}: channels of type {', '.join(sorted(map(str, dtypes)))}: need half or float")
    precision = "half" if np.dtype(np.float16) in dtypes else "float"
    rgb = np.stack([ch[c].astype(np.float64) for c in "RGB"], axis=-1)
    if step is not None and not (isinstance(step, float) and math.isfinite(step) and step > 0):
        raise ValidateError(f"{path}: header {QUANTISATION_ATTRIBUTE} = {step!r}: need a positive float")
    return rgb, ch["A"].astype(np.float64) if "A" in ch else None, precision, step


def _read_pfm(path: Path) -> tuple[np.ndarray, None, str, None]:
    data = path.read_bytes()
    try:
        head, rest = data.split(b"\n", 1)
        dims, rest = rest.split(b"\n", 1)
        scale_line, pixels = rest.split(b"\n", 1)
        w, h = (int(v) for v in dims.split())
        scale = float(scale_line)
    except ValueError:
        raise ValidateError(f"{path}: not a PFM file (header 'PF', 'W H', scale)") from None
    if head.strip() == b"Pf":
        raise ValidateError(f"{path}: a one-channel PFM (Pf): need three channels (PF)")
    if head.strip() != b"PF" or w < 1 or h < 1 or scale == 0:
        raise ValidateError(f"{path}: not a three-channel PFM (header {head[:8]!r}, size {w}x{h}, scale {scale})")
    if len(pixels) < w * h * 12:
        raise ValidateError(f"{path}: PFM truncated ({len(pixels)} bytes of pixels, need {w * h * 12})")
    arr = np.frombuffer(pixels[:w * h * 12], dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return arr[::-1].astype(np.float64), None, "float", None


def image_size(path: Path) -> tuple[int, int]:
    """(width, height) of an image the judge reads (module docstring), from its header; one-line errors."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in REFUSED_SUFFIXES:
        raise ValidateError(f"{path}: {REFUSED_SUFFIXES[suffix]}; write linear radiance as OpenEXR (half or float) "
                            f"or PFM")
    if suffix == ".pfm":
        try:
            lines = path.read_bytes()[:64].split(b"\n")
            w, h = (int(v) for v in lines[1].split())
        except OSError as exc:
            raise ValidateError(f"{path}: cannot read ({exc.strerror or exc})") from None
        except (ValueError, IndexError):
            raise ValidateError(f"{path}: not a PFM file (header 'PF', 'W H', scale)") from None
        return w, h
    if suffix != ".exr":
        raise ValidateError(f"{path}: unsupported file type {suffix!r} (use .exr or .pfm)")
    rgb = _read_exr(path)[0]
    return rgb.shape[1], rgb.shape[0]


def read_engine_image(path: Path, width: int, height: int) -> EngineImage:
    """The image at ``path`` for a scene of ``width`` × ``height`` (module docstring); one-line errors."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in REFUSED_SUFFIXES:
        raise ValidateError(f"{path}: {REFUSED_SUFFIXES[suffix]}; write linear radiance as OpenEXR (half or float) "
                            f"or PFM")
    if suffix not in IMAGE_SUFFIXES:
        raise ValidateError(f"{path}: unsupported file type {suffix!r} (use .exr or .pfm)")
    try:
        rgb, alpha, precision, step = _read_exr(path) if suffix == ".exr" else _read_pfm(path)
    except OSError as exc:
        raise ValidateError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if rgb.shape[:2] != (height, width):
        raise ValidateError(f"{path}: image is {rgb.shape[1]}x{rgb.shape[0]}, the scene is {width}x{height}")
    bad = ~np.isfinite(rgb)
    if bad.any():
        raise ValidateError(f"{path}: {int(bad.any(axis=-1).sum())} pixel(s) NaN or Inf (first at row, column "
                            f"{tuple(int(v) for v in np.argwhere(bad)[0][:2])})")
    if (rgb < 0).any():
        raise ValidateError(f"{path}: {int((rgb < 0).any(axis=-1).sum())} pixel(s) negative (min {rgb.min():.3g}): "
                            f"radiance is >= 0")
    if alpha is not None and (not np.all(np.isfinite(alpha)) or alpha.min() < 0 or alpha.max() > 1):
        raise ValidateError(f"{path}: alpha outside [0, 1] (coverage): min {np.nanmin(alpha):.3g}, "
                            f"max {np.nanmax(alpha):.3g}")
    se = half_stderr(rgb) if precision == "half" else np.zeros_like(rgb)
    if step is not None:
        se, precision = np.sqrt(se**2 + step**2 / 12.0), "unorm8"
    cov = alpha if alpha is not None else np.ones(rgb.shape[:2])
    return EngineImage(rgb, cov, precision, se, alpha is not None)


def write_exr(path: Path, rgb: np.ndarray, alpha: np.ndarray | None = None, half: bool = False) -> None:
    """An (H, W, 3) image (and coverage) as OpenEXR, half or float — what an engine writes back (tests, examples)."""
    import OpenEXR

    dt = np.float16 if half else np.float32
    chans = {c: np.ascontiguousarray(rgb[..., k], dt) for k, c in enumerate("RGB")}
    if alpha is not None:
        chans["A"] = np.ascontiguousarray(alpha, dt)
    with OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, chans) as f:
        f.write(str(path))


def write_pfm(path: Path, rgb: np.ndarray) -> None:
    """An (H, W, 3) image as little-endian PFM (rows bottom-up, as the format stores them)."""
    h, w = rgb.shape[:2]
    Path(path).write_bytes(f"PF\n{w} {h}\n-1.0\n".encode("ascii") +
                           np.ascontiguousarray(rgb[::-1], "<f4").tobytes())
