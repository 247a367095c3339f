"""Blender's start-up and frame times in ``python -m validate bench`` (section ``render``, beside the browser engines).

One Blender child process (:func:`validate.local_models.render.blender.render_batch`: nothing cached, nothing warm
but the disk caches the operating system and Mesa keep) renders the browser engines' first scene,
``lambert_directional`` (the 64² Lambertian sphere under a sun, through Blender's glTF importer), with Cycles
(:data:`CYCLES_SPP` spp per frame) and with EEVEE (:data:`EEVEE_SAMPLES` TAA samples per frame, the count the
``blender`` experiment renders its world-lit spheres with), :data:`FRAMES` frames each. Figures: ``import bpy`` in
the child, the child's whole wall time, per engine the scene set-up (import of the .glb, settings), the first frame
(EEVEE: its shaders compiled on llvmpipe, unless Mesa's shader disk cache holds them) and the median of the later
frames. Without Blender the table holds the reason.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

import numpy as np

FRAMES = 4
CYCLES_SPP = 16
EEVEE_SAMPLES = (4, 16)
RESOLUTION = 64


def records() -> dict[str, Any]:
    from ..errors import ValidateError  # noqa: PLC0415
    from ..local_models.render import blender as bl  # noqa: PLC0415
    from ..scenes import render_scenes as rs  # noqa: PLC0415
    from ..scenes.gltf_export import glb_bytes  # noqa: PLC0415

    version, why = bl.available()
    if version is None:
        return {"error": f"Blender not installed ({why}): {bl.FIX}"}
    scene = rs.lambert_sun_scene(RESOLUTION)
    with tempfile.TemporaryDirectory(prefix="validate-bench-blender-") as d:
        work = Path(d)
        glb = work / "scene.glb"
        glb.write_bytes(glb_bytes(scene))
        seeds = tuple(range(FRAMES))
        runs = [("blender_cycles", CYCLES_SPP, bl.Job(str(glb), str(work / "c"), "CYCLES", RESOLUTION, CYCLES_SPP,
                                                       seeds))]
        runs += [("blender_eevee", n, bl.Job(str(glb), str(work / f"e{n}"), "BLENDER_EEVEE", RESOLUTION, n, seeds))
                 for n in EEVEE_SAMPLES]
        try:
            batch = bl.render_batch([j for _, _, j in runs], work)
        except ValidateError as exc:
            return {"error": str(exc)}
    return {"version": batch.version, "import_s": batch.import_s, "process_wall_s": batch.wall_s, "scene": scene.name,
            "engines": [{"engine": e, "samples": n, "setup_s": r.setup_s, "first_s": r.frame_s[0],
                         "later_s": float(np.median(r.frame_s[1:])), "later_frames": len(r.frame_s) - 1}
                        for (e, n, _), r in zip(runs, batch.results, strict=True)]}


def tables(rec: dict[str, Any]) -> list[dict[str, Any]]:
    if "error" in rec:
        return [{"caption": "Blender's start-up and frame times (skipped)", "headers": ["reason (–)"],
                 "rows": [[rec["error"]]]}]
    rows = [["start-up: import bpy in the child", "", round(1e3 * rec["import_s"], 1), "", ""],
            ["the child process, start to exit", "", round(1e3 * rec["process_wall_s"], 1), "", ""]]
    rows += [[e["engine"], e["samples"], round(1e3 * e["setup_s"], 1), round(1e3 * e["first_s"], 1),
              round(1e3 * e["later_s"], 1)] for e in rec["engines"]]
    return [{"caption": f"Blender {rec['version']}: start-up and frames of {rec['scene']} at {RESOLUTION}² (one child "
                        f"process; later = median of {FRAMES - 1} frames; Cycles spp / EEVEE TAA samples)",
             "headers": ["step", "samples (count)", "set-up or wall (ms)", "first frame (ms)", "later frames (ms)"],
             "rows": rows}]
