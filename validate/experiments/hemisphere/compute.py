"""Experiment ``hemisphere``: hemisphere lighting (sky/ground blend) and every irradiance technique under
the skies hemisphere lighting is meant for, against Mitsuba.

Two blend weights (:mod:`validate.local_models.irradiance.hemisphere`), as functions of the tilt β of the
normal from up (cos β = N·U):  f = ½(1 + cos β)  and the Red Book's  a = 1 − ½ sin β (β ≤ 90°),
½ sin β (β > 90°).

* Two-tone sky (:func:`validate.scenes.procedural.two_tone`; L_s, L_g its sky and ground radiance):
  f·π is the exact irradiance (view factor (1 + cos β)/2, Cohen & Wallace 1993 §4 [2]). Checked against
  (1) Mitsuba's ``irradiancemeter`` (Student-t/Šidák test) and (2) the deterministic quadrature of
  Mitsuba's radiance (per-normal relative error |E′ − E| / E in luminance). The Red Book weight's error
  is predicted analytically, (a − f)(Y_s − Y_g) / (f Y_s + (1 − f) Y_g), and the quadrature must find it.
* ``sunsky`` (sky + sun, 3 sun elevations): neither formula is exact. C_sky = E(up)/π and
  C_ground = E(down)/π from the reference, so both are exact at β = 0° and 180°; the error at tilt β
  is the maximum over azimuths of |E′ − E| / max_n E (luminance, peak-normalised: E facing the dark
  ground is close to 0).
* Every registered ``irradiance`` technique (the two hemisphere techniques, whose colours are E(±U)/π of
  the map, SH of order 1/2/4, plug-ins) is measured on the same skies with the metrics of
  :mod:`validate.metrics.irradiance_error` over the tilt × azimuth normals: a row, a results.json entry,
  a claim per declared threshold.

References
  [1] The seed's hemisphere-lighting formulas; the Red Book's piecewise sine called "the actual analytic
      function".
  [2] M. F. Cohen, J. R. Wallace, *Radiosity and Realistic Image Synthesis*, 1993, §4 (Nusselt analog).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...local_models import irradiance
from ...local_models.irradiance import hemisphere as hm
from ...metrics.irradiance_error import METRIC_NAMES, irradiance_errors
from ...reference import area_irradiance as ai
from ...reference.irradiance import reference_irradiance
from ...scenes import area_lights, latlong, procedural
from ...scenes.environment import Environment
from ..base import Context, settings_json
from ..techniques import Measured
from .settings import Settings

UP = np.array([0.0, 1.0, 0.0])
EXACT_TOLERANCE = 1e-3  # the reference quadrature's agreement with closed forms (README: constant, two-tone,
#                         band-limited within 0.1 %; measured ≤ 4e-4 of the peak irradiance)
BIAS = 0.01  # the reference-bias power check: a 1 % scale error of the prediction or of the reference
ALPHA = ai.DEFAULT_ALPHA


def tilt_normals(betas_deg: np.ndarray, azimuths: int) -> np.ndarray:
    """Normals at tilt β from +y and azimuth φ_k = 2πk/K (φ = 0 towards −z, Mitsuba's lat-long φ); (B, K, 3)."""
    phi = np.arange(azimuths) * (2 * np.pi / azimuths)
    bb, pp = np.meshgrid(np.radians(betas_deg), phi, indexing="ij")
    return latlong.spherical_to_direction(bb, pp)


def _y(rgb: np.ndarray) -> np.ndarray:
    return latlong.luminance(np.asarray(rgb))


# -- compute -----------------------------------------------------------------------------------------
def weight_curves(betas_deg: np.ndarray) -> dict:
    """Both weights and their difference on a β grid, and the measured worst angle."""
    c = np.cos(np.radians(betas_deg))
    f, a = hm.blend_weight(c, "exact"), hm.blend_weight(c, "red_book")
    k = int(np.argmax(np.abs(a - f)))
    return {"beta_deg": betas_deg.tolist(), "exact": f.tolist(), "red_book": a.tolist(),
            "worst_beta_deg": float(betas_deg[k]), "worst_abs_weight_difference": float(abs(a[k] - f[k]))}


def red_book_prediction(betas_deg: np.ndarray, swapped: bool = False) -> np.ndarray:
    """Relative luminance error of the Red Book weight under the two-tone sky, analytically:
    |a − f| |Y_s − Y_g| / (f Y_s + (1 − f) Y_g) (``swapped``: a with its two branches exchanged)."""
    c = np.cos(np.radians(betas_deg))
    f = 0.5 * (1 + c)
    s = np.sqrt(np.maximum(1 - c * c, 0.0))
    a = np.where((c >= 0) != swapped, 1 - 0.5 * s, 0.5 * s)
    ys, yg = float(_y(procedural.SKY)), float(_y(procedural.GROUND))
    return np.abs(a - f) * abs(ys - yg) / (f * ys + (1 - f) * yg)


def two_tone_analysis(env: Environment, ctx: Context, s: Settings) -> dict:
    """Both formulas vs the quadrature reference (all β) and vs the irradiance meter (a subset)."""
    betas = np.arange(0.0, 180.0 + 1e-9, s.beta_step_deg)
    normals = area_lights.tilted_normals(betas, UP, [1.0, 0.0, 0.0])
    ref = reference_irradiance(env, normals, cells=s.cells)
    e_ref, unc = _y(ref.irradiance), _y(ref.uncertainty)
    out: dict = {"beta_deg": betas.tolist(), "reference_cells": 2 * s.cells, "formulas": {},
                 "red_book_predicted": red_book_prediction(betas).tolist()}
    for formula in hm.FORMULAS:
        e = _y(hm.hemisphere_irradiance(normals, procedural.SKY, procedural.GROUND, UP, formula))
        rel = np.abs(e - e_ref) / e_ref
        k = int(np.argmax(rel))
        out["formulas"][formula] = {"relative_error": rel.tolist(), "max_relative_error": float(rel[k]),
                                    "worst_beta_deg": float(betas[k]), "uncertainty": float(np.max(unc / e_ref)),
                                    "max_relative_error_biased_reference": float(np.max(np.abs(e - e_ref * (1 + BIAS))
                                                                                        / (e_ref * (1 + BIAS))))}
    rb = out["formulas"]["red_book"]
    rel_rb = np.asarray(rb["relative_error"])
    rb["deviation_from_prediction"] = float(np.max(np.abs(rel_rb - red_book_prediction(betas))))
    rb["swapped_deviation"] = float(np.max(np.abs(np.asarray(rb["relative_error"])
                                                  - red_book_prediction(betas, swapped=True))))
    out["meter"] = meter_analysis(env, ctx, s)
    return out


def meter_analysis(env: Environment, ctx: Context, s: Settings) -> dict:
    """Mitsuba's irradiance meter (first, red, channel; the sky's radiance maximum bounds a sample) against
    both formulas and against the exact one scaled by 1 + BIAS (the power check)."""
    mb = np.asarray(s.meter_betas_deg, dtype=np.float64)
    mn = area_lights.tilted_normals(mb, UP, [1.0, 0.0, 0.0])
    meas = ai.measure_irradiance(area_lights.sky(env, s.meter_film), mn, spp=s.meter_spp,
                                 passes=s.meter_passes, seed=ctx.seed % 2048)
    lmax = float(env.radiance.max())
    out: dict = {"beta_deg": mb.tolist(), **meas.to_json(), "tests": {}}
    for formula in hm.FORMULAS:
        pred = hm.hemisphere_irradiance(mn, procedural.SKY, procedural.GROUND, UP, formula)[:, 0]
        out["tests"][formula] = {**ai.compare(meas, pred, lmax).to_json(), "predicted": pred.tolist()}
    exact = np.asarray(out["tests"]["exact"]["predicted"])
    out["tests"]["exact_biased"] = ai.compare(meas, exact * (1 + BIAS), lmax).to_json()
    return out


def sky_analysis(env: Environment, s: Settings) -> dict:
    """On the tilt × azimuth normals: both formulas calibrated at the poles (error vs β, peak-normalised) and
    every registered irradiance technique under the metrics of :mod:`validate.metrics.irradiance_error`."""
    betas = np.arange(0.0, 180.0 + 1e-9, s.beta_step_deg)
    nb = tilt_normals(betas, s.azimuths)
    ref = reference_irradiance(env, np.concatenate([nb.reshape(-1, 3), np.array([UP, -UP])]), cells=s.cells)
    e_ref, unc = ref.irradiance[:-2], ref.uncertainty[:-2]
    c_sky, c_ground = ref.irradiance[-2] / np.pi, ref.irradiance[-1] / np.pi
    peak = float(_y(e_ref).max())
    out: dict = {"beta_deg": betas.tolist(), "peak_irradiance_luminance": peak, "sky_colour": c_sky.tolist(),
                 "ground_colour": c_ground.tolist(), "convergence": ref.convergence, "formulas": {},
                 "techniques": {}}
    for formula in hm.FORMULAS:
        e = hm.hemisphere_irradiance(nb.reshape(-1, 3), c_sky, c_ground, UP, formula)
        err = (np.abs(_y(e) - _y(e_ref)) / peak).reshape(nb.shape[:2])
        out["formulas"][formula] = {"max_over_azimuth": err.max(axis=1).tolist(),
                                    "mean_over_azimuth": err.mean(axis=1).tolist(),
                                    "max": float(err.max()), "mean": float(err.mean()),
                                    "worst_beta_deg": float(betas[int(np.argmax(err.max(axis=1)))]),
                                    "uncertainty": float(_y(unc).max() / peak)}
    out["poles"] = pole_check(env, ref.irradiance[-2:], ref.uncertainty[-2:])
    flux = env.total_flux()
    for tech in irradiance:
        e = irradiance.call(tech, env.radiance, nb.reshape(-1, 3))
        out["techniques"][tech.name] = {k: v.to_json() for k, v in irradiance_errors(e_ref, e, flux, unc).items()}
    return out


def pole_check(env: Environment, e_poles: np.ndarray, unc_poles: np.ndarray) -> dict[str, float]:
    """The registered ``hemisphere`` technique at the zenith and nadir against the reference, relative to the
    zenith irradiance (luminance); and the same with colours taken as each hemisphere's *mean* radiance
    (solid-angle weighted, no cosine) — the power check: a plausible calibration bug."""
    e = irradiance.call("hemisphere", env.radiance, np.array([UP, -UP]))
    h, w = env.radiance.shape[:2]
    up = latlong.spherical_to_direction(latlong.row_theta(h), np.zeros(h))[:, 1] > 0  # rows above the horizon
    flux_rows, omega_rows = latlong.row_sums(env.radiance) * latlong.row_solid_angles(h, w)[:, None], \
        latlong.row_solid_angles(h, w) * w
    mean = [flux_rows[m].sum(axis=0) / omega_rows[m].sum() for m in (up, ~up)]
    z = float(_y(e_poles[0]))
    return {"deviation": float(np.max(np.abs(_y(e) - _y(e_poles))) / z), "uncertainty": float(_y(unc_poles).max() / z),
            "mean_radiance_deviation": float(np.max(np.abs(_y(np.pi * np.array(mean)) - _y(e_poles))) / z)}


def compute(ctx: Context, s: Settings) -> dict[str, Any]:
    """Every number of the experiment (JSON-able)."""
    envs, _ = ctx.environments()
    by_name = {e.name: e for e in envs}
    two_tone = by_name.get("two_tone") or procedural.two_tone()
    suns = [by_name[f"sunsky_{e:g}deg"] for e in procedural.SUN_ELEVATIONS_DEG if f"sunsky_{e:g}deg" in by_name]
    skies = [two_tone, *suns]
    return {"settings": settings_json(s), "weights": weight_curves(np.arange(0.0, 180.0 + 1e-9, 0.25)),
            "two_tone": two_tone_analysis(two_tone, ctx, s),
            "skies": dict(zip([e.name for e in skies], ctx.map(lambda env: sky_analysis(env, s), skies,
                                                               "hemisphere: skies"), strict=True))}


def technique_measured(m: dict[str, Any], name: str, skies: list[str] | None = None) -> dict[str, Measured]:
    """Worst over ``skies`` (default all) of every metric's mean, max and rms ± uncertainty (rms: the max
    uncertainty, since |rms(e′) − rms(e)| ≤ max δ); power 'error × 1.5'."""
    out: dict[str, Measured] = {}
    chosen = [m["skies"][k] for k in (skies if skies is not None else m["skies"])]
    for metric in METRIC_NAMES:
        for stat in ("mean", "max", "rms"):
            unc = "max_uncertainty" if stat == "rms" else f"{stat}_uncertainty"
            vals = [(sky["techniques"][name][metric][stat], sky["techniques"][name][metric][unc])
                    for sky in chosen if name in sky["techniques"]]
            if vals:
                v, u = max(vals)
                out[f"{metric}.{stat}"] = Measured(v, u, 1.5 * v, "error × 1.5", unit="%", stat=stat)
    return out




