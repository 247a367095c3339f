"""The hosted engines' common harness: a page of this folder in the run's one headless Chromium.

A hosted engine is a page (``<engine>.html`` + ``<engine>_render.mjs``) in the run's one headless Chromium
(:mod:`validate.gl.browser_page`), reading the scene JSON of
:meth:`~validate.scenes.render_scenes.RenderScene.engine_json` and returning an RGBA32F image read back exactly (or,
Filament, its 8-bit canvas: :func:`decode_unorm8`). :meth:`BrowserEngine.render` returns (R, R, 4) float32 with
row 0 = TOP (the scene's convention), the alpha channel = coverage (0 off the sphere).

An engine is a :class:`BrowserEngine` declared in its own module (``three``, ``babylon``, ``filament``): the fields
of :class:`.engine.Engine`, plus its page, the page's entry point, the options the page reads and the npm package
whose version it is.

Precision budget (what an engine may differ from the exact integral of its own model without a bug):
three's PMREM and Babylon's prefiltered cube store half floats (relative 2⁻¹¹ ≈ 4.9e-4 per texel);
SwiftShader's sin/cos are good to ~2e-4 absolute (:mod:`validate.gl.webgl`).
"""

from __future__ import annotations

import base64
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...gl import browser_page, runtime
from ...setup import paths
from .engine import Engine, EngineRender, Unavailable

HERE = Path(__file__).resolve().parent
HALF_FLOAT_RTOL = 2.0**-11  # IEEE binary16: 10 explicit mantissa bits, unit roundoff 2⁻¹¹
SWIFTSHADER_TRIG_ATOL = 2e-4  # measured sin/cos error (validate.gl.webgl docstring)
FIX_NPM = "python -m validate setup --engines"
# three.js r187's RectAreaLight (lights_physical_pars_fragment.glsl) and Babylon 9.35's (ltcHelperFunctions, the same
# LTC code): the clipped-sphere form factor (|F|² + F·n)/(|F| + 1) (three LTC_ClippedSphereFormFactor, Babylon
# LTCClippedSphereFormFactor) even where the rectangle is wholly above the horizon and the exact form factor is F·n
# (Lambert's polygon formula) — measured engine/(L·that) = 0.9999 for both engines
LTC_CLIPPED_SPHERE = ("its clipped-sphere form factor (|F|² + F·n)/(|F| + 1) over-estimates a tilted rectangle wholly "
                      "above the horizon, where the exact form factor is F·n")


@dataclass(frozen=True)
class BrowserEngine(Engine):
    """One engine hosted in the run's Chromium (module docstring)."""

    page: str = ""  # the page of this folder (``three.html``)
    entry: str = ""  # the page's render function (``renderThree``)
    options: dict[str, Any] = field(default_factory=dict)  # what the page reads besides the scene
    package: str = ""  # the npm package whose version is the engine's
    scripts: tuple[str, ...] = ()  # the page's own modules (``three_render.mjs`` …), beside the page

    def version(self) -> str | None:
        return paths.installed_version(self.package) if self.package else None

    def unavailable(self) -> Unavailable | None:
        return missing_runtime((self.package,) if self.package else None)

    def pages(self) -> tuple[str, ...]:
        return (self.page,)

    def sources(self) -> tuple[Path, ...]:
        return tuple(HERE / f for f in (self.page, "common.mjs", *self.scripts))

    def cache_parts(self, scene: Any) -> dict[str, Any] | None:
        parts = super().cache_parts(scene)
        return None if parts is None else {**parts, "options": self.options}

    def render(self, scene: Any) -> EngineRender:
        """The page renders ``scene``; raises GLUnavailable with the reason when it cannot run, ValidateError for a
        shadow type the engine does not offer."""
        shadow = getattr(scene, "shadow_type", None)
        if shadow is not None and shadow not in self.shadow_types:
            raise ValidateError(f"engine {self.name}: shadow type {shadow!r} not one of {list(self.shadow_types)}")
        t0 = time.perf_counter()
        r = browser_page.call(self.page, self.entry, dict(scene.engine_json(), options=self.options))
        n = scene.resolution
        stderr = 0.0
        if r.get("encoding") == "unorm8_linear":  # Filament's canvas: q = round(255·e·L), alpha 255 = covered
            img, stderr = decode_unorm8(r["data"], (n, n, 4), float(r["exposure"]))
        else:
            img = browser_page.decode_f32(r["data"], (n, n, 4))
        img = img[::-1].copy()  # readPixels row 0 = bottom
        return EngineRender(img, float(r.get("frame_ms", np.nan)), time.perf_counter() - t0,
                            str(r.get("version", "")), dict(r.get("info") or {}), stderr)


def missing_runtime(packages: tuple[str, ...] | None = None) -> Unavailable | None:
    """Why a hosted engine cannot render here (its npm package — by default every pinned one — not installed at the
    pinned version, or no headless Chromium with WebGL2), or None. Checks the cheap one first; the browser check
    starts the run's browser, which the renders use next."""
    pinned = paths.pinned_versions()
    absent = [p for p, v in pinned.items() if (packages is None or p in packages) and paths.installed_version(p) != v]
    if absent:
        return Unavailable("npm engines", f"{', '.join(absent)} not installed in {paths.node_modules()}", FIX_NPM)
    ok, why = runtime.available("webgl2")
    if not ok:
        return Unavailable("Chromium (WebGL2)", why.splitlines()[0][:200] if why else "unavailable",
                           "python -m validate setup --system")
    return None


def decode_unorm8(data: str, shape: tuple[int, ...], exposure: float) -> tuple[np.ndarray, float]:
    """8-bit linear readback → (radiance L = q/(255·e) with alpha q/255, its standard uncertainty).

    Rounding to nearest leaves an error uniform on ±½ LSB: standard deviation 1/√12 LSB, i.e.
    σ_L = 1/(255·√12·e) in radiance."""
    q = np.frombuffer(base64.b64decode(data), dtype=np.uint8).reshape(shape).astype(np.float32) / 255.0
    q[..., :3] /= exposure
    return q, 1.0 / (255.0 * np.sqrt(12.0) * exposure)


__all__ = ["BrowserEngine", "LTC_CLIPPED_SPHERE", "missing_runtime", "decode_unorm8", "HALF_FLOAT_RTOL",
           "SWIFTSHADER_TRIG_ATOL"]
