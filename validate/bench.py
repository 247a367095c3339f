"""``python -m validate bench``: speed and memory, measured side by side in one run.

* SH projection (order 2 and 8) of a 512×1024 lat-long map: the drjit local model vs a plain numpy
  einsum over the same texels — the ratio, not the absolute time, is the figure to compare.
* SH9 irradiance at 100k normals: drjit vs numpy.
* The reference quadrature for one environment (10k normals, default cells) and its peak memory.

Each timing is the best of ``repeats`` runs after one warm-up (JIT compilation excluded). Results go
to ``<out>/bench.json`` (atomic) and are printed.
"""

from __future__ import annotations

import json
import resource
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np


def _best(fn: Callable[[], object], repeats: int = 3) -> float:
    fn()  # warm-up (JIT compilation, caches)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def run_bench(out: Path) -> int:
    from . import backend
    from .atomic import write_text
    from .local_models import sh
    from .reference.irradiance import reference_irradiance
    from .scenes import latlong, procedural

    be = backend.init()
    print(f"backend: {be.describe()}")
    rng = np.random.default_rng(7)
    rad = rng.uniform(0.0, 1.0, (512, 1024, 3)).astype(np.float32)
    d = latlong.texel_directions(512, 1024).reshape(-1, 3)
    dw = latlong.texel_solid_angles(512, 1024).reshape(-1)
    normals = latlong.fibonacci_sphere(100_000)
    rows = []
    for lmax in (2, 8):
        t_dr = _best(lambda lm=lmax: sh.project_environment(rad, lm))
        t_np = _best(lambda lm=lmax: np.einsum("nk,nc->kc", sh.eval_basis_numpy(d, lm),
                                               rad.reshape(-1, 3) * dw[:, None]))
        rows.append({"task": f"SH projection l≤{lmax}, 512×1024 texels", "drjit_s": t_dr, "numpy_s": t_np,
                     "speedup": t_np / t_dr})
    coeffs = sh.project_environment(rad, 2)
    t_dr = _best(lambda: sh.render_irradiance_rh2001(coeffs, normals))
    t_np = _best(lambda: np.einsum("nk,kc->nc", sh.eval_basis_numpy(normals, 2),
                                   coeffs * np.array([sh.clamped_cosine_al(sh.degree_of(k))
                                                      for k in range(9)])[:, None]))
    rows.append({"task": "SH9 irradiance, 100k normals", "drjit_s": t_dr, "numpy_s": t_np, "speedup": t_np / t_dr})

    import os
    cache = os.environ.get("VALIDATE_CACHE")
    os.environ["VALIDATE_CACHE"] = "off"
    try:
        env = procedural.disc_on_sky()
        n10k = latlong.fibonacci_sphere(10_000)
        rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        t0 = time.perf_counter()
        reference_irradiance(env, n10k)
        t_ref = time.perf_counter() - t0
        rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    finally:
        if cache is None:
            os.environ.pop("VALIDATE_CACHE", None)
        else:
            os.environ["VALIDATE_CACHE"] = cache
    result = {"backend": be.variant, "rows": rows,
              "reference": {"task": "reference quadrature, disc_on_sky 256×512, 10k normals",
                            "seconds": t_ref, "peak_rss_mib": rss1 / 1024, "rss_growth_mib": (rss1 - rss0) / 1024}}
    print(f"\n{'task':44s} {'drjit':>10s} {'numpy':>10s} {'speed-up':>9s}")
    for r in rows:
        print(f"{r['task']:44s} {r['drjit_s'] * 1e3:8.1f}ms {r['numpy_s'] * 1e3:8.1f}ms {r['speedup']:8.1f}×")
    ref = result["reference"]
    print(f"{ref['task']}: {ref['seconds']:.2f} s, peak RSS {ref['peak_rss_mib']:.0f} MiB")
    out.mkdir(parents=True, exist_ok=True)
    write_text(out / "bench.json", json.dumps(result, indent=2))
    print(f"wrote {out / 'bench.json'}")
    return 0
