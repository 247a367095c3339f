"""``python -m validate bench``: speed and memory, measured side by side in one run.

Kernels (this process; best of ``repeats`` runs after one warm-up, JIT compilation excluded; a projection
and its plain reduction run alternately, so that load on the machine touches both alike):

* SH projection (l ≤ 2 and l ≤ 8) of a 512×1024 lat-long map — the separable projection
  (:func:`validate.local_models.irradiance.sh.project_environment`) beside a *plain reduction over the same
  texels*, Σ_i Ω_i Σ_j L_ij, computed the fastest way we know (the same polyphase per-row matrix
  products, rows shared among the CPUs the same way, with a single row of ones), beside a plain
  drjit sum of the texels already on the device, and beside the direct per-texel sum in drjit
  (:func:`~validate.local_models.irradiance.sh.project_samples`). The ratio to the plain reduction is the figure:
  the memory-bound limit is one pass over the texels.
* SH9 irradiance at 100k normals: drjit vs numpy; the techniques ported to drjit (ltc per shape,
  uberlight_fore_june_printed, phong_prefiltered_s) beside their frozen numpy originals (:func:`.kernels.port_rows`).
* The GL runtimes (:mod:`validate.bench.gl_runtimes`): cold start of each runtime, and each built-in GLSL technique's
  per-receiver cost beside its Python transcription.
* The fits (:mod:`validate.bench.fits`): each scipy fit beside its drjit-AD twin, time and residual.
* The engines (:mod:`validate.bench.render`): browser start, page load per engine, first frame and the median of
  later frames per engine and scene, in one fresh process; beside them Blender (:mod:`validate.bench.blender`):
  start-up, first and later frames of Cycles and EEVEE in one Blender child process.

Map sizes (one child process per size and task, so that each peak RSS is clean): an H×2H map
(H = 1024, 2048, 4096, 8192 by default: "1k" … "8k" name the rows), a smooth sky with a 0.5° sun,
built in the child row block by row block (not timed: it stands for reading the file). Tasks:

* ``reference`` — :func:`~validate.reference.irradiance.reference_irradiance` at 10k normals,
  default cells, cache off: seconds, peak RSS, the doubling change (convergence).
* ``sh9`` — SH9 at 10k normals (projection + R&H eq. 12) and, in the same process, the plain
  reduction over the same texels: seconds, their ratio, peak RSS; then (after the peak is read) a
  plain drjit sum of the same texels already copied to the device, the memory-bound reference.

A size whose estimated peak (:func:`validate.scenes.loaders.estimated_peak_bytes`) exceeds the
memory available is skipped with the reason. ``--only`` runs some of the sections :data:`SECTIONS`
(kernels, gl, sizes, fits, render). Results go to ``<out>/bench.json`` (atomic): ``tables``
(headers, rows, caption — what the report shows) and the raw ``kernels`` and ``sizes`` records.
"""

from __future__ import annotations

import datetime as _dt
import json
from pathlib import Path
from typing import Any

from .kernels import DEFAULT_SIZES

# ``--only`` picks among these (fits: :mod:`.fits`, render: :mod:`.render`)
SECTIONS = ("kernels", "gl", "sizes", "fits", "render")


def run_bench(out: Path, sizes: tuple[int, ...] = DEFAULT_SIZES, sections: tuple[str, ...] = SECTIONS) -> int:
    from .. import backend
    from ..atomic import write_text
    from . import blender as bench_blender
    from . import fits as bench_fits
    from . import gl_runtimes as bench_gl
    from . import render as bench_render
    from .kernels import kernel_rows, size_records, tables

    be = backend.init()
    print(f"backend: {be.describe()}")
    kernels = kernel_rows() if "kernels" in sections else []
    gl_starts: list[dict[str, Any]] = []
    gl_rows: list[dict[str, Any]] = []
    if "gl" in sections:
        print("GL runtimes (cold start: child processes; per receiver: this process) ...")
        gl_starts, gl_rows = bench_gl.startup_records(), bench_gl.per_receiver_rows()
    records: list[dict[str, Any]] = []
    if "sizes" in sections:
        print("map sizes (child processes):")
        records = size_records(sizes)
    fits = bench_fits.fit_rows() if "fits" in sections else []
    render: dict[str, Any] = {}
    if "render" in sections:
        print("engines: start-up and frame times (a child process) ...")
        render = bench_render.records()
        print("Blender: start-up and frame times (a child process) ...")
        render["blender"] = bench_blender.records()
    tabs = tables(kernels, records) if kernels or records else []
    tabs += bench_gl.tables(gl_starts, gl_rows) if "gl" in sections else []
    tabs += bench_fits.tables(fits) if fits else []
    tabs += bench_render.tables(render) if "render" in sections else []
    tabs += bench_blender.tables(render["blender"]) if "render" in sections else []
    doc = {"generated": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"), "backend": be.variant,
           "sections": list(sections), "tables": tabs, "kernels": kernels, "sizes": records,
           "gl": {"startup": gl_starts, "per_receiver": gl_rows}, "fits": fits, "render": render}
    for t in doc["tables"]:
        print(f"\n{t['caption']}")
        print(" | ".join(t["headers"]))
        for r in t["rows"]:
            print(" | ".join(str(v) for v in r))
    out.mkdir(parents=True, exist_ok=True)
    write_text(out / "bench.json", json.dumps(doc, indent=2))
    print(f"\nwrote {out / 'bench.json'}")
    return 0

