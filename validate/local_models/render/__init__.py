"""Engines rendering a :class:`~validate.scenes.render_scenes.RenderScene` through their own pipelines.

Each engine is a page (``<engine>.html`` + ``<engine>_render.mjs``) in the run's one headless Chromium
(:mod:`validate.gl.browser_page`), reading the scene JSON of
:meth:`~validate.scenes.render_scenes.RenderScene.engine_json` and returning an RGBA32F image read back
exactly. :func:`render` returns (R, R, 4) float32 with row 0 = TOP (the scene's convention), the alpha
channel = coverage (0 off the sphere).

Engines
-------
``three``    three.js 0.187 — MeshPhysicalMaterial, PMREMGenerator, FloatType target (three_render.mjs).
``babylon``  Babylon.js 9.35 — PBRMaterial, its HDR prefilter, TEXTURETYPE_FLOAT target (babylon_render.mjs).

``filament`` Filament 1.53.4 (npm, WebAssembly) — a glTF binary of the geometry through gltfio's ubershader, its
             LightManager lights (filament.html + filament_render.mjs). Punctual lights only: the package ships no
             IBL prefilter (cmgen), no area lights, and its JS Renderer has no ``readPixels``; the canvas (RGBA8,
             post-processing off: linear, no OETF) is read with WebGL2's own ``gl.readPixels``. The 8-bit readback
             is decoded as radiance = q/(255·e) (e = the exposure the page picked) and carries its quantisation as
             a per-pixel standard uncertainty ``EngineRender.stderr`` = 1/(255·√12·e) (±½ LSB uniform, rounding to
             nearest: OpenGL ES 3.0 §2.1.6.1).

Precision budget (what an engine may differ from the exact integral of its own model without a bug):
three's PMREM and Babylon's prefiltered cube store half floats (relative 2⁻¹¹ ≈ 4.9e-4 per texel);
SwiftShader's sin/cos are good to ~2e-4 absolute (:mod:`validate.gl.webgl`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ...gl import browser_page, runtime
from ...scenes.render_scenes import RenderScene
from ...setup import paths

# engine → (page, entry point, options the page reads); "babylon_lambert" is Babylon with its diffuse model set to
# Lambert (MATERIAL_DIFFUSE_MODEL_LAMBERT = 2) instead of its default energy-preserving Oren–Nayar; "three_probe" is
# three.js with a hemisphere light given as a LightProbe whose SH is built as three's HemisphereLightProbe built it
# (removed from three; three issue 26668) instead of a HemisphereLight.
ENGINES = {"three": ("three.html", "renderThree", {}), "babylon": ("babylon.html", "renderBabylon", {}),
           "babylon_lambert": ("babylon.html", "renderBabylon", {"diffuseModel": 2}),
           "three_probe": ("three.html", "renderThree", {"hemisphereProbe": True}),
           "filament": ("filament.html", "renderFilament", {})}
# Babylon's CDF irradiance (babylon_cdf.mjs; validate.scenes.render_cdf_scenes): "babylon_cdf<size>_<variant>", the
# Lambert diffuse model, the cube of <size>, supersampling as shipped (forced by Babylon PR 16247) or as before it
ENGINES.update({f"babylon_cdf{n}_{v}": ("babylon.html", "renderBabylon",
                                        {"diffuseModel": 2, "irradiance": "cdf", "cubeSize": n, "supersample": v})
                for n in (32, 64, 128, 256, 512) for v in ("shipped", "pre16247")})
# what each engine is, for a person: the product whose pixels are judged
PRODUCTS = {"three": "three.js", "babylon": "Babylon.js", "filament": "Filament"}
HALF_FLOAT_RTOL = 2.0**-11  # IEEE binary16: 10 explicit mantissa bits, unit roundoff 2⁻¹¹
SWIFTSHADER_TRIG_ATOL = 2e-4  # measured sin/cos error (validate.gl.webgl docstring)


@dataclass
class EngineRender:
    image: np.ndarray  # (R, R, 4) float32, row 0 = top
    frame_ms: float
    wall_s: float
    version: str
    info: dict = field(default_factory=dict)  # what the page reports besides pixels (e.g. three's light.power)
    stderr: float = 0.0  # the readback's own standard uncertainty per value (radiance; 0 for a float target)


def product(engine: str) -> str:
    """The product an engine name renders with (``babylon_cdf64_shipped`` → Babylon.js)."""
    return next((v for k, v in PRODUCTS.items() if engine.startswith(k)), engine)


@dataclass(frozen=True)
class Missing:
    """A runtime the engines need that this machine lacks: what it is, why, and the command that installs it."""

    piece: str
    why: str
    fix: str


def missing_runtime() -> Missing | None:
    """Why no engine can render here (the npm engines not installed, or no headless Chromium with WebGL2), or None.
    Checks the cheap one first; the browser check starts the run's browser, which the renders use next."""
    absent = [p for p, v in paths.pinned_versions().items() if paths.installed_version(p) != v]
    if absent:
        return Missing("npm engines", f"{', '.join(absent)} not installed in {paths.node_modules()}",
                       "python -m validate setup --engines")
    ok, why = runtime.available("webgl2")
    if not ok:
        return Missing("Chromium (WebGL2)", why.splitlines()[0][:200] if why else "unavailable",
                       "python -m validate setup --system")
    return None


def render(engine: str, scene: RenderScene) -> EngineRender:
    """``engine`` renders ``scene``; raises GLUnavailable with the reason when it cannot run."""
    page, fn, options = ENGINES[engine]
    t0 = time.perf_counter()
    r = browser_page.call(page, fn, dict(scene.engine_json(), options=options))
    n = scene.resolution
    stderr = 0.0
    if r.get("encoding") == "unorm8_linear":  # Filament's canvas: q = round(255·e·L), alpha 255 = covered
        img, stderr = decode_unorm8(r["data"], (n, n, 4), float(r["exposure"]))
    else:
        img = browser_page.decode_f32(r["data"], (n, n, 4))
    img = img[::-1].copy()  # readPixels row 0 = bottom
    return EngineRender(img, float(r.get("frame_ms", np.nan)), time.perf_counter() - t0, str(r.get("version", "")),
                        dict(r.get("info") or {}), stderr)


def decode_unorm8(data: str, shape: tuple[int, ...], exposure: float) -> tuple[np.ndarray, float]:
    """8-bit linear readback → (radiance L = q/(255·e) with alpha q/255, its standard uncertainty).

    Rounding to nearest leaves an error uniform on ±½ LSB: standard deviation 1/√12 LSB, i.e.
    σ_L = 1/(255·√12·e) in radiance."""
    import base64

    q = np.frombuffer(base64.b64decode(data), dtype=np.uint8).reshape(shape).astype(np.float32) / 255.0
    q[..., :3] /= exposure
    return q, 1.0 / (255.0 * np.sqrt(12.0) * exposure)


__all__ = ["ENGINES", "EngineRender", "render", "decode_unorm8", "HALF_FLOAT_RTOL", "SWIFTSHADER_TRIG_ATOL"]

