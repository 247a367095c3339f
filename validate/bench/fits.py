"""The fits in ``python -m validate bench`` (section ``fits``): each scipy fit beside its drjit-AD twin.

Same data and same starting points both ways; times are the best of ``repeats`` runs after one warm-up each
(drjit's kernel compilation excluded), the two run alternately (:func:`validate.bench.timing.best_pair`). Residuals:

* LTC entry (:func:`~validate.local_models.specular_arealight.ltc.fit_entry_scipy`, Nelder–Mead, vs
  :func:`~validate.local_models.specular_arealight.ltc.fit_entry_ad`, L-BFGS-B): ∫ |E·D − f cos|³ dω, on
  entries of the shipped table, each started from its rougher neighbour's stored parameters (as
  scripts/fit_ltc.py does);
* überlight barn door (:func:`~validate.experiments.uberlight.compute.fit_beam`, trust-region least squares
  with the finite-difference vs the AD Jacobian): the RMS of (L_model − L_ref)/peak, on the quick settings'
  barn-door renders;
* spot exponent and lamp fits (:mod:`validate.experiments.lights.sweeps`): the rms of the profile fit.

``AD / scipy residual − 1`` is the relative excess of the AD residual; a fit counts as matched where it is
≤ :data:`RESIDUAL_TOL`.
"""

from __future__ import annotations

import dataclasses
import importlib
from collections.abc import Callable
from typing import Any

import numpy as np

from .timing import best_pair

RESIDUAL_TOL = 1e-6  # relative; both fits stop on their own tolerances, rounding of the sums is ~1e-13
# (i_r, j_θ) of the 24 × 24 table; (0, 4) and (0, 13): α = 10⁻³, where the two land apart (either way)
LTC_ENTRIES = ((23, 0), (23, 5), (20, 6), (14, 12), (8, 20), (5, 23), (2, 10), (0, 4), (0, 13))
BARNDOORS = ((0.025, 0.0), (0.025, 0.6))  # (disc radius m, hole roundness), the quick settings' renders


def _row(name: str, data: str, scipy_fit: Callable[[], Any], ad_fit: Callable[[], Any],
         residual: Callable[[Any], float], repeats: int, used: str, residual_unit: str = "–") -> dict[str, Any]:
    """Both fits timed and their residuals (in ``residual_unit``: "–" for an rms relative to the peak)."""

    t_scipy, t_ad = best_pair(scipy_fit, ad_fit, repeats=repeats)
    r_scipy, r_ad = residual(scipy_fit()), residual(ad_fit())
    return {"fit": name, "data": data, "scipy_s": t_scipy, "scipy_residual": r_scipy, "ad_s": t_ad,
            "ad_residual": r_ad, "time_ratio": t_ad / t_scipy,
            "residual_ratio": r_ad / r_scipy if r_scipy > 0 else float("nan"),
            "matched": bool(r_ad <= r_scipy * (1.0 + RESIDUAL_TOL)), "experiment_uses": used,
            "residual_unit": residual_unit}


def ltc_rows(repeats: int) -> list[dict[str, Any]]:
    from ..local_models.specular_arealight import ltc

    t = ltc.load_table()
    r, mus = ltc.table_axes(t.size)
    rows = []
    for i, j in LTC_ENTRIES:
        init = tuple(t.params[i + 1, j]) if i + 1 < t.size else None
        prob = ltc.fit_problem(float(mus[j]), ltc.alpha_of(float(r[i])), init)

        def l3(e: Any, prob: Any = prob) -> float:
            return prob.l3_error(np.asarray(e.params[:1] if prob.iso else e.params))
        rows.append(_row("LTC entry (L³ error)", f"r = {r[i]:.3f}, cos θ_v = {mus[j]:.3f}",
                         lambda p=prob: ltc.fit_entry_scipy(p), lambda p=prob: ltc.fit_entry_ad(p), l3, repeats,
                         "scipy (the shipped table)", "sr⁻²"))  # D and f cos in sr⁻¹, cubed, times dω
    return rows


def uberlight_rows(repeats: int) -> list[dict[str, Any]]:
    from ..experiments import uberlight as exp
    from ..reference import uberlight_render as ur

    um = importlib.import_module("validate.experiments.uberlight.compute")
    s = dataclasses.replace(exp.QUICK, barndoors=BARNDOORS)
    rows = []
    for radius, roundness in BARNDOORS:
        sc = um.barndoor(s, radius, roundness)
        frame = um.Frame(sc, ur.render(sc, None, s.barndoor_spp, s.barndoor_passes, s.seed), shadowed=False)
        rows.append(_row("überlight barn door (RMS)", f"{um.config_key(sc)}, {len(frame.radiance)} px",
                         lambda f=frame: um.fit_beam(f, "scipy"), lambda f=frame: um.fit_beam(f, "ad"),
                         lambda fit: fit["rms_residual"], repeats, "ad"))
    return rows


def lights_rows(repeats: int) -> list[dict[str, Any]]:
    from ..experiments.lights import sweeps as sw
    from ..scenes import light_scenes as ls

    spot, lamp = ls.STANDARD_LIGHTS["spot"], ls.STANDARD_LIGHTS["lamp"]
    rows = [_row("spot exponent (rms)", f"beam {spot.beam_deg:g}°, cutoff {spot.cutoff_deg:g}°",
                 lambda: sw.fit_spot_exponent(spot.beam_deg, spot.cutoff_deg, method="scipy"),
                 lambda: sw.fit_spot_exponent(spot.beam_deg, spot.cutoff_deg, method="ad"),
                 lambda fit: fit[1], repeats, "ad")]
    prob = sw.lamp_problem(*lamp.size)
    for part, key, which, used in (("cos^f", "cos_f_rms", (True, False), "ad"),
                                   ("Mitsuba spot", "mitsuba_rms", (False, True), "scipy")):
        rows.append(_row(f"lamp {part} (rms)", "r, h, a = " + ", ".join(f"{v:g}" for v in lamp.size),
                         lambda w=which: sw.fit_lamp_scipy(prob, w), lambda w=which: sw.fit_lamp_ad(prob, w),
                         lambda fit, k=key: fit[k], repeats, used))
    return rows


def fit_rows(repeats: int = 3, log: Callable[[str], None] = print) -> list[dict[str, Any]]:
    """Every fit both ways (module docstring)."""
    from ..numerics import adfit

    if not adfit.available():
        return [{"fit": "all", "skipped": "the active variant has no AD"}]
    rows = []
    for label, fn in (("LTC", ltc_rows), ("überlight", uberlight_rows), ("lights", lights_rows)):
        log(f"  fits: {label} ...")
        rows += fn(repeats)
    return rows


def tables(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    out = [[r["fit"], r["data"], r.get("residual_unit", "–"), round(r["scipy_s"] * 1e3, 1),
            f"{r['scipy_residual']:.9g}", round(r["ad_s"] * 1e3, 1), f"{r['ad_residual']:.9g}",
            round(r["time_ratio"], 2),
            f"{r['residual_ratio'] - 1.0:+.1e}", "yes" if r["matched"] else "no", r["experiment_uses"]]
           for r in rows if "skipped" not in r]
    out += [[r["fit"], r["skipped"]] + [None] * 9 for r in rows if "skipped" in r]
    return [{"caption": f"Fits: scipy vs drjit AD, same data and start (ms: best of 3 after a warm-up; matched: "
                        f"AD residual ≤ scipy × (1 + {RESIDUAL_TOL:g}))",
             "headers": ["fit", "data", "unit", "scipy (ms)", "scipy residual (unit)", "AD (ms)", "AD residual (unit)",
                         "AD / scipy time (×)", "AD / scipy residual − 1 (–)", "matched?", "experiment uses"],
             "rows": out}]
