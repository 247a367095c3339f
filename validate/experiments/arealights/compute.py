"""Numbers of the ``arealights`` experiment (no claims, no prose): every function returns JSON-able data.

Receivers and lights (unit radius r = 1, unit radiance; the light's centre at the origin, the receiver at
(0, 0, d), so the direction to the light is −z; receiver normals turned by θ ∈ [0°, 180°] towards +x):

* ``sphere`` of radius r at distance d — the cap sin σ = r/d seen from any receiver;
* ``disc`` of radius r facing the receiver on its axis — the cap tan σ = r/d.

Error of a technique E′ against the exact cap irradiance E (validated against Mitsuba first), per scene:
``flux`` = |E′ − E| / Φ with Φ = L · 2π(1 − cos σ) the flux of the cap (R&H's normalisation, under which
order-2 SH tends to 3/32 for a point-like light), ``peak`` = |E′ − E| / E(0) (the irradiance at normal
incidence, the largest); each as mean and max over the θ grid (uniform in θ). Against Mitsuba's meter:
``mitsuba_flux`` = max over the meter's normals of |E′ − m_n| / Φ, with the bound of :func:`meter_bounds`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from scipy.optimize import brentq

from ...backend import float_type
from ...local_models import arealight
from ...local_models.arealight import disc_sh, point_light, sphere_cap
from ...local_models.irradiance import sh as shm
from ...local_models.registry import Technique
from ...reference import area_irradiance as ai
from ...scenes import area_lights, procedural
from ...stats import sidak_alpha, sidak_critical
from ..base import Context, settings_json
from .settings import Settings
from .specular.compute import compute as specular_compute

ORDERS = (2, 4, 8)
ALPHA = ai.DEFAULT_ALPHA  # family-wise significance level of every Mitsuba decision
CAP_QUADRATURE_TOLERANCE = 1e-5  # float32 closed form vs float64 quadrature, relative to π sin²σ;
#                                   measured 8.8e-7 over sin²σ ∈ {0.01 … 0.9} (float32 rounding, 11× margin)
X_AXIS = np.array([1.0, 0.0, 0.0])


# -- scenes ------------------------------------------------------------------------------------------
def light_mapping(shape: str, distance: float, radius: float = 1.0) -> dict[str, Any]:
    """The ``arealight`` family's light mapping for the scenes of :mod:`validate.scenes.area_lights`."""
    return {"shape": shape, "center": (0.0, 0.0, 0.0), "normal": (0.0, 0.0, 1.0), "radius": radius,
            "radiance": 1.0}


def scene_table(alpha20_deg: float) -> dict[str, dict[str, Any]]:
    """The three closed-form/Mitsuba scenes: name → shape, distance, sin²σ."""
    d20 = 1.0 / math.sin(math.radians(alpha20_deg))
    out = {}
    for name, shape, d in (("sphere_r1_d2", "sphere", 2.0), (f"sphere_alpha{alpha20_deg:g}", "sphere", d20),
                           ("disc_r1_d2", "disc", 2.0)):
        s2 = sphere_cap.sin2_sigma_sphere(1.0, d) if shape == "sphere" else sphere_cap.sin2_sigma_disc(1.0, d)
        out[name] = {"shape": shape, "distance": d, "sin2_sigma": s2,
                     "sigma_deg": math.degrees(math.asin(math.sqrt(s2)))}
    return out


def meter_scene(sc: dict[str, Any], film: int) -> area_lights.MeterScene:
    make = area_lights.sphere_light if sc["shape"] == "sphere" else area_lights.disc_light
    return make(1.0, sc["distance"], film_size=film)


def receivers(distance: float, thetas_deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(points, normals) of the receiver at (0, 0, d) turned by θ from the light (−z) towards +x."""
    n = area_lights.tilted_normals(np.asarray(thetas_deg, dtype=np.float64), np.array([0.0, 0.0, -1.0]), X_AXIS)
    return np.tile([0.0, 0.0, float(distance)], (len(n), 1)), n


def cap_flux(sin2_sigma: float, radiance: float = 1.0) -> float:
    """Φ = L · 2π(1 − cos σ) = L · 4π sin²(σ/2): the flux ∫_cap L dω of the cap."""
    return radiance * 4 * math.pi * math.sin(0.5 * math.asin(math.sqrt(sin2_sigma))) ** 2


def supports(tech: Technique, shape: str) -> bool:
    """A technique declares the shapes it handles as meta ``shapes``; undeclared means every shape."""
    return shape in tuple(tech.meta.get("shapes", ("disc", "sphere", "rectangle")))


# -- Mitsuba decisions -------------------------------------------------------------------------------
def meter_bounds(meas: ai.MeterIrradiance, alpha: float = ALPHA, radiance_max: float = 1.0) -> np.ndarray:
    """Per-normal half-width h_n with |m_n − E_true,n| < h_n for all n jointly at family-wise level α.

    Normals where some sample hit the light: h = z*·s (Šidák z* over the N normals). Normals where no
    sample hit it (s = 0): N_s samples of weight π L_max all missing has probability (1 − E/(πL_max))^N_s ≤
    exp(−N_s E/(π L_max)), so E ≥ π L_max ln(1/α₁)/N_s is rejected at level α₁ (the Šidák per-normal level)."""
    m = meas.mean.size
    z = sidak_critical(m, alpha)
    zero_hit = math.pi * radiance_max * math.log(1.0 / sidak_alpha(alpha, m)) / meas.samples
    return np.where(meas.stderr > 0, z * meas.stderr, zero_hit)


def measure_meter(sc: dict[str, Any], thetas_deg: list[float], spp: int, passes: int, film: int,
                  seed: int) -> tuple[area_lights.MeterScene, np.ndarray, ai.MeterIrradiance]:
    meter = meter_scene(sc, film)
    normals = area_lights.tilted_normals(np.asarray(thetas_deg, dtype=np.float64), meter.light_direction, X_AXIS)
    return meter, normals, ai.measure_irradiance(meter, normals, spp=spp, passes=passes, seed=seed)


def reference_check(name: str, sc: dict[str, Any], s: Settings, seed: int) -> dict[str, Any]:
    """Mitsuba's meter vs the closed-form cap; the unclipped form and a 2 % scale error must be rejected."""
    meter, normals, meas = measure_meter(sc, s.meter_thetas_deg, s.meter_spp, s.meter_passes,
                                         s.meter_film, seed)
    cos_t = normals @ meter.light_direction
    closed = sphere_cap.cap_irradiance(cos_t, sc["sin2_sigma"])
    unclipped = sphere_cap.cap_irradiance_unclipped(cos_t, sc["sin2_sigma"])
    return {"name": name, "sin2_sigma": sc["sin2_sigma"], "sigma_deg": sc["sigma_deg"],
            "theta_deg": list(s.meter_thetas_deg), **meas.to_json(), "closed_form": closed.tolist(),
            "unclipped": unclipped.tolist(), "bounds": meter_bounds(meas).tolist(),
            "closed_test": ai.compare(meas, closed, 1.0).to_json(),
            "unclipped_test": ai.compare(meas, unclipped, 1.0).to_json(),
            "scaled_test": ai.compare(meas, closed * (1 + s.scale_error), 1.0).to_json()}


def mitsuba_error(tech: Technique, sc: dict[str, Any], check: dict[str, Any]) -> dict[str, float]:
    """max_n |E′ − m_n| / Φ over the meter normals, and its upper bound max_n (|E′ − m_n| + h_n) / Φ."""
    pts, nrm = receivers(sc["distance"], np.asarray(check["theta_deg"]))
    e = arealight.call(tech, light_mapping(sc["shape"], sc["distance"]), pts, nrm)
    dev = np.abs(e - np.asarray(check["mean"]))
    phi = cap_flux(sc["sin2_sigma"])
    value = float(dev.max() / phi)
    return {"value": value, "uncertainty": float((dev + np.asarray(check["bounds"])).max() / phi) - value}


def decide_alpha(alpha_deg: float, s: Settings, seed: int) -> dict[str, Any]:
    """Order-2 SH of a sphere light with sin α = r/d against a long Mitsuba run: the upper bound
    max_n (|E_2 − m_n| + h_n)/Φ and lower bound max_n (|E_2 − m_n| − h_n)/Φ of max_n |E_2 − E_true|/Φ."""
    sc = {"shape": "sphere", "distance": 1.0 / math.sin(math.radians(alpha_deg)),
          "sin2_sigma": math.sin(math.radians(alpha_deg)) ** 2, "sigma_deg": alpha_deg}
    d = s.decide
    _, _, meas = measure_meter(sc, d.thetas_deg, d.spp, d.passes, s.meter_film, seed)
    return decision(sc, d.thetas_deg, meas)


def decision(sc: dict[str, Any], thetas_deg: list[float], meas: ai.MeterIrradiance) -> dict[str, Any]:
    """Bounds on the order-2 error max_n |E_2 − E_true| / Φ from one meter measurement (see decide_alpha)."""
    pts, nrm = receivers(sc["distance"], np.asarray(thetas_deg))
    e2 = arealight.call("sh_order2", light_mapping(sc["shape"], sc["distance"]), pts, nrm)
    dev = np.abs(e2 - meas.mean)
    h = meter_bounds(meas)
    phi = cap_flux(sc["sin2_sigma"])
    return {"alpha_deg": sc["sigma_deg"], "theta_deg": list(thetas_deg), "value": float(dev.max() / phi),
            "upper": float((dev + h).max() / phi), "lower": float((dev - h).max() / phi),
            "samples_per_normal": meas.samples, "mean": meas.mean.tolist(), "bound": h.tolist()}


# -- closed-form sweeps ------------------------------------------------------------------------------
def cap_quadrature_check(cos_t: np.ndarray, unclipped: bool = False) -> float:
    """max |closed form (float32 drjit) − quadrature (float64)| / (π sin²σ) over a few σ and all θ
    (``unclipped``: the horizon clamp dropped, π sin²σ max(cos θ, 0) — the power check)."""
    worst = 0.0
    for s2 in (0.01, 0.1, 0.25, 0.5, 0.9):
        e = (sphere_cap.cap_irradiance_unclipped if unclipped else sphere_cap.cap_irradiance)(cos_t, s2)
        q = sphere_cap.cap_irradiance_quadrature(cos_t, s2, nodes=64)  # converged to ~1e-11 (vs 256 nodes)
        worst = max(worst, float(np.max(np.abs(e - q)) / (math.pi * s2)))
    return worst


def technique_errors(tech: Technique, sc: dict[str, Any], thetas_deg: np.ndarray) -> dict[str, float]:
    """flux/peak mean and max of one technique on one scene against the closed-form cap (dense θ)."""
    pts, nrm = receivers(sc["distance"], thetas_deg)
    e = arealight.call(tech, light_mapping(sc["shape"], sc["distance"]), pts, nrm)
    exact = sphere_cap.cap_irradiance(np.cos(np.radians(thetas_deg)), sc["sin2_sigma"])
    dev = np.abs(e - exact)
    phi, peak = cap_flux(sc["sin2_sigma"]), float(exact[0])
    unc = CAP_QUADRATURE_TOLERANCE * math.pi * sc["sin2_sigma"]
    return {"flux.max": float(dev.max() / phi), "flux.mean": float(dev.mean() / phi),
            "peak.max": float(dev.max() / peak), "peak.mean": float(dev.mean() / peak),
            "flux.uncertainty": unc / phi, "peak.uncertainty": unc / peak, "theta_worst_deg":
            float(thetas_deg[int(np.argmax(dev))])}


def sphere_alpha_error(tech: Technique | str, alpha_deg: float, thetas_deg: np.ndarray) -> float:
    """max_θ |E′ − E| / Φ of a unit sphere light with sin α = r/d (α in degrees)."""
    a = math.radians(alpha_deg)
    sc = {"shape": "sphere", "distance": 1.0 / math.sin(a), "sin2_sigma": math.sin(a) ** 2}
    t = arealight[tech] if isinstance(tech, str) else tech
    return technique_errors(t, sc, thetas_deg)["flux.max"]


def alpha_crossing(fn: Callable[[float], float], alphas: np.ndarray, errs: np.ndarray, level: float) -> float | None:
    """The largest α at which ``fn(α)`` falls through ``level`` (≥ level just below it), by Brent's method
    between the bracketing grid points; None if the grid shows no such crossing."""
    above = np.asarray(errs) >= level
    idx = [i for i in range(len(alphas) - 1) if above[i] and not above[i + 1]]
    if not idx:
        return None
    i = idx[-1]
    return float(brentq(lambda a: fn(a) - level, alphas[i], alphas[i + 1], xtol=ALPHA_XTOL_DEG))


def seed_check(s: Settings, alpha20_deg: float) -> dict:
    """The seed's order-2 formulas vs a numerical projection (quadrature over the cap), and the same
    comparison with the l = 2 band's sign flipped (the power check)."""
    dev, unc, flipped = 0.0, 0.0, 0.0
    rows = []
    for a_deg in s.alphas_deg:
        a = math.radians(a_deg)
        num = disc_sh.project_cap_numerical(a, np.array([0.0, 0.0, 1.0]), 2, s.projection_nodes)
        num2 = disc_sh.project_cap_numerical(a, np.array([0.0, 0.0, 1.0]), 2, 2 * s.projection_nodes)
        zon = num[[shm.sh_index(l, 0) for l in range(3)]]
        seed = disc_sh.seed_zonal_order2(a)
        # irradiance polynomial from the numerical projection: k_l = A_l L_l0 √((2l+1)/4π) × (1, 1, ½)
        k_num = np.array([shm.clamped_cosine_al(l) * zon[l] * math.sqrt((2 * l + 1) / (4 * math.pi))
                          for l in range(3)]) * np.array([1.0, 1.0, 0.5])
        c, s2 = math.cos(a), math.sin(a) ** 2
        k_seed = np.array([disc_sh.SEED_E0 * (1 - c), disc_sh.SEED_E1 * s2, disc_sh.SEED_E2 * c * s2])
        d = float(max(np.max(np.abs(seed - zon)), np.max(np.abs(k_seed - k_num))))
        sign = np.array([1.0, 1.0, -1.0])
        flipped = max(flipped, float(max(np.max(np.abs(seed * sign - zon)), np.max(np.abs(k_seed * sign - k_num)))))
        dev, unc = max(dev, d), max(unc, float(np.max(np.abs(num - num2))))
        rows.append([a_deg, float(np.max(np.abs(seed - zon))), float(np.max(np.abs(k_seed - k_num)))])
    k20 = np.array(disc_sh.irradiance_polynomial_order2(math.radians(alpha20_deg)))
    d20 = float(np.max(np.abs(k20 - np.array(disc_sh.SEED_E_20DEG))))
    return {"max_deviation": max(dev, d20), "quadrature_uncertainty": unc, "rows": rows,
            "band2_flipped_deviation": flipped, "alpha20_polynomial": k20.tolist(),
            "alpha20_seed": list(disc_sh.SEED_E_20DEG), "alpha20_deviation": d20}


def elevation_sweep(s: Settings, alphas_deg: tuple[float, ...]) -> dict:
    """A receiver facing up and a disc (α = 5°, 20°) at elevation e above its horizon: |E_N − E| / Φ per order.

    SH through the engine path (zonal → rotated with Y_lm(d) → Σ Â_l L_lm Y_lm(n)). E depends on d·n only,
    so the light is rotated once, to d = up, and the normals carry the elevation: n(e) at elevation e
    (azimuth 30°) gives d·n = sin e, the same as a light at elevation e over an upward normal."""
    elev = np.arange(-30.0, 90.0 + 1e-9, s.elevation_step_deg)
    up = np.array([0.0, 1.0, 0.0])
    normals = np.stack([procedural.direction_from_elevation(x, 30.0) for x in elev])
    out: dict = {"elevation_deg": elev.tolist()}
    for a_deg in alphas_deg:
        a = math.radians(a_deg)
        exact = sphere_cap.cap_irradiance(normals @ up, math.sin(a) ** 2)
        out[f"alpha{a_deg:g}"] = {"exact": exact.tolist()}
        for n in ORDERS:
            e = disc_sh.disc_irradiance_sh_rotated(a, up, normals, n)
            out[f"alpha{a_deg:g}"][f"order{n}"] = (np.abs(e - exact) / cap_flux(math.sin(a) ** 2)).tolist()
    return out


def distance_sweep(s: Settings, thetas_deg: np.ndarray, level: float) -> dict:
    """Every technique vs d/r on a sphere and a facing disc (max_θ |E′ − E| / E(0)); the disc's on-axis
    inverse-square error at normal incidence; a sphere replaced by a disc of the same radius (tan α = r/d)."""
    ratios = np.geomspace(1.1, 100.0, s.distance_ratios)
    out: dict = {"d_over_r": ratios.tolist(), "techniques": {}, "crossing_xtol": RATIO_XTOL}
    for tech in arealight:
        for shape in ("sphere", "disc"):
            if supports(tech, shape):
                out["techniques"][f"{tech.name} ({shape})"] = peak_errors_vs_distance(tech, shape, ratios,
                                                                                      thetas_deg).tolist()
    cos_t = np.cos(np.radians(thetas_deg))
    out["inverse_square_disc_normal_incidence"] = [_inv_disc_axis(q) for q in ratios]
    out["sphere_as_disc_tan"] = [float(np.max(np.abs(sphere_cap.cap_irradiance(cos_t, _scene("disc", q)["sin2_sigma"])
                                                    - sphere_cap.cap_irradiance(cos_t, 1 / q**2))) / (math.pi / q**2))
                                 for q in ratios]

    def crossing(values: list[float], fn: Callable[[float], float]) -> float | None:
        v = np.asarray(values)
        idx = [i for i in range(len(ratios) - 1) if v[i] > level >= v[i + 1]]
        return (float(brentq(lambda q: fn(q) - level, ratios[idx[-1]], ratios[idx[-1] + 1], xtol=RATIO_XTOL)) if idx
                else None)

    inv = out["techniques"].get("inverse_square (sphere)")
    out["crossing_inverse_square_sphere"] = None if inv is None else crossing(
        inv, lambda q: technique_errors(arealight["inverse_square"], _scene("sphere", q), thetas_deg)["peak.max"])
    out["crossing_inverse_square_disc_normal_incidence"] = crossing(out["inverse_square_disc_normal_incidence"],
                                                                    _inv_disc_axis)
    return out


def peak_errors_vs_distance(tech: Technique, shape: str, ratios: np.ndarray, thetas_deg: np.ndarray) -> np.ndarray:
    """max_θ |E′ − E| / E(0) at every d/r in one call of the technique (receivers at (0, 0, d) for all d)."""
    pts, nrm = receivers(1.0, thetas_deg)
    pts = np.repeat(np.asarray(ratios, dtype=np.float64), len(nrm))[:, None] * pts[:1]
    nrm = np.tile(nrm, (len(ratios), 1))
    e = arealight.call(tech, light_mapping(shape, 1.0), pts, nrm).reshape(len(ratios), -1)
    s2 = np.array([_scene(shape, q)["sin2_sigma"] for q in ratios])
    f = float_type()
    cos_t = np.tile(np.cos(np.radians(thetas_deg)), len(ratios))
    exact = np.array(sphere_cap.cap_irradiance_dr(f(cos_t.astype(np.float32)),
                                                  f(np.repeat(s2, len(thetas_deg)).astype(np.float32))),
                     dtype=np.float64).reshape(len(ratios), -1)
    return np.abs(e - exact).max(axis=1) / exact[:, 0]


def _scene(shape: str, q: float) -> dict[str, Any]:
    s2 = sphere_cap.sin2_sigma_sphere(1.0, q) if shape == "sphere" else sphere_cap.sin2_sigma_disc(1.0, q)
    return {"shape": shape, "distance": q, "sin2_sigma": s2}


def _inv_disc_axis(q: float) -> float:
    """|π/q² − E(0)| / E(0) for a facing disc at d/r = q (inverse square at normal incidence)."""
    e0 = float(sphere_cap.cap_irradiance(np.array([1.0]), sphere_cap.sin2_sigma_disc(1.0, q))[0])
    return abs(float(point_light.inverse_square(point_light.disc_intensity(1.0), q, 1.0)) / e0 - 1.0)



SH_THRESHOLD = 0.05  # [2]'s order-2 "maximum error < 5 %", in R&H's flux normalisation


POINT_THRESHOLD = 0.01  # "off by more than 1 %": the level at which the d/r crossing is reported (finding)
# The crossings' root tolerances (Brent's xtol, stated with each figure): α in degrees, d/r dimensionless.
ALPHA_XTOL_DEG = 1e-3
RATIO_XTOL = 1e-4


ALPHA20 = 20.0  # [1]'s worked example; the lower end of the α range the 5 % statement holds on


ALPHA_INSIDE, ALPHA_OUTSIDE = 25.0, 19.5  # Mitsuba decisions either side of the range's end


def _thetas(s: Settings) -> np.ndarray:
    return np.arange(0.0, 180.0 + 1e-9, s.theta_step_deg)


def compute(ctx: Context, s: Settings) -> dict[str, Any]:
    """Every number of the experiment (JSON-able)."""
    seed = ctx.seed % 2048
    scenes = scene_table(ALPHA20)
    checks = ctx.map(lambda item: reference_check(item[1][0], item[1][1], s, (seed + item[0]) % 2048),
                     list(enumerate(scenes.items())), "arealights: Mitsuba")  # independent seeds per scene
    th = _thetas(s)
    return {"settings": settings_json(s, omit=("specular",)), "scenes": scenes, "reference_checks": checks,
            "cap_quadrature": {"max": cap_quadrature_check(np.cos(np.radians(th))),
                               "unclipped": cap_quadrature_check(np.cos(np.radians(th)), unclipped=True)},
            "seed_formulas": seed_check(s, ALPHA20),
            "techniques": measure_techniques(scenes, {c["name"]: c for c in checks}, th),
            "alpha_sweep": alpha_sweep(s, th), "alpha_range": alpha_range(s, th),
            "decide": {k: decide_alpha(a, s, (seed + 7 + i) % 2048)
                       for i, (k, a) in enumerate((("inside", ALPHA_INSIDE), ("outside", ALPHA_OUTSIDE)))},
            "sh_vs_elevation": elevation_sweep(s, (5.0, ALPHA20)),
            "point_lights": distance_sweep(s, th, POINT_THRESHOLD),
            "specular": specular_compute(s.specular)}


def measure_techniques(scenes: dict, checks: dict, thetas: np.ndarray,
                       techniques: Sequence[Technique] | None = None) -> dict[str, dict[str, Any]]:
    """Per technique and supported scene: closed-form flux/peak errors and the error against Mitsuba."""
    out: dict[str, dict[str, Any]] = {}
    for tech in techniques if techniques is not None else list(arealight):
        out[tech.name] = {}
        for name, sc in scenes.items():
            if supports(tech, sc["shape"]):
                out[tech.name][name] = {**technique_errors(tech, sc, thetas),
                                        "mitsuba": mitsuba_error(tech, sc, checks[name]) if name in checks else None}
    return out


def alpha_sweep(s: Settings, thetas: np.ndarray) -> dict[str, Any]:
    """max_θ |E′ − E| / Φ vs α for every technique that handles a sphere (sin α = r/d), and the α at which
    each falls through 5 % (Brent between grid points)."""
    alphas = np.asarray(s.alphas_deg, dtype=np.float64)
    out: dict[str, Any] = {"alpha_deg": alphas.tolist(), "errors": {}, "crossing_5pct": {},
                           "crossing_xtol_deg": ALPHA_XTOL_DEG}
    for tech in arealight:
        if supports(tech, "sphere"):
            errs = [sphere_alpha_error(tech, a, thetas) for a in alphas]
            out["errors"][tech.name] = errs
            out["crossing_5pct"][tech.name] = alpha_crossing(
                lambda a, t=tech: sphere_alpha_error(t, a, thetas), alphas, np.asarray(errs), SH_THRESHOLD)
    return out


def alpha_range(s: Settings, thetas: np.ndarray) -> dict[str, Any]:
    """Order-2 SH error on a fine α grid (closed form): where it meets 5 % of Φ and where not."""
    lo, hi = s.range_deg
    alphas = np.arange(lo, hi + 1e-9, s.range_step_deg)
    errs = np.array([sphere_alpha_error("sh_order2", a, thetas) for a in alphas])
    inside = alphas >= ALPHA20 - 1e-9
    below = alphas[~inside][-1]
    # closed-form uncertainty relative to Φ: CAP_QUADRATURE_TOLERANCE·π sin²α / (2π(1 − cos α)) ≤ tolerance
    return {"alpha_deg": alphas.tolist(), "order2": errs.tolist(), "uncertainty": CAP_QUADRATURE_TOLERANCE,
            "inside_max": float(errs[inside].max()), "outside_min": float(errs[~inside].min()),
            "below_deg": float(below), "with_below_max": float(errs[alphas >= below - 1e-9].max()),
            "with_end_min": float(errs[alphas <= ALPHA20 + 1e-9].min()),
            "crossing_deg": alpha_crossing(lambda a: sphere_alpha_error("sh_order2", a, thetas),
                                              alphas, errs, SH_THRESHOLD), "crossing_xtol_deg": ALPHA_XTOL_DEG}
