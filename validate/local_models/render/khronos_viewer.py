"""``khronos_viewer``: the Khronos glTF Sample Viewer (npm ``@khronosgroup/gltf-viewer`` 1.1.0), Khronos's reference
renderer for glTF PBR, rendering the exported scene files.

The viewer runs as a page (``khronos_viewer.html`` + ``khronos_viewer.mjs``) in the run's one headless Chromium
(:mod:`validate.gl.browser_page`, which serves ``node_modules`` and the published files locally: no CDN). Each scene
goes through the viewer's own public API only: ``ResourceLoader.loadGltf`` on the exported ``.glb``,
``ResourceLoader.loadEnvironment`` on the scene's environment (its RGBE reader, then its WebGL IBL sampler:
panorama → 256² cube, Lambertian cube of 2048 samples per texel, GGX mip chain of 1024, Charlie chain, its
1024² GGX LUT — the viewer's defaults, unchanged) and ``GltfView.renderFrame`` with the glTF file's camera.

Inputs the viewer cannot take as exported, converted without loss where possible:

* the environment: its loader reads Radiance RGBE (``.hdr``) only, so the manifest's OpenEXR is re-encoded as RGBE
  (:func:`validate.scenes.render_scenes.rgbe_bytes`; 8-bit mantissas: radiance 1 — the furnace — round-trips exactly,
  other values to 2⁻⁸ relative at worst), unrotated, with the viewer's default ``environmentRotation`` (90°);
* the sheen "E" LUT (``lut_sheen_E.png``), a file of the viewer's web app that the npm package does not ship: a 1×1
  placeholder is served. It only scales materials with ``KHR_materials_sheen``, which no exported scene uses.

Readback. ``renderFrame`` draws only to the canvas (RGBA8): with tone mapping ``ToneMaps.NONE`` ("linear mapping,
clamped at 1.0") the shader still applies its output transfer pow(c, 1/2.2) (``tonemapping.glsl``
``linearTosRGB``: a pure 2.2 gamma, not the sRGB curve). The page reads the canvas with ``gl.readPixels`` and tries
exposures (the viewer's own ``renderingParameters.exposure``, a factor before the transfer) from high to low until
no covered value is 255; :func:`decode` gives radiance L = (q/255)^2.2 / e and, for the uncertainty, rounding to
nearest leaves q uniform on ±½ LSB, so σ_L = 2.2 (q/255)^1.2 / (255 √12 e) (:func:`readback_stderr`). The written
``<scene>.exr`` holds the decoded float values (alpha = coverage q_a/255); ``precision = "unorm8"`` says the
quantisation must be added (the ``renders`` experiment's ``khronos`` part does, per pixel); ``validate judge`` on the
folder alone reads float and adds none.
"""

from __future__ import annotations

import hashlib
import json
import struct
import time
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...setup import paths
from .engine import Engine, FolderRender, Unavailable

PACKAGE = "@khronosgroup/gltf-viewer"
PAGE = "khronos_viewer.html"
GAMMA = 2.2  # the viewer's output transfer (tonemapping.glsl: INV_GAMMA = 1/2.2)
EXPOSURES = tuple(2.0**k for k in range(1, -11, -1))  # tried in order: the first with no covered value at 255
FIX = "python -m validate setup --engines"
# The IBL sampler's instance fields (khronos_viewer.mjs sets them after its constructor). Its defaults (IBL_DEFAULTS)
# cost 560 s per environment on SwiftShader (2 cores, measured: 3.5e9 texture samples, 2.1e9 of them the two
# 1024² LUTs); the suite keeps its sample counts and its five GGX roughness levels (lowestMipLevel lowered with the
# cube, roughness = level/4 as shipped) and shrinks the cube and the LUT (IBL_SUITE). A scene without an environment
# gets a black one with IBL off, filtered at the smallest sizes (IBL_OFF: its textures are never sampled).
IBL_DEFAULTS = {"textureSize": 256, "lowestMipLevel": 4, "lutResolution": 1024, "lambertianSampleCount": 2048,
                "ggxSampleCount": 1024, "sheenSamplCount": 64}
IBL_SUITE = {**IBL_DEFAULTS, "textureSize": 64, "lowestMipLevel": 2, "lutResolution": 128}
# quick runs: cube 16², LUT 64² (4.5 s of SwiftShader; 64² / 128² took 36 s for the furnace, measured). On a constant
# environment the cube's size and sample counts change nothing (every sample returns the constant; both filters
# normalise by their weights): only the LUT is approximated, by its bilinear lookup at 64².
IBL_QUICK = {**IBL_DEFAULTS, "textureSize": 16, "lowestMipLevel": 0, "lutResolution": 64}
IBL_OFF = {"textureSize": 16, "lowestMipLevel": 0, "lutResolution": 16, "lambertianSampleCount": 1,
           "ggxSampleCount": 1, "sheenSamplCount": 1}


def decode(q: np.ndarray, exposure: float) -> np.ndarray:
    """(H, W, 4) RGBA8 canvas values → RGB radiance (q/255)^2.2/e and alpha q/255 (row order unchanged)."""
    x = np.asarray(q, np.float64) / 255.0
    out = x.copy()
    out[..., :3] = x[..., :3] ** GAMMA / exposure
    return out


def readback_stderr(radiance: np.ndarray, exposure: float) -> np.ndarray:
    """σ of the decoded radiance from the 8-bit rounding (module docstring): 2.2 c^1.2/(255 √12 e),
    c = (e L)^(1/2.2)."""
    c = np.clip(np.asarray(radiance, np.float64) * exposure, 0.0, None) ** (1.0 / GAMMA)
    return GAMMA * c ** (GAMMA - 1.0) / (255.0 * np.sqrt(12.0) * exposure)


def _png_1x1() -> bytes:
    """A 1×1 black RGB PNG (the sheen E LUT placeholder: module docstring)."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(b"\x00\x00\x00\x00")) + chunk(b"IEND", b""))


def _write_exr(path: Path, rgba: np.ndarray) -> None:
    import OpenEXR

    chans = {c: np.ascontiguousarray(rgba[..., k], np.float32) for k, c in enumerate("RGBA")}
    with OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, chans) as f:
        f.write(str(path))


def _publish(name: str, data: bytes) -> str:
    from ...gl import browser_page

    return browser_page.publish(f"khronos_{hashlib.sha256(data).hexdigest()[:16]}_{name}", data)


def _environment_url(scenes_dir: Path, entry: dict, cache: dict[str, str]) -> str:
    env = entry.get("environment")
    if not env:  # the viewer draws nothing without an environment object: a black one, IBL off (module docstring)
        if "" not in cache:
            from ...scenes.render_scenes import rgbe_bytes

            cache[""] = _publish("black.hdr", rgbe_bytes(np.zeros((4, 8, 3))))
        return cache[""]
    f = env["file"]
    if f not in cache:
        from ...scenes.manifest import read_exr_rgb
        from ...scenes.render_scenes import rgbe_bytes

        cache[f] = _publish(Path(f).stem + ".hdr", rgbe_bytes(read_exr_rgb(scenes_dir / f)))
    return cache[f]


@dataclass(frozen=True)
class KhronosViewer(Engine):
    """The glTF Sample Viewer in the run's Chromium (module docstring); ``ibl``: its IBL sampler's fields."""

    ibl: dict = field(default_factory=lambda: dict(IBL_QUICK))

    def version(self) -> str | None:
        return paths.installed_version(PACKAGE)

    def unavailable(self) -> Unavailable | None:
        if self.version() is None:
            return Unavailable(f"npm {PACKAGE}", f"not installed in {paths.node_modules()}", FIX)
        from ...gl import runtime

        ok, why = runtime.available("webgl2")
        if not ok:
            return Unavailable("Chromium (WebGL2)", (why or "unavailable").splitlines()[0][:200],
                               "python -m validate setup --system")
        return None

    def render_folder(self, scenes_dir: Path, names: Sequence[str], out_dir: Path) -> FolderRender:
        """Render ``names`` of the exported folder into ``out_dir/<scene>.exr`` (module docstring)."""
        import base64

        from ...gl import browser_page

        t_start = time.perf_counter()
        scenes_dir, out_dir = Path(scenes_dir), Path(out_dir)
        doc = json.loads((scenes_dir / "manifest.json").read_text())
        entries = {e["name"]: e for e in doc["scenes"] + doc.get("gltf_scenes", [])}
        out = FolderRender(version=self.version() or "?", images={})
        t0 = time.perf_counter()
        browser_page.open_page(PAGE)
        out.startup_s = time.perf_counter() - t0
        out_dir.mkdir(parents=True, exist_ok=True)
        sheen = _publish("lut_sheen_E.png", _png_1x1())
        envs: dict[str, str] = {}
        for name in names:
            e = entries.get(name)
            if e is None:
                out.skipped[name] = f"no scene {name!r} in {scenes_dir / 'manifest.json'}"
                continue
            w, h = int(e["image"]["width"]), int(e["image"]["height"])
            arg = {"glb": _publish(e["glb"], (scenes_dir / e["glb"]).read_bytes()),
                   "env": _environment_url(scenes_dir, e, envs), "ibl": bool(e.get("environment")),
                   "iblSettings": self.ibl if e.get("environment") else IBL_OFF, "sheenLut": sheen, "width": w,
                   "height": h, "exposures": list(EXPOSURES)}
            r = browser_page.call(PAGE, "renderKhronos", arg)
            q = np.frombuffer(base64.b64decode(r["pixels"]), np.uint8).reshape(h, w, 4)[::-1]  # row 0 = top
            rgba = decode(q, float(r["exposure"]))
            path = out_dir / f"{name}.exr"
            _write_exr(path, rgba)
            out.images[name] = path
            out.frame_ms[name] = float(r["frame_ms"])
            out.info[name] = {"exposure": float(r["exposure"]), "exposures_tried": int(r["tries"]),
                              "saturated": bool((q[..., :3][q[..., 3] > 0] == 255).any()),
                              "load_ms": float(r["load_ms"]), "environment_ms": float(r["env_ms"]),
                              "ibl": r.get("ibl"), "renderer": r.get("renderer"), "encoding": "gamma2.2_unorm8"}
        out.wall_s = time.perf_counter() - t_start
        return out


ENGINE = KhronosViewer(
    name="khronos_viewer", product="glTF Sample Viewer", precision="unorm8",
    supports=("furnace", "directional", "point", "spot", "environment", "perspective", "textures"),
    defects={"readback": "renderFrame draws only to the 8-bit canvas with a 2.2 gamma (tonemapping.glsl "
                         "linearTosRGB): decoded, the quantisation enters the uncertainty",
             "environment": "loadEnvironment reads Radiance .hdr only (resource_loader.js loadHDR)",
             "shadows": "draws no shadows (measured: shadow_directional 9.1 % of the pixels accepted, its umbra lit)"})

__all__ = ["ENGINE", "KhronosViewer", "decode", "readback_stderr", "EXPOSURES", "GAMMA", "PACKAGE"]
