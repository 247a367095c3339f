"""The kernel and map-size sections of ``python -m validate bench`` (described in :mod:`validate.bench`): SH
projection beside its plain reduction, the drjit ports beside their numpy originals (:func:`port_rows`), and one
child process per map size and task (:func:`child`, run as ``python -m validate.bench TASK HEIGHT``)."""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .timing import best_pair, best_time

DEFAULT_SIZES = (1024, 2048, 4096, 8192)
N_NORMALS = 10_000
SUN_HALF_ANGLE_DEG = 0.5
SUN_ELEVATION_DEG = 35.0


def plain_reduction(radiance: np.ndarray) -> np.ndarray:
    """Σ_i Ω_i Σ_j L_ij (3,): the same row products as the SH projection
    (:func:`~.local_models.irradiance.sh.fourier_row_sums` with lmax = 0: the same polyphase matrix products,
    threads and blocks, one row of ones instead of the 2·lmax+1 Fourier columns) — the floor a projection can
    approach."""
    from ..local_models.irradiance.sh import fourier_row_sums
    from ..scenes import latlong

    h, w = radiance.shape[:2]
    rows = fourier_row_sums(radiance, 0)
    return latlong.row_solid_angles(h, w) @ rows[:, 0, :].astype(np.float64)


def sky_with_sun(height: int) -> np.ndarray:
    """A (H, 2H, 3) float32 test map: a smooth sky brighter at the zenith and a 0.5° sun at 35°
    elevation (radiance 2·10⁴), built in row blocks (no full-size float64 temporaries)."""
    from ..scenes import latlong

    w = 2 * height
    out = np.empty((height, w, 3), dtype=np.float32)
    el = np.radians(SUN_ELEVATION_DEG)
    sun = np.array([0.0, np.sin(el), -np.cos(el)])
    cos_sun = np.cos(np.radians(SUN_HALF_ANGLE_DEG))
    sky = np.array([0.35, 0.5, 0.9])
    ph = latlong.col_phi(w)
    th_all = latlong.row_theta(height)
    step = max(1, (16 << 20) // (w * 24))
    for s in range(0, height, step):
        d = latlong.spherical_to_direction(th_all[s:s + step, None], ph[None, :])
        up = np.clip(d[..., 1:2], -1.0, 1.0)
        val = sky * (1.2 + up) + 2e4 * (d @ sun >= cos_sun)[..., None]
        out[s:s + step] = val
    return out


def _peak_rss_mib() -> float:
    """This process's peak RSS: ``VmHWM`` (belongs to the address space, so it starts afresh at exec;
    ``ru_maxrss`` would carry the parent's peak over a fork + exec), else ``ru_maxrss``."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024  # kB
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # Linux: KiB


def child(task: str, height: int) -> dict[str, Any]:
    """One measurement in a fresh process (see the module docstring); returns a JSON-able record."""
    os.environ["VALIDATE_CACHE"] = "off"
    from .. import backend
    from ..local_models import sh
    from ..reference.irradiance import reference_irradiance
    from ..scenes import latlong
    from ..scenes.environment import Environment

    backend.init()
    normals = latlong.fibonacci_sphere(N_NORMALS)
    rad = sky_with_sun(height)
    rec: dict[str, Any] = {"task": task, "height": height, "width": 2 * height,
                           "map_mib": rad.nbytes / 2**20, "rss_before_mib": _peak_rss_mib()}
    if task == "reference":
        env = Environment(f"bench_{height}", rad)
        t0 = time.perf_counter()
        ref = reference_irradiance(env, normals)
        rec["seconds"] = time.perf_counter() - t0
        rec["convergence"] = ref.convergence
    elif task == "sh9":
        t0 = time.perf_counter()
        sh.render_irradiance_rh2001(sh.project_environment(rad, 2), normals)
        rec["seconds"] = time.perf_counter() - t0
        rec["projection_s"], rec["plain_reduction_s"] = best_pair(lambda: sh.project_environment(rad, 2),
                                                                   lambda: plain_reduction(rad), repeats=3)
        rec["peak_rss_mib"] = _peak_rss_mib()  # before the drjit copy of the map below
        rec["drjit_sum_s"] = _drjit_sum_seconds(rad)
    else:
        raise ValueError(f"unknown bench task {task!r}")
    rec.setdefault("peak_rss_mib", _peak_rss_mib())
    return rec


def _run_child(task: str, height: int) -> dict[str, Any]:
    proc = subprocess.run([sys.executable, "-m", "validate.bench", task, str(height)], capture_output=True,
                          text=True, timeout=3600)
    if proc.returncode != 0:
        last = (proc.stderr.strip().splitlines() or [f"exit status {proc.returncode}"])[-1]
        return {"task": task, "height": height, "width": 2 * height, "error": last[:200]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _drjit_sum_seconds(rad: np.ndarray) -> float:
    """A plain drjit reduction Σ L over the same texels (already on the device; evaluated)."""
    import drjit as dr

    from ..backend import float_type

    x = float_type()(np.ascontiguousarray(rad.reshape(-1), dtype=np.float32))
    dr.eval(x)

    def run() -> float:
        s = dr.sum(x)
        return float(s[0]) if dr.is_array_v(s) else float(s)

    return best_time(run)


def kernel_rows() -> list[dict[str, Any]]:
    """The in-process kernel comparisons (module docstring)."""
    from ..local_models import sh
    from ..scenes import latlong

    rng = np.random.default_rng(7)
    rad = rng.uniform(0.0, 1.0, (512, 1024, 3)).astype(np.float32)
    d = latlong.texel_directions(512, 1024).reshape(-1, 3)
    dw = latlong.texel_solid_angles(512, 1024).reshape(-1)
    rows = []
    t_drjit_sum = _drjit_sum_seconds(rad)
    for lmax in (2, 8):
        t_sep, t_plain = best_pair(lambda lm=lmax: sh.project_environment(rad, lm), lambda: plain_reduction(rad))
        t_direct = best_time(lambda lm=lmax: sh.project_samples(d, dw, rad.reshape(-1, 3).astype(np.float64), lm))
        rows.append({"task": f"SH projection l≤{lmax}, 512×1024 texels", "projection_s": t_sep,
                     "plain_reduction_s": t_plain, "ratio_to_plain": t_sep / t_plain,
                     "plain_drjit_sum_s": t_drjit_sum, "direct_drjit_s": t_direct})
    normals = latlong.fibonacci_sphere(100_000)
    coeffs = sh.project_environment(rad, 2)
    al = np.array([sh.clamped_cosine_al(sh.degree_of(k)) for k in range(9)])[:, None]
    t_dr = best_time(lambda: sh.render_irradiance_rh2001(coeffs, normals))
    t_np = best_time(lambda: np.einsum("nk,kc->nc", sh.eval_basis_numpy(normals, 2), coeffs * al))
    rows.append({"task": "SH9 irradiance, 100k normals", "drjit_s": t_dr, "numpy_s": t_np, "speedup": t_np / t_dr})
    return rows + port_rows()


PORTS_TEST = Path(__file__).resolve().parents[1] / "tests" / "local_models" / "test_ports.py"


def port_rows(n: int = 20_000) -> list[dict[str, Any]]:
    """The techniques ported from numpy to drjit (issue 22 item 3) beside their numpy originals, frozen in
    ``tests/local_models/test_ports.py`` (read from the checkout: one copy of each original; absent in an installed
    package, then one row says so). Each pair runs alternately (:func:`best_pair`), the family call in its dtype
    on the active backend, n receivers, the technique functions called directly (no registry checks) on both sides;
    set-up cached alike for both (the LTC table, the Phong maps: built in the warm-up)."""
    import importlib.util

    from ..geometry import unit

    if not PORTS_TEST.is_file():
        return [{"task": "numpy-vs-drjit ports", "skipped": f"{PORTS_TEST} absent (not a checkout)"}]
    spec = importlib.util.spec_from_file_location("_validate_frozen_ports", PORTS_TEST)
    t = importlib.util.module_from_spec(spec)  # type: ignore[arg-type]
    spec.loader.exec_module(t)  # type: ignore[union-attr]
    rng = np.random.default_rng(9)
    pts = rng.uniform(-2.0, 2.0, (n, 3))
    pts[:, 1] = rng.uniform(-1.0, 0.5, n)
    nrm = unit(rng.normal(size=(n, 3)))
    views = unit(nrm + rng.normal(0.0, 0.6, nrm.shape))
    from ..local_models.specular import prefiltered_specular as ps
    from ..local_models.specular.common import reflect
    from ..local_models.specular_arealight import ltc
    from ..local_models.uberlight import fore_june_falloff as fj

    rows = []
    f0 = np.array([0.9, 0.6, 0.3])
    for light in t.LTC_LIGHTS:
        brdf = {"alpha": 0.3, "f0": tuple(f0)}
        pair = best_pair(lambda lt=light, b=brdf: ltc.ltc(lt, b, pts, nrm, views),
                          lambda lt=light: t._np_ltc(lt, 0.3, f0, pts, nrm, views), repeats=3)
        rows.append((f"ltc, {light['shape']}, α = 0.3", pair))
    light, mat = t._uberlight_light(), {"albedo": 0.7, "ks": 0.3, "specular_exponent": 20.0}
    rows.append(("uberlight_fore_june_printed", best_pair(
        lambda: fj.uberlight_fore_june_printed(light, pts, nrm, views, mat),
        lambda: t._np_fore_june_printed(light, pts, nrm, views, mat), repeats=3)))
    rad = t._phong_env()
    v = np.where(np.sum(nrm * views, axis=1, keepdims=True) < 0, -views, views)
    brdf = {"model": "phong", "exponent": 100.0, "reflectance": 0.8}

    def original() -> np.ndarray:  # phong_prefiltered_s as it was: r in numpy float64, the same map cache
        r = reflect(nrm, v)
        return 0.8 * ps.cached_phong_cube(rad, 100.0, r).lookup(r)

    rows.append(("phong_prefiltered_s, s = 100", best_pair(lambda: ps.phong_prefiltered_s(rad, brdf, nrm, v),
                                                            original, repeats=3)))
    return [{"task": f"{name}, {n // 1000}k receivers", "drjit_s": dr_s, "numpy_s": np_s, "speedup": np_s / dr_s}
            for name, (dr_s, np_s) in rows]


def size_records(sizes: tuple[int, ...], log: Callable[[str], None] = print) -> list[dict[str, Any]]:
    """Reference and SH9 per map size, each in a child process (skipped when memory is short)."""
    from ..scenes.loaders import available_memory, estimated_peak_bytes

    out = []
    for h in sizes:
        need, avail = estimated_peak_bytes(h, 2 * h), available_memory()
        for task in ("reference", "sh9"):
            if avail is not None and need > avail:
                rec = {"task": task, "height": h, "width": 2 * h,
                       "skipped": f"needs ≈ {need / 2**30:.1f} GiB, {avail / 2**30:.1f} GiB available"}
            else:
                log(f"  {task} {h}×{2 * h} ...")
                rec = _run_child(task, h)
            out.append(rec)
    return out


def tables(kernels: list[dict[str, Any]], sizes: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The report's tables (headers, rows, caption) from the raw records."""
    proj = [[k["task"], round(k["projection_s"] * 1e3, 2), round(k["plain_reduction_s"] * 1e3, 2),
             round(k["ratio_to_plain"], 2), round(k["plain_drjit_sum_s"] * 1e3, 2), round(k["direct_drjit_s"] * 1e3, 1)]
            for k in kernels if "projection_s" in k]
    other = [[k["task"], round(k["drjit_s"] * 1e3, 2), round(k["numpy_s"] * 1e3, 2), round(k["speedup"], 1)]
             for k in kernels if "drjit_s" in k]
    other += [[k["task"], k["skipped"], None, None] for k in kernels if "skipped" in k]
    by = {(r["height"], r["task"]): r for r in sizes}
    rows = []
    for h in sorted({r["height"] for r in sizes}):
        ref, s9 = by.get((h, "reference"), {}), by.get((h, "sh9"), {})

        def cell(r: dict[str, Any], key: str, scale: float = 1.0, nd: int = 2) -> Any:
            return round(r[key] * scale, nd) if key in r else (r.get("skipped") or r.get("error") or None)

        label = f"{h // 1024}k ({h}×{2 * h})" if h % 1024 == 0 else f"{h}×{2 * h}"
        rows.append([label, round(h * 2 * h * 12 / 2**20, 1),
                     cell(ref, "seconds"), cell(ref, "peak_rss_mib", nd=0), cell(ref, "convergence", 100, 4),
                     cell(s9, "seconds"), cell(s9, "peak_rss_mib", nd=0),
                     cell(s9, "projection_s", 1e3), cell(s9, "plain_reduction_s", 1e3), cell(s9, "drjit_sum_s", 1e3),
                     round(s9["projection_s"] / s9["plain_reduction_s"], 2) if "projection_s" in s9 else None])
    return [
        {"caption": "SH projection vs a plain reduction over the same texels (ms; best of 3)",
         "headers": ["task", "projection (ms)", "plain reduction (ms)", "projection / plain reduction (×)",
                     "plain drjit sum (ms)", "direct drjit projection (ms)"], "rows": proj},
        {"caption": "drjit vs numpy: SH9 irradiance and the ported techniques (ms; best of 3, pairs run alternately)",
         "headers": ["task", "drjit (ms)", "numpy (ms)", "speed-up (×)"], "rows": other},
        {"caption": "Reference and SH9 per map size, each in its own process (peak RSS includes the map)",
         "headers": ["map", "map size (MiB)", "reference (s)", "reference peak RSS (MiB)", "reference convergence (%)",
                     "SH9 (s)", "SH9 peak RSS (MiB)", "SH9 projection (ms)", "plain reduction (ms)",
                     "drjit sum, map on device (ms)", "SH9 projection / plain reduction (×)"], "rows": rows},
    ]
