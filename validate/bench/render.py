"""The engines' frame times and start-up in ``python -m validate bench`` (issue 21 item 7), side by side in one run.

One fresh child process (nothing warm: no browser, no page, no compiled program) measures, in order:

* browser start — :func:`validate.gl.runtime.get` ``("webgl2")``: headless Chromium on SwiftShader with its WebGL2
  page (ms);
* per engine, page load — :func:`validate.gl.browser_page.open_page`: the engine's ES modules imported from
  node_modules over the loopback server until the page sets ``window.ready`` (ms);
* per engine and scene, the first frame (shader compilation, shadow-map allocation, geometry upload) and then
  ``LATER_FRAMES`` later frames of the same scene, the engines taking turns frame by frame so that load on the machine
  touches all alike; each frame is timed twice: the wall time of :func:`validate.local_models.render.render` (the
  page call, scene build, draw, read-back — float32 for three/Babylon, the 8-bit canvas for Filament, which draws
  2–4 frames per call for its auto exposure (:mod:`validate.local_models.render`) — and transfer) and the page's own
  ``frame_ms`` (draw + read-back, ``performance.now()`` in the page). The figures are the first frame, the median
  of the later frames, and their ratio first / later (×).

Engines: every registered engine that renders in this process and is not a variant
(:mod:`validate.local_models.render.registry`; today three.js, Babylon.js, Filament). Scenes:
``lambert_directional`` (the 64² Lambertian sphere under a directional light, scene (c)) and ``shadow_directional``
with PCF shadows (scene (e), a 512² shadow map; Filament's 1024², its default) for the engines offering PCF. Without
Chromium or node_modules the section holds the reason.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from typing import Any

import numpy as np

LATER_FRAMES = 5
RESOLUTION = 64


def engines() -> list[Any]:
    """The registered engines that render in this process, variants left out (module docstring)."""
    from ..experiments.renders.kinds import renders_in_process  # noqa: PLC0415
    from ..local_models.render import registry  # noqa: PLC0415

    return [e for e in registry.main_engines() if renders_in_process(e)]


def _scenes() -> list[tuple[Any, tuple[str, ...]]]:
    """(scene, the features it needs) pairs."""
    from ..scenes import render_scenes as rs  # noqa: PLC0415
    from ..scenes import render_shadow_scenes as rss  # noqa: PLC0415

    return [(rs.lambert_sun_scene(RESOLUTION), ("directional",)),
            (rss.sun_shadow_scene(RESOLUTION).with_shadow_type("pcf"), ("directional", "shadows"))]


def _renders(engine: Any, scene: Any, needs: tuple[str, ...]) -> bool:
    shadow = getattr(scene, "shadow_type", None)
    return engine.skip_reason(needs) is None and (shadow is None or shadow in engine.shadow_types)


def _timed(engine: Any, scene: Any) -> tuple[float, float]:
    t0 = time.perf_counter()
    r = engine.render(scene)
    return (time.perf_counter() - t0) * 1e3, float(r.frame_ms)


def child() -> dict[str, Any]:
    """The measurement in this (fresh) process (module docstring); a JSON-able record."""
    from ..gl import browser_page, runtime  # noqa: PLC0415

    t0 = time.perf_counter()
    rt = runtime.get("webgl2")
    rec: dict[str, Any] = {"browser_start_ms": (time.perf_counter() - t0) * 1e3,
                           "renderer": rt.info.get("GL_RENDERER", ""), "engines": {}}
    engs = engines()
    for e in engs:
        t0 = time.perf_counter()
        for page in e.pages():
            browser_page.open_page(page)
        rec["engines"][e.name] = {"page_load_ms": (time.perf_counter() - t0) * 1e3, "scenes": {}}
    for scene, needs in _scenes():
        these = [e for e in engs if _renders(e, scene, needs)]
        frames: dict[str, list[tuple[float, float]]] = {e.name: [_timed(e, scene)] for e in these}
        for _ in range(LATER_FRAMES):
            for e in these:
                frames[e.name].append(_timed(e, scene))
        for e in frames:
            f = np.asarray(frames[e])
            rec["engines"][e]["scenes"][scene.name] = {
                "first_wall_ms": f[0, 0], "first_page_ms": f[0, 1], "later_wall_ms": float(np.median(f[1:, 0])),
                "later_page_ms": float(np.median(f[1:, 1])), "later_frames": LATER_FRAMES}
    runtime.close_all()
    return rec


def records() -> dict[str, Any]:
    """Run :func:`child` in a fresh process; ``{"error": ...}`` with the reason when it cannot run."""
    proc = subprocess.run([sys.executable, "-m", "validate.bench.render"], capture_output=True, text=True, timeout=900)
    if proc.returncode != 0:
        last = (proc.stderr.strip().splitlines() or [f"exit status {proc.returncode}"])[-1]
        return {"error": last[:300]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def tables(rec: dict[str, Any]) -> list[dict[str, Any]]:
    """Two tables: start-up (browser, page load per engine) and frames per engine × scene."""
    if "error" in rec:
        return [{"caption": "Engines' start-up and frame times (skipped)", "headers": ["reason (–)"],
                 "rows": [[rec["error"]]]}]
    st = [["browser (headless Chromium, SwiftShader WebGL2)", round(rec["browser_start_ms"], 1)]]
    st += [[f"page load: {e}", round(r["page_load_ms"], 1)] for e, r in rec["engines"].items()]
    fr = []
    for e, r in rec["engines"].items():
        for name, s in r["scenes"].items():
            fr.append([e, name, round(s["first_wall_ms"], 1), round(s["first_page_ms"], 1),
                       round(s["later_wall_ms"], 1), round(s["later_page_ms"], 1),
                       round(s["first_wall_ms"] / s["later_wall_ms"], 2)])
    return [
        {"caption": f"Engines' start-up, one fresh process ({rec.get('renderer', '')}; ms)",
         "headers": ["step", "wall (ms)"], "rows": st},
        {"caption": f"Engines' frames at {RESOLUTION}² (first frame, then the median of {LATER_FRAMES} later frames, "
                    "engines taking turns; wall = the whole call with read-back and transfer, page = draw + "
                    "read-back inside the page)",
         "headers": ["engine", "scene", "first frame wall (ms)", "first frame page (ms)", "later frames wall (ms)",
                     "later frames page (ms)", "first / later wall (×)"], "rows": fr},
    ]


if __name__ == "__main__":  # child process: python -m validate.bench.render
    print(json.dumps(child()))
