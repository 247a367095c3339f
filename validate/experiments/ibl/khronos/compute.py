"""The glTF-IBL-Sampler part of ``ibl``, the measurements (numbers only).

* ``furnace``: the tool's Lambertian cube and GGX chain (roughness 0 and 1) of a constant environment L ≡ 1:
  max |C − 1| (units);
* ``orientation``: a marked environment (red, green: each texel's own (u, v) in the suite's lat-long
  convention) through the GGX chain's level 0 (roughness 0: the panorama resampled to the cube), looked up at
  R d (:data:`~validate.local_models.khronos_ibl.SUITE_TO_CUBE`) and at the mirrored R·diag(−1, 1, 1) d: the
  largest (u, v) error in texels of the panorama, away from the seam and the poles (one job for both:
  :func:`orientation_and_furnace`);
* ``probes``: on each of the paper's probes present, flux_luminance mean / max (|ΔY(E)| / Y(Φ)) against the
  irradiance quadrature (:func:`validate.reference.irradiance.reference_irradiance`) of
  ``khronos_ibl_lambertian``, of ``sh9`` and of the suite's convolution cube of the same face, and of the
  technique at mirrored normals (x → −x, the power check);
* ``sweep``: the technique's error on the first paper probe with one of ``sampleCount``, face and ``lodBias``
  changed at a time.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ....local_models import irradiance, khronos_ibl
from ....local_models.irradiance import irradiance_map as im
from ....local_models.irradiance.khronos_ibl_lambertian import FACE, lambertian_irradiance, lambertian_options
from ....metrics.irradiance_error import irradiance_errors
from ....reference.irradiance import reference_irradiance
from ....scenes import latlong
from ....scenes.probes import read_aliases
from ...base import Context, NotRun
from ..settings import Settings

TECH = "khronos_ibl_lambertian"
SPEC_TECH = "khronos_ibl_ggx"
MIRROR = np.array([-1.0, 1.0, 1.0])
MIRRORED = "normals mirrored x → −x (a handedness bug: the cube read in the mirrored frame)"
MARKED_SHAPE = (64, 128)  # the marked panorama (rows, columns)


@dataclass
class KhronosMeasurements:
    version: str | None
    missing: NotRun | None = None
    furnace: dict[str, float] = field(default_factory=dict)
    orientation: dict[str, float] = field(default_factory=dict)
    probes: dict[str, dict[str, Any]] = field(default_factory=dict)  # probe → {model: {mean, max, …}}
    sweep: dict[str, Any] = field(default_factory=dict)
    specular: dict[str, dict[str, Any]] = field(default_factory=dict)  # technique → case → relative error stats


def orientation_and_furnace() -> tuple[dict[str, float], dict[str, float]]:
    """One GGX job on a marked environment: red and green each texel's own (u, v) in the suite's lat-long
    convention, blue ≡ 1. Level 0 (roughness 0: the panorama resampled to the cube) read at R d and at the mirror
    R·diag(−1, 1, 1) d gives the (u, v) error in panorama texels, away from the seams and the poles; blue in both
    levels (roughness 0 and 1) and the Lambertian cube of L ≡ 1 (the availability probe's own job) are the furnace:
    max |C − 1|."""
    h, w = MARKED_SHAPE
    dirs = latlong.texel_directions(h, w).reshape(-1, 3)
    theta, phi = latlong.direction_to_spherical(dirs)
    marked = np.stack([phi / (2 * np.pi), theta / np.pi, np.ones_like(phi)], -1).reshape(h, w, 3).astype(np.float32)
    out = khronos_ibl.run_sampler(marked, khronos_ibl.Options("GGX", 16, 32, 0.0, 2))
    cube = im.CubeMap(out.levels[0])
    test = latlong.fibonacci_sphere(2000)
    t, p = latlong.direction_to_spherical(test)
    u, v = p / (2 * np.pi), t / np.pi
    keep = (u > 0.1) & (u < 0.9) & (v > 0.1) & (v < 0.9)  # away from the tool's and the suite's seams, the poles
    orient = {}
    for label, m in (("rotation", khronos_ibl.SUITE_TO_CUBE), ("mirrored", khronos_ibl.SUITE_TO_CUBE * MIRROR)):
        got = cube.lookup_numpy(test[keep] @ m.T)
        orient[f"{label}_u_texels"] = float(np.max(np.abs(got[:, 0] - u[keep])) * w)
        orient[f"{label}_v_texels"] = float(np.max(np.abs(got[:, 1] - v[keep])) * h)
    ones = np.ones(khronos_ibl.FURNACE_SHAPE + (3,), np.float32)
    lam = khronos_ibl.run_sampler(ones, khronos_ibl.FURNACE_OPTIONS)
    furnace = {"lambertian_max_deviation": float(np.max(np.abs(lam.levels[0] - 1.0))),
               "ggx_max_deviation": float(max(np.max(np.abs(lv[..., 2] - 1.0)) for lv in out.levels)),
               "ggx_levels": len(out.levels)}
    return orient, furnace


def flux_stats(e_ref: np.ndarray, e: np.ndarray, flux: np.ndarray, unc: np.ndarray) -> dict[str, float]:
    s = irradiance_errors(e_ref, e, flux, unc)["flux_luminance"]
    return {"mean": s.mean, "max": s.max, "mean_uncertainty": s.mean_uncertainty, "max_uncertainty": s.max_uncertainty}


def paper_probes(ctx: Context) -> list[Any]:
    """The paper's probes (R&H 2001's table, ``probe_aliases.csv``) among the run's environments."""
    stems = set(read_aliases())
    envs, _ = ctx.environments()
    return [e for e in envs if e.kind == "probe" and e.source is not None and e.source.stem in stems]


def probe_errors(env: Any, normals: np.ndarray) -> dict[str, Any]:
    ref = reference_irradiance(env, normals)
    flux = env.total_flux()
    e_tool = irradiance.call(irradiance[TECH], env.radiance, np.concatenate([normals, normals * MIRROR]))
    k = len(normals)
    cube = im.compute_irradiance_cube(env.radiance, FACE, needed=normals)
    return {"flux_luminance": float(latlong.luminance(flux)), "resolution": [env.width, env.height],
            TECH: flux_stats(ref.irradiance, e_tool[:k], flux, ref.uncertainty),
            "mirrored": flux_stats(ref.irradiance, e_tool[k:], flux, ref.uncertainty),
            "sh9": flux_stats(ref.irradiance, irradiance.call("sh9", env.radiance, normals), flux, ref.uncertainty),
            f"cube {FACE}²": flux_stats(ref.irradiance, cube.lookup(normals), flux, ref.uncertainty)}


def sweep(env: Any, normals: np.ndarray, st: Settings) -> dict[str, Any]:
    """flux_luminance mean / max with one knob changed at a time (the others the technique's)."""
    ref = reference_irradiance(env, normals)
    flux = env.total_flux()
    base = lambertian_options()
    rows = []
    points = ([("sampleCount", s, lambertian_options(sample_count=s)) for s in st.khronos_samples]
              + [("cubeMapResolution", f, lambertian_options(face=f or None)) for f in st.khronos_faces]
              + [("lodBias", b, lambertian_options(lod_bias=b)) for b in st.khronos_lod_biases])
    for knob, value, opts in points:
        e = lambertian_irradiance(env.radiance, normals, opts)
        rows.append({"knob": knob, "value": value, "default": opts == base,
                     **flux_stats(ref.irradiance, e, flux, ref.uncertainty)})
    return {"environment": env.name, "rows": rows}


def specular_rows(spec_run: Any) -> dict[str, dict[str, Any]]:
    """Relative error (mean, p95, bias ± σ) per GGX conductor case of the tool and of ``split_sum_ggx``."""
    out: dict[str, dict[str, Any]] = {}
    for name in (SPEC_TECH, "split_sum_ggx"):
        for key, c in spec_run.comparisons.get(name, {}).items():
            if key.startswith("ggx_") and not key.startswith("ggx_plastic"):
                s = c.rel.stats
                out.setdefault(name, {})[key] = {"alpha": float(key.removeprefix("ggx_")), "mean": s.mean,
                                                 "mean_uncertainty": s.mean_uncertainty, "p95": s.p95,
                                                 "bias": s.bias, "bias_uncertainty": s.bias_uncertainty}
    return out


def compute_khronos(ctx: Context, st: Settings, spec_run: Any) -> KhronosMeasurements:
    version = khronos_ibl.version()
    why = irradiance[TECH].meta["unavailable"]()
    if why is not None:
        return KhronosMeasurements(version, NotRun(f"glTF-IBL-Sampler techniques ({TECH}, {SPEC_TECH})", why,
                                                   khronos_ibl.FIX))
    normals = latlong.fibonacci_sphere(st.khronos_normals)
    probes = paper_probes(ctx)
    orient, furn = orientation_and_furnace()
    m = KhronosMeasurements(version, furnace=furn, orientation=orient, specular=specular_rows(spec_run))
    for env in ctx.progress(probes, "ibl: glTF-IBL-Sampler on the paper's probes"):
        m.probes[env.name] = probe_errors(env, normals)
    if probes:
        m.sweep = sweep(probes[0], normals, st)
    return m
