"""Noise-free sweeps of the ``lights`` experiment: attenuation against 1/d², when a point light stands
in for an area light, how the n×n grid converges, and the spot profiles.

Every technique is called through ``light.call`` (the family's output contract); the exact
references are closed forms: 1/d² itself, Lambert's polygon formula for the rectangle
(:func:`validate.reference.light_render.rectangle_irradiance`, checked against Mitsuba by the
experiment's claim), the spherical-cap formula for the sphere (Snyder 1996,
:mod:`validate.local_models.arealight.sphere_cap`), and for the disc the configuration factors of an element
parallel and perpendicular to a coaxial disc (:func:`disc_irradiance`; it agrees with an independent float64
Gauss–Legendre quadrature, :func:`quadrature_irradiance`, to 4·10⁻¹⁴ on the stand-in receivers at d/size 0.8–5.6,
where the 64×64 midpoint grid used before was 1.6·10⁻⁴ to 5·10⁻⁶ off — enough to move the 1 % crossing by
1.4·10⁻³ in d/size).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numpy as np

from ...local_models import light as family
from ...local_models.arealight import sphere_cap
from ...local_models.light.light_grid import emitter_points
from ...metrics import crossing
from ...reference import light_render as lr
from ...scenes.light_scenes import Light

STANDIN_LEVEL = 0.01  # the finding's "within 1 %"


# -- attenuation -----------------------------------------------------------------------------------
def point_techniques() -> list[Any]:
    return [t for t in family if "point" in t.meta.get("lights", ())]


def attenuation_curves(distances: np.ndarray, light_range: float) -> dict[str, np.ndarray]:
    """E_tech(d) / (I/d²) for every point technique, receivers on the axis facing the light (I = 1)."""
    pts = np.stack([np.zeros_like(distances), -distances, np.zeros_like(distances)], axis=1)
    normals = np.tile([0.0, 1.0, 0.0], (distances.size, 1))
    lm = {"type": "point", "position": np.zeros(3), "intensity": 1.0, "range": light_range}
    return {t.name: family.call(t, lm, pts, normals) * distances**2 for t in point_techniques()}


def best_scale_error(ratio: np.ndarray) -> tuple[float, float]:
    """(k, max |k·ratio − 1|) minimised over the scale k: k = 2/(max + min), error (max − min)/(max + min)."""
    lo, hi = float(ratio.min()), float(ratio.max())
    if hi <= 0:
        return float("nan"), 1.0
    return 2.0 / (hi + lo), (hi - lo) / (hi + lo)


# -- point light standing in for an area light ------------------------------------------------------
def standin_receivers(light: Light, distance: float, polar_deg: tuple[float, ...], tilt_deg: tuple[float, ...]
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Receivers at ``distance`` from the light's centre, at polar angles from its normal (the light's
    front for rectangle/disc; any axis for a sphere), normals tilted from the direction to the light."""
    left, up, fwd = light.frame() if light.kind != "sphere" else (np.array([1.0, 0, 0]), np.array([0, 0, 1.0]),
                                                                  np.array([0, -1.0, 0]))
    pts, nrm = [], []
    for p in polar_deg:
        a = math.radians(p)
        w = math.cos(a) * fwd + math.sin(a) * left
        to_light = -w
        side = np.cross(to_light, up)  # per polar angle: the tilts share it (formed once, the same values)
        side_unit = side / max(np.linalg.norm(side), 1e-12)
        point = np.asarray(light.position) + distance * w
        for t in tilt_deg:
            b = math.radians(t)
            nrm.append(math.cos(b) * to_light + math.sin(b) * side_unit)
            pts.append(point)
    n = np.array(nrm)
    return np.array(pts), n / np.linalg.norm(n, axis=1, keepdims=True)


def exact_area_irradiance(light: Light, pts: np.ndarray, nrm: np.ndarray) -> np.ndarray:
    """The reference E of an area light (module docstring)."""
    if light.kind == "rectangle":
        return lr.rectangle_irradiance(light, pts, nrm)
    if light.kind == "sphere":
        return sphere_irradiance(light, pts, nrm, sphere_cap.cap_irradiance)
    return disc_irradiance(light, pts, nrm)


def sphere_irradiance(light: Light, pts: np.ndarray, nrm: np.ndarray,
                      cap: Callable[[np.ndarray, float], np.ndarray]) -> np.ndarray:
    """L · cap(cos θ, r²/d²) for a sphere of radius r at distance d (the cap formula of
    :mod:`validate.local_models.arealight.sphere_cap`), one call per distinct distance."""
    c = np.asarray(light.position)
    d = np.linalg.norm(pts - c, axis=1)
    cos_t = np.clip(np.einsum("nk,nk->n", nrm, (c - pts) / d[:, None]), -1.0, 1.0)
    out = np.empty(d.size)
    for dd in np.unique(d):
        sel = d == dd
        out[sel] = cap(cos_t[sel], float((light.size[0] / dd) ** 2))
    return light.power * out


def disc_irradiance(light: Light, pts: np.ndarray, nrm: np.ndarray) -> np.ndarray:
    """Exact E of a Lambertian disc (radius R, radiance L) wholly above the receiver's horizon, NaN where its
    rim crosses the horizon. E is linear in the normal, E = L n·Φ with Φ = ∫_disc ω dω, whose two components are
    the configuration factors from a plane element parallel, resp. perpendicular, to a disc (J. R. Howell, *A
    Catalog of Radiation Heat Transfer Configuration Factors*, thermalradiation.net; derived from Φ's definition
    and checked against :func:`quadrature_irradiance` to 4·10⁻¹⁴, see the module docstring): at height h and
    distance ρ from the axis, with
    A = h² + ρ² + R² and D = √(A² − 4R²ρ²),
    Φ·(−n_L) = (π/2)(1 − (h² + ρ² − R²)/D),   Φ·(−e_ρ) = (π h / 2ρ)(A/D − 1)   (e_ρ away from the axis)."""
    m = light.as_mapping()
    nl, rad = np.asarray(m["normal"]), float(m["radius"])
    rel = pts - np.asarray(light.position)
    h = rel @ nl
    radial = rel - h[:, None] * nl
    rho = np.linalg.norm(radial, axis=1)
    e_rho = np.where(rho[:, None] > 0, radial / np.maximum(rho, 1e-300)[:, None], 0.0)
    a = h**2 + rho**2 + rad**2
    dd = np.sqrt(a**2 - 4 * rad**2 * rho**2)
    f_par = 0.5 * (1.0 - (h**2 + rho**2 - rad**2) / dd)
    with np.errstate(divide="ignore", invalid="ignore"):
        f_perp = np.where(rho > 0, h / (2 * np.maximum(rho, 1e-300)) * (a / dd - 1.0), 0.0)
    e = math.pi * light.power * (f_par * (nrm @ -nl) + f_perp * np.einsum("nk,nk->n", nrm, -e_rho))
    tangential = np.linalg.norm(nrm - (nrm @ nl)[:, None] * nl, axis=1)
    above = np.einsum("nk,nk->n", nrm, -rel) - rad * tangential > 0  # the rim's lowest point above the horizon
    return np.where(above & (h > 0), e, np.nan)


def standin_irradiance(light: Light, pts: np.ndarray, nrm: np.ndarray) -> np.ndarray:
    """The single point light: a sphere's isotropic I = π r² L (``point_inverse_square``); a rectangle's or
    disc's cosine-lobe point I(ψ) = L A cos ψ at the centre (``area_grid`` with n = 1)."""
    if light.kind == "sphere":
        lm = {"type": "point", "position": np.asarray(light.position), "intensity": math.pi * light.size[0] ** 2
              * light.power}
        return family.call("point_inverse_square", lm, pts, nrm)
    return family.call("area_grid", dict(light.as_mapping(), grid=1), pts, nrm)


def standin_error(light: Light, ratio: float, polar_deg: tuple[float, ...], tilt_deg: tuple[float, ...],
                  reference: Callable[[Light, np.ndarray, np.ndarray], np.ndarray] = exact_area_irradiance
                  ) -> tuple[float, int]:
    """(max over receivers of |E_point − E| / E at d = ratio · extent, receivers skipped): the stand-in's error
    against ``reference`` (default: the closed forms of the module docstring); receivers whose reference is not
    finite and positive (a horizon cutting a flat light) are skipped."""
    pts, nrm = standin_receivers(light, float(ratio) * light.extent, polar_deg, tilt_deg)
    exact = reference(light, pts, nrm)
    ok = np.isfinite(exact) & (exact > 0)
    if not ok.any():
        return float("nan"), int(ok.size)
    approx = standin_irradiance(light, pts[ok], nrm[ok])
    return float(np.max(np.abs(approx - exact[ok]) / exact[ok])), int((~ok).sum())


def standin_sweep(lights: dict[str, Light], ratios: np.ndarray, polar_deg: tuple[float, ...],
                  tilt_deg: tuple[float, ...], xtol: float) -> dict[str, Any]:
    """Max relative error of the single point light vs d / extent on the grid ``ratios``, and the ratio beyond
    which it stays ≤ 1 %: the last root of (max-over-receivers error − 0.01), bracketed on the grid and refined
    by Brent's method on the exact evaluation to ``xtol`` in d/size (:func:`validate.metrics.crossing.last_crossing`);
    checked by an independent locator (:func:`independent_crossing`)."""
    out: dict[str, Any] = {"ratios": ratios.tolist(), "polar_deg": list(polar_deg), "tilt_deg": list(tilt_deg),
                           "level": STANDIN_LEVEL, "xtol": xtol}
    for kind, light in lights.items():
        sweep = [standin_error(light, float(r), polar_deg, tilt_deg) for r in ratios]
        e = np.array([v for v, _ in sweep])
        c = crossing.last_crossing(lambda r, lt=light: standin_error(lt, r, polar_deg, tilt_deg)[0], ratios, e,
                                   STANDIN_LEVEL, xtol)
        out[kind] = {"max_rel": e.tolist(), "ratio_within_1pct": c.root, "crossing": c.to_json(),
                     "skipped_receivers": sum(k for _, k in sweep), "extent": light.extent,
                     "independent": independent_crossing(light, c, ratios, polar_deg, tilt_deg, xtol)}
    return out


def independent_crossing(light: Light, c: crossing.Crossing, ratios: np.ndarray, polar_deg: tuple[float, ...],
                         tilt_deg: tuple[float, ...], xtol: float) -> dict[str, Any]:
    """The same crossing located independently of :func:`standin_sweep`'s reference and root finder: the error
    against :func:`quadrature_irradiance` (Gauss–Legendre, float64), its last crossing in the grid bracket found by
    a plain bisection (:func:`validate.metrics.crossing.bisect_last`, 16 scan nodes, to xtol/10); and the
    reference's own disagreement at the root, |E_quad − E_ref| / E_ref (max over receivers)."""
    if c.root is None or c.grid_node is None:
        return {"root": None, "reference_disagreement": None}
    i = int(np.searchsorted(ratios, c.grid_node))
    root = crossing.bisect_last(lambda r: standin_error(light, r, polar_deg, tilt_deg, quadrature_irradiance)[0],
                                float(ratios[i - 1]), float(ratios[i]), STANDIN_LEVEL, xtol / 10, 16)
    pts, nrm = standin_receivers(light, c.root * light.extent, polar_deg, tilt_deg)
    ref, quad = exact_area_irradiance(light, pts, nrm), quadrature_irradiance(light, pts, nrm)
    ok = np.isfinite(ref) & np.isfinite(quad) & (ref > 0)
    return {"root": root, "xtol": xtol / 10, "reference_disagreement": float(np.max(np.abs(quad[ok] - ref[ok])
                                                                                     / ref[ok]))}


@lru_cache(maxsize=4)
def _leggauss_cached(n: int) -> tuple[np.ndarray, np.ndarray]:
    return np.polynomial.legendre.leggauss(n)


def _leggauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """``numpy.polynomial.legendre.leggauss(n)`` (nodes, weights), computed once per n (an eigenvalue problem; the
    crossing searches call :func:`quadrature_irradiance` dozens of times); copies."""
    x, w = _leggauss_cached(int(n))
    return x.copy(), w.copy()


def quadrature_irradiance(light: Light, pts: np.ndarray, nrm: np.ndarray) -> np.ndarray:
    """An independent float64 E(x) = L ∫ cos θ cos θ' / r² dA: rectangle, a 48×48 Gauss–Legendre tensor rule over
    (s, t) ∈ [−1, 1]²; disc, 48-point Gauss–Legendre in the radius (weight ρ) × a 96-point trapezoid in the azimuth
    (exponentially convergent for a smooth periodic integrand; Davis & Rabinowitz 1984 §2.9, §2.7); NaN where an
    emitter node lies behind the receiver's tangent plane (the rule assumes a smooth integrand). Sphere:
    :func:`validate.local_models.arealight.sphere_cap.cap_irradiance_quadrature` with 2×32 nodes (the
    horizon-clipped cap, its azimuth integral in closed form; within 10⁻⁹ of π sin²σ of its 2×256-node value
    for sin²σ ∈ {0.1, 0.4, 0.9}) — independent of the cap formula the sweep uses."""
    m = light.as_mapping()
    if light.kind == "sphere":
        return sphere_irradiance(light, pts, nrm, lambda c, s2: sphere_cap.cap_irradiance_quadrature(c, s2, 32))
    xg, wg = _leggauss(48)
    if light.kind == "rectangle":
        a, b = m["axes"]
        s, t = np.meshgrid(xg, xg, indexing="ij")
        q = np.asarray(light.position) + s.ravel()[:, None] * a + t.ravel()[:, None] * b
        w = np.outer(wg, wg).ravel() * np.linalg.norm(a) * np.linalg.norm(b)
    else:
        rho, phi = 0.5 * (xg + 1.0) * m["radius"], np.arange(96) * (2 * math.pi / 96)
        rr, pp = np.meshgrid(rho, phi, indexing="ij")
        q = (np.asarray(light.position) + (rr * np.cos(pp)).ravel()[:, None] * m["axes"][0]
             + (rr * np.sin(pp)).ravel()[:, None] * m["axes"][1])
        w = (np.outer(0.5 * wg * m["radius"] * rho, np.full(96, 2 * math.pi / 96))).ravel()
    v = q[None, :, :] - pts[:, None, :]
    r2 = np.einsum("nkc,nkc->nk", v, v)
    cos_r = np.einsum("nkc,nc->nk", v, nrm) / np.sqrt(r2)
    cos_l = -(v @ m["normal"]) / np.sqrt(r2)
    e = light.power * np.sum(w * np.maximum(cos_l, 0.0) * cos_r / r2, axis=1)
    return np.where(np.all(cos_r > 0, axis=1), e, np.nan)


# -- n×n grid convergence ------------------------------------------------------------------------------
def grid_errors(light: Light, pts: np.ndarray, nrm: np.ndarray, exact: np.ndarray, ns: list[int],
                offset: float) -> list[float]:
    """max over receivers of |E_n − E| / E for the unshadowed grid (``grid_offset`` = offset)."""
    ok = np.isfinite(exact) & (exact > 0)
    out = []
    for n in ns:
        e = family.call("area_grid", dict(light.as_mapping(), grid=n, grid_offset=offset), pts[ok], nrm[ok])
        out.append(float(np.max(np.abs(e - exact[ok]) / exact[ok])))
    return out


def loglog_slope(ns: list[int], errs: list[float], n_min: int) -> float:
    """Least-squares slope of log(error) against log(n) over n ≥ n_min."""
    x = np.log([n for n in ns if n >= n_min])
    y = np.log([e for n, e in zip(ns, errs, strict=True) if n >= n_min])
    return float(np.polyfit(x, y, 1)[0])


VISIBLE_FRACTION_ROWS = 2048  # receivers per block of :func:`visible_fraction` (its (N, side², 3) temporaries)


def visible_fraction(light: Light, pts: np.ndarray, nrm: np.ndarray, visible: Any, side: int) -> np.ndarray:
    """Reference V(x): fraction of the side×side emitter points in front of x's tangent plane that x sees
    (NaN where none is in front). Receivers in blocks of :data:`VISIBLE_FRACTION_ROWS`: every receiver's value is
    its own points' and shadow rays' (the same rays, the same answers), with temporaries a block in size."""
    out = np.empty(len(pts))
    for s in range(0, len(pts), VISIBLE_FRACTION_ROWS):
        e = s + VISIBLE_FRACTION_ROWS
        out[s:e] = _visible_fraction_block(light, pts[s:e], nrm[s:e], visible, side)
    return out


def _visible_fraction_block(light: Light, pts: np.ndarray, nrm: np.ndarray, visible: Any, side: int
                            ) -> np.ndarray:
    q, _, _ = emitter_points(light.as_mapping(), pts, side, 0.5)
    k = q.shape[1]
    front = np.einsum("nk,nmk->nm", nrm, q - pts[:, None, :]) > 0
    rows, cols = np.nonzero(front)
    vis = np.zeros(front.shape, dtype=bool)
    if rows.size:
        vis[rows, cols] = visible(pts[rows], nrm[rows], q[rows, cols])
    cnt = front.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(cnt > 0, vis.sum(axis=1) / np.maximum(cnt, 1), np.nan) if k else np.full(len(pts), np.nan)


# -- spot profiles -------------------------------------------------------------------------------------
def mitsuba_spot_profile(alpha_deg: np.ndarray, beam_deg: float, cutoff_deg: float) -> np.ndarray:
    """Mitsuba's falloff_curve (float64): 1 to the beam width, linear in α to 0 at the cutoff."""
    a = np.asarray(alpha_deg, dtype=np.float64)
    ramp = (cutoff_deg - a) / (cutoff_deg - beam_deg)
    return np.where(a < cutoff_deg, np.where(a <= beam_deg, 1.0, ramp), 0.0)


BRENT_START = (3.0 - math.sqrt(5.0)) / 2.0  # scipy's bounded Brent evaluates lo + 0.381966 (hi − lo) first


def spot_exponent_problem(beam_deg: float, cutoff_deg: float, nodes: int = 2000) -> dict[str, np.ndarray]:
    """Nodes α_i on [0, cutoff], weights w_i = sin α_i + 10⁻¹², Mitsuba's profile there."""
    a = np.linspace(0.0, cutoff_deg, nodes)
    return {"alpha": a, "w": np.sin(np.radians(a)) + 1e-12, "target": mitsuba_spot_profile(a, beam_deg, cutoff_deg)}


def spot_exponent_objective_ad(prob: dict[str, np.ndarray]) -> Any:
    """Σ w_i (cos^f α_i − profile_i)² / Σ w_i in drjit (cos^f = exp(f ln cos α)), a function of [f]."""
    import drjit as dr

    from ...numerics import adfit

    log_cos = adfit.array(np.log(np.cos(np.radians(prob["alpha"]))))
    wn, t = adfit.array(prob["w"] / np.sum(prob["w"])), adfit.array(prob["target"])
    return lambda p: dr.sum(wn * (dr.exp(p[0] * log_cos) - t) ** 2)


def fit_spot_exponent(beam_deg: float, cutoff_deg: float, nodes: int = 2000, method: str = "ad"
                      ) -> tuple[float, float]:
    """f minimising ∫₀^cutoff (cos^f α − profile(α))² sin α dα (solid-angle weighted least squares), and the
    rms of the fit relative to the peak. ``method="scipy"``: bounded Brent on f ∈ [0, 2000] (xatol 10⁻³);
    ``"ad"`` (the experiment's path where the variant has AD): L-BFGS-B on the same bounds with drjit's
    gradient (:func:`validate.numerics.adfit.minimize`), started where Brent starts (:data:`BRENT_START`)."""
    from ...numerics import adfit

    prob = spot_exponent_problem(beam_deg, cutoff_deg, nodes)
    a, w, target = prob["alpha"], prob["w"], prob["target"]
    if method == "ad" and adfit.available():
        fit = adfit.minimize(spot_exponent_objective_ad(prob), [BRENT_START * 2000.0], bounds=[(0.0, 2000.0)])
        return float(fit.x[0]), float(math.sqrt(max(fit.fun, 0.0)))
    from scipy.optimize import minimize_scalar

    def cost(f: float) -> float:
        return float(np.sum(w * (np.cos(np.radians(a)) ** f - target) ** 2) / np.sum(w))

    res = minimize_scalar(cost, bounds=(0.0, 2000.0), method="bounded", options={"xatol": 1e-3})
    return float(res.x), float(math.sqrt(res.fun))


# -- a real lamp: a disc behind a circular aperture -------------------------------------------------------
def lens_area(delta: np.ndarray, r1: float, r2: float) -> np.ndarray:
    """Overlap area of two discs of radii r1 and r2 whose centres are ``delta`` apart."""
    d = np.maximum(np.asarray(delta, dtype=np.float64), 0.0)
    small, big = min(r1, r2), max(r1, r2)
    inside = d <= big - small
    apart = d >= big + small
    dd = np.where(inside | apart, 0.5 * (big + small), d)  # a safe value where the general branch is unused
    a1 = small**2 * np.arccos(np.clip((dd**2 + small**2 - big**2) / (2 * dd * small), -1, 1))
    a2 = big**2 * np.arccos(np.clip((dd**2 + big**2 - small**2) / (2 * dd * big), -1, 1))
    k = (-dd + small + big) * (dd + small - big) * (dd - small + big) * (dd + small + big)
    general = a1 + a2 - 0.5 * np.sqrt(np.maximum(k, 0.0))
    return np.where(inside, math.pi * small**2, np.where(apart, 0.0, general))


def lamp_profile(alpha_deg: np.ndarray, radius: float, depth: float, aperture: float) -> np.ndarray:
    """Far-field I(α)/I₀ of a disc of ``radius`` at ``depth`` behind a circular mouth of radius ``aperture``:
    cos α · A(depth · tan α) / (π r²) (see :mod:`validate.scenes.light_scenes`, kind ``lamp``)."""
    a = np.radians(np.asarray(alpha_deg, dtype=np.float64))
    inside = a < math.pi / 2
    t = np.where(inside, np.tan(np.where(inside, a, 0.0)), 1e30)
    return np.where(inside, np.cos(a) * lens_area(depth * t, radius, aperture) / (math.pi * radius**2), 0.0)


def lamp_problem(radius: float, depth: float, aperture: float, nodes: int = 1500) -> dict[str, Any]:
    """The lamp fits' data: the beam edge atan((r + a)/h), nodes on [0, 1.1 edge], weights, the profile."""
    edge = math.degrees(math.atan((radius + aperture) / depth))
    a = np.linspace(0.0, edge * 1.1, nodes)
    return {"edge": edge, "alpha": a, "w": np.sin(np.radians(a)) + 1e-12,
            "target": lamp_profile(a, radius, depth, aperture)}


def fit_lamp(radius: float, depth: float, aperture: float, nodes: int = 1500,
             methods: tuple[str, str] = ("ad", "scipy")) -> dict[str, float]:
    """Least-squares (solid-angle weighted) cos^f spot (cutoff = the lamp's beam edge) and Mitsuba spot
    (beam width and cutoff) matching :func:`lamp_profile`; rms of each fit relative to the peak.
    ``methods`` = (cos^f fit, Mitsuba fit), each ``"scipy"`` (bounded Brent for f ∈ [0, 500]; Nelder–Mead for
    (beam, cutoff) from (0.3, 1) × edge) or ``"ad"`` (L-BFGS-B with drjit gradients from the same starts,
    :func:`fit_lamp_ad`; used only where the variant has AD). The experiment's choice, (AD, Nelder–Mead): the
    AD cos^f fit reaches the Brent residual; the Mitsuba profile is piecewise linear in (beam, cutoff) (a kink
    wherever either crosses a node), where L-BFGS-B stops 8·10⁻⁶ (relative) above Nelder–Mead's rms."""
    from ...numerics import adfit

    prob = lamp_problem(radius, depth, aperture, nodes)
    ad = tuple(m == "ad" and adfit.available() for m in methods)
    out = fit_lamp_ad(prob, ad) if any(ad) else {"edge_deg": prob["edge"]}
    return out | fit_lamp_scipy(prob, tuple(not x for x in ad))


def fit_lamp_scipy(prob: dict[str, Any], which: tuple[bool, ...] = (True, True)) -> dict[str, float]:
    """:func:`fit_lamp`'s scipy fits (``which`` = (cos^f, Mitsuba)): bounded Brent for f ∈ [0, 500] on the rms;
    Nelder–Mead (xatol 10⁻⁴, fatol 10⁻⁹) for (beam, cutoff) from (0.3, 1) × edge."""
    from scipy.optimize import minimize, minimize_scalar

    edge, a, w, target = prob["edge"], prob["alpha"], prob["w"], prob["target"]

    def rms(model: np.ndarray) -> float:
        return float(math.sqrt(np.sum(w * (model - target) ** 2) / np.sum(w)))

    cos_a = np.cos(np.radians(a))
    out: dict[str, float] = {"edge_deg": edge}
    if which[0]:
        res = minimize_scalar(lambda f: rms(np.where(a < edge, cos_a**f, 0.0)), bounds=(0.0, 500.0),
                              method="bounded")
        out.update(cos_f_exponent=float(res.x), cos_f_rms=rms(np.where(a < edge, cos_a**res.x, 0.0)))
    if not which[1]:
        return out

    def mitsuba(p: np.ndarray) -> np.ndarray:  # beam width in [0, cutoff]
        cut = max(float(p[1]), 1e-3)
        return mitsuba_spot_profile(a, float(np.clip(p[0], 0.0, cut - 1e-6)), cut)

    mit = minimize(lambda p: rms(mitsuba(p)), x0=[0.3 * edge, edge], method="Nelder-Mead",
                   options={"xatol": 1e-4, "fatol": 1e-9})
    cut = max(float(mit.x[1]), 1e-3)
    return out | {"mitsuba_beam_deg": float(np.clip(mit.x[0], 0.0, cut - 1e-6)), "mitsuba_cutoff_deg": cut,
                  "mitsuba_rms": float(mit.fun)}


def lamp_objectives_ad(prob: dict[str, Any]) -> tuple[Any, Any]:
    """The weighted mean squares of :func:`fit_lamp_ad` in drjit: (of [f] for cos^f inside the edge, of
    [beam, cutoff] for Mitsuba's profile)."""
    import drjit as dr

    from ...numerics import adfit

    a_np, w = prob["alpha"], prob["w"]
    a, wn, t = adfit.array(a_np), adfit.array(w / np.sum(w)), adfit.array(prob["target"])
    inside = adfit.array((a_np < prob["edge"]).astype(np.float64))
    log_cos = adfit.array(np.log(np.cos(np.radians(a_np))))

    def cos_f(p: list[Any]) -> Any:
        return dr.sum(wn * (inside * dr.exp(p[0] * log_cos) - t) ** 2)

    def mitsuba(p: list[Any]) -> Any:
        cut = dr.maximum(p[1], 1e-3)
        beam = dr.clip(p[0], 0.0, cut - 1e-6)
        model = dr.select(a < cut, dr.select(a <= beam, 1.0, (cut - a) / (cut - beam)), 0.0)
        return dr.sum(wn * (model - t) ** 2)

    return cos_f, mitsuba


def fit_lamp_ad(prob: dict[str, Any], which: tuple[bool, ...] = (True, True)) -> dict[str, float]:
    """:func:`fit_lamp`'s two fits in drjit, minimising the weighted mean square (the rms's square: the same
    minimiser) by L-BFGS-B (:func:`validate.numerics.adfit.minimize`): cos^f from Brent's first point
    (:data:`BRENT_START` of [0, 500]); Mitsuba's (beam, cutoff) — 1 to the beam, linear to 0 at the cutoff, beam
    clipped to [0, cutoff − 10⁻⁶] — from (0.3, 1) × edge with cutoff ≥ 10⁻³; ``which`` = (cos^f, Mitsuba) to fit."""
    from ...numerics import adfit

    edge = prob["edge"]
    cos_f, mitsuba = lamp_objectives_ad(prob)
    out: dict[str, float] = {"edge_deg": edge}
    if which[0]:
        f = adfit.minimize(cos_f, [BRENT_START * 500.0], bounds=[(0.0, 500.0)])
        out.update(cos_f_exponent=float(f.x[0]), cos_f_rms=math.sqrt(max(f.fun, 0.0)))
    if which[1]:
        m = adfit.minimize(mitsuba, [0.3 * edge, edge], bounds=[(0.0, None), (1e-3, None)])
        cut = max(float(m.x[1]), 1e-3)
        out.update(mitsuba_beam_deg=float(np.clip(m.x[0], 0.0, cut - 1e-6)), mitsuba_cutoff_deg=cut,
                   mitsuba_rms=math.sqrt(max(m.fun, 0.0)))
    return out
