"""Measurements of the überlight experiment: projector agreement, barn-door fits, sweeps, falloff.

Definitions (every metric is a fraction; "peak" is the reference's largest receiver radiance):

* projector ``max_rel`` / ``mean_rel``: max / mean over the compared receiver pixels of
  |L_model − L_ref| / peak. Compared pixels: receivers whose bilinear texture footprint (the 2 × 2
  texel centres around the lookup point) has one mask value — where the footprint straddles a hard
  edge Mitsuba blends two texels, a one-texel property of the reference, not of the model (their
  count is reported). ``scaled_max_rel``: the same after the least-squares scale of L_model.
  Uncertainty: the largest per-pixel standard error / peak (0 for the delta projector).
* barn-door ``edge_rms``: beam fraction A_ref = L_ref/U against the fitted A, U = I₀ ρ/π cos/d² the
  fitted beam without shaping, over the penumbra band (0 < A_fit < 1):
  edge_rms = √max(0, mean((A_fit − A_ref)²) − mean(σ_A²)) (the noise variance σ_A² = (s/U)² removed),
  uncertainty √(edge_rms² + SE[mean((A_fit − A_ref)²)]) − edge_rms.
* falloff: Fore June's I(d)/d-form against E(d) = π L r²/(r² + d²) (relative error over d ∈ [0, 20 r]).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import least_squares, minimize_scalar

from ...local_models import uberlight as family
from ...local_models.uberlight import orange_book as ub
from ...local_models.uberlight.common import superellipse_shape_ad
from ...numerics import adfit
from ...reference import uberlight_render as ur
from ...scenes import uberlight_scenes as us
from ..base import Context, settings_json
from ..techniques import Measured
from .settings import Settings


def light_mapping(lum: us.Luminaire, intensity: float, shape: Mapping[str, float], **extra: float) -> dict[str, Any]:
    """The technique's light: the luminaire's frame + the überlight shape (no distance shaping by default)."""
    return {"position": np.asarray(lum.position, dtype=np.float64), "axes": lum.frame(), "intensity": float(intensity),
            **ub.NO_DISTANCE_SHAPING, **shape, **extra}


class Frame:
    """One reference render's receiver pixels: G-buffer, reference, views and the light's visibility."""

    def __init__(self, scene: us.UberScene, ref: ur.UberRender, shadowed: bool = True):
        self.scene, self.ref, self.valid = scene, ref, ref.valid
        v = ref.valid
        self.position, self.normal, self.albedo = ref.position[v], ref.normal[v], ref.albedo[v]
        self.radiance, self.uncertainty, self.passes = ref.radiance[v], ref.uncertainty[v], ref.pass_images[:, v]
        views = np.asarray(scene.camera.origin) - self.position
        self.views = views / np.linalg.norm(views, axis=1)[:, None]
        self.shadow = ur.visibility(scene, self.position, self.normal) if shadowed else np.ones(len(self.position))
        self.peak = float(self.radiance.max())

    def material(self) -> dict[str, Any]:
        return {"albedo": self.albedo, "ks": 0.0}

    def image(self, values: np.ndarray) -> np.ndarray:
        out = np.full(self.valid.shape, np.nan)
        out[self.valid] = values
        return out

    def unshaped(self, lum: us.Luminaire) -> tuple[np.ndarray, np.ndarray]:
        """(light coordinates (N, 3), ρ/π · max(0, n·l)/d² · shadow) of every receiver."""
        lc = ub.light_coordinates({"position": lum.position, "axes": lum.frame()}, self.position)
        to = np.asarray(lum.position) - self.position
        d = np.linalg.norm(to, axis=1)
        cos = np.maximum(np.einsum("nk,nk->n", self.normal, to / d[:, None]), 0.0)
        return lc, self.albedo / math.pi * cos / d ** 2 * self.shadow


# -- projector ---------------------------------------------------------------------------------------------
def projector_mask(shape: Mapping[str, float], n: int, fov_deg: float) -> np.ndarray:
    """The überlight's angular mask A at the projector's texel centres (the model's own numpy form)."""
    x, y = ur.texel_directions(n, fov_deg)
    return ub.superellipse_shape_np(shape, x, y, np.ones_like(x))


def edge_footprint(frame: Frame, shape: Mapping[str, float], n: int, fov_deg: float) -> np.ndarray:
    """(N,) True where the 2 × 2 bilinear footprint of the lookup spans more than one mask value."""
    lum = frame.scene.luminaire
    lc, _ = frame.unshaped(lum)
    t = math.tan(math.radians(fov_deg) / 2)
    z = np.where(lc[:, 2] > 0, lc[:, 2], 1.0)
    fi = (0.5 - 0.5 * lc[:, 0] / (z * t)) * n - 0.5
    fj = (0.5 - 0.5 * lc[:, 1] / (z * t)) * n - 0.5
    vals = []
    for di in (0, 1):
        for dj in (0, 1):
            i, j = np.floor(fi) + di, np.floor(fj) + dj
            x, y = t * (1 - 2 * (i + 0.5) / n), t * (1 - 2 * (j + 0.5) / n)
            vals.append(ub.superellipse_shape_np(shape, x, y, np.ones_like(x)))
    v = np.stack(vals)
    return (v.max(axis=0) != v.min(axis=0)) & (lc[:, 2] > 0)


def projector_errors(frame: Frame, approx: np.ndarray, keep: np.ndarray) -> dict[str, float]:
    """max_rel, mean_rel, scaled_max_rel (± uncertainty) over the ``keep`` pixels (module docstring)."""
    ref, peak = frame.radiance[keep], frame.peak
    a = approx[keep]
    err = np.abs(a - ref) / peak
    k = float(a @ ref / (a @ a)) if a @ a > 0 else 1.0
    unc = float(frame.uncertainty[keep].max() / peak)
    return {"max_rel": float(err.max()), "mean_rel": float(err.mean()),
            "scaled_max_rel": float((np.abs(k * a - ref) / peak).max()), "scale": k, "uncertainty": unc}


# -- barn door -----------------------------------------------------------------------------------------------
FIT_KEYS = ("width", "height", "width_edge", "height_edge", "roundness")


def beam_model(lc: np.ndarray, unshaped: np.ndarray, params: np.ndarray) -> np.ndarray:
    """I₀ · A(width, height, edges, roundness) · unshaped (params = the 5 shape values + I₀)."""
    shape = dict(zip(FIT_KEYS, params[:5], strict=True))
    return params[5] * unshaped * ub.superellipse_shape_np(shape, lc[:, 0], lc[:, 1], lc[:, 2])


def beam_problem(frame: Frame) -> dict[str, Any]:
    """The barn-door fit's data: light coordinates, U, the start (the geometric penumbra), bounds, scales."""
    lum = frame.scene.luminaire
    lc, u = frame.unshaped(lum)
    (ax, ay), h, r = lum.aperture, lum.depth, lum.radius
    p0 = np.array([(ax - r) / h, (ay - r) / h, 2 * r / h, 2 * r / h, 0.3, lum.intensity()])
    lo = np.array([1e-3, 1e-3, 0.0, 0.0, 0.05, 0.1 * p0[5]])
    hi = np.array([2.0, 2.0, 2.0, 2.0, 4.0, 10.0 * p0[5]])
    return {"lc": lc, "u": u, "p0": p0, "bounds": (lo, hi), "x_scale": np.array([0.1, 0.1, 0.1, 0.1, 0.3, p0[5]])}


def beam_residuals_ad(frame: Frame, prob: dict[str, Any]) -> Any:
    """(L_model − L_ref)/peak per receiver in drjit (:func:`beam_model` with
    :func:`~validate.local_models.uberlight.common.superellipse_shape_ad`): a function of the 6 parameters."""
    x, y, z = (adfit.array(prob["lc"][:, k]) for k in range(3))
    u, ref, peak = adfit.array(prob["u"]), adfit.array(frame.radiance), frame.peak

    def residuals(p: list[Any]) -> Any:
        return (p[5] * u * superellipse_shape_ad(*p[:5], x, y, z) - ref) / peak
    return residuals


def fit_beam(frame: Frame, method: str = "ad") -> dict[str, Any]:
    """Least squares of the überlight shape and I₀ to the barn-door render, residuals (L_model − L_ref)/peak over
    every receiver pixel; start: the geometric penumbra. scipy's trust-region reflective method either with its
    finite-difference Jacobian (``method="scipy"``) or with drjit's forward-mode Jacobian (``"ad"``,
    :func:`validate.numerics.adfit.least_squares`; the experiment's path where the variant has AD: it reaches the
    finite-difference fit's RMS to 10⁻¹³ relative, ``python -m validate bench --only fits``)."""
    prob = beam_problem(frame)
    if method == "ad" and adfit.available():
        fit = adfit.least_squares(beam_residuals_ad(frame, prob), prob["p0"], prob["bounds"], prob["x_scale"])
        p = fit.x
    else:
        res = least_squares(lambda q: (beam_model(prob["lc"], prob["u"], q) - frame.radiance) / frame.peak,
                            prob["p0"], bounds=prob["bounds"], x_scale=prob["x_scale"])
        p = res.x
    resid = (beam_model(prob["lc"], prob["u"], p) - frame.radiance) / frame.peak
    return {"shape": dict(zip(FIT_KEYS, map(float, p[:5]), strict=True)), "intensity": float(p[5]),
            "rms_residual": float(np.sqrt(np.mean(resid ** 2))), "start": prob["p0"].tolist(), "params": p.tolist(),
            "method": "ad" if method == "ad" and adfit.available() else "scipy"}


def edge_rms(frame: Frame, params: np.ndarray, fitted: np.ndarray, passes: np.ndarray | None = None
             ) -> tuple[float, float, int]:
    """(edge_rms, uncertainty, band pixels) of the shape ``params`` against the render (module docstring);
    the band and U come from the ``fitted`` parameters."""
    lum = frame.scene.luminaire
    lc, u = frame.unshaped(lum)
    uu = fitted[5] * u
    ok = uu > 0
    a_fit = np.where(ok, beam_model(lc, u, fitted) / np.where(ok, uu, 1.0), 0.0)
    band = ok & (a_fit > 0) & (a_fit < 1)
    a_test = beam_model(lc, u, params)[band] / uu[band]
    a_ref = frame.radiance[band] / uu[band]
    sig = frame.uncertainty[band] / uu[band]
    sq = (a_test - a_ref) ** 2
    ms = float(sq.mean() - (sig ** 2).mean())
    m = math.sqrt(max(ms, 0.0))
    se = float(sq.std(ddof=1) / math.sqrt(len(sq)))
    return m, math.sqrt(m * m + se) - m, int(band.sum())


def segment_fraction(u: np.ndarray) -> np.ndarray:
    """Fraction of a disc of unit radius with x < u: (π − acos u + u√(1 − u²))/π (the straight-edge penumbra)."""
    u = np.clip(u, -1.0, 1.0)
    return (math.pi - np.arccos(u) + u * np.sqrt(1.0 - u * u)) / math.pi


def smoothstep01(t: np.ndarray) -> np.ndarray:
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3 - 2 * t)


def smoothstep_vs_disc() -> dict[str, float]:
    """Best span 2c (in disc radii) of a smoothstep fitted to the straight-edge disc penumbra, its RMS and max
    error over the span (dense 1-D minimisation; a property of the two curves, no rendering)."""
    def rms(c: float) -> float:
        u = np.linspace(-c, c, 20001)
        return float(np.sqrt(np.mean((segment_fraction(u) - smoothstep01((u + c) / (2 * c))) ** 2)))
    c = float(minimize_scalar(rms, bounds=(0.5, 2.0), method="bounded").x)
    u = np.linspace(-c, c, 20001)
    return {"span_over_diameter": c, "rms": rms(c),
            "max": float(np.abs(segment_fraction(u) - smoothstep01((u + c) / (2 * c))).max())}


def error_budget(frame: Frame, fitted: np.ndarray, disc: dict[str, float]) -> dict[str, float]:
    """Claim 2's threshold: the 1-D smoothstep-vs-disc RMS + the penumbra-width change with depth over the band
    (the smoothstep of mean width against ±half the spread of 1 − h/Z) + the Lambertian cos α the überlight lacks:
    half its spread across the band along the principal axes, max_i (cos atan w_i − cos atan(w_i + e_i))/2."""
    lum = frame.scene.luminaire
    lc, u = frame.unshaped(lum)
    uu = fitted[5] * u
    ok = uu > 0
    a_fit = np.where(ok, beam_model(lc, u, fitted) / np.where(ok, uu, 1.0), 0.0)
    band = ok & (a_fit > 0) & (a_fit < 1)
    z = lc[band, 2]
    k = 1.0 - lum.depth / z
    spread = float((k.max() - k.min()) / (k.max() + k.min()))
    t = np.linspace(-1.0, 1.0, 4001)
    depth_term = float(np.sqrt(np.mean((smoothstep01((t + 1) / 2) - smoothstep01((t * (1 + spread) + 1) / 2)) ** 2)))
    def cos_a(t: float) -> float:
        return 1.0 / math.sqrt(1.0 + t * t)
    cos_term = max(cos_a(fitted[i]) - cos_a(fitted[i] + fitted[i + 2]) for i in (0, 1)) / 2.0
    return {"disc_shape": disc["rms"], "depth": depth_term, "cos": cos_term,
            "total": disc["rms"] + depth_term + cos_term, "depth_spread": spread}


# -- falloff -------------------------------------------------------------------------------------------------
def falloff_study(radius: float, radiance: float, d0_values: list[float], alpha: float = 2.0) -> dict[str, Any]:
    """Fore June's falloff with M = π L (the disc's E(0)) and K = I₀/d₀^α, I₀ = π L r², against the exact
    on-axis E(d) of the disc over d ∈ [0, 20 r]: max relative error per d₀, and the best d₀."""
    i0 = math.pi * radiance * radius ** 2
    m = math.pi * radiance
    d = np.linspace(0.0, 20.0 * radius, 2001)
    exact = ur.disc_on_axis_irradiance(d, radiance, radius)

    def err(d0: float) -> float:
        if i0 / d0 ** alpha >= m:
            return float("inf")
        return float(np.max(np.abs(ub.fore_june_falloff(d, i0, d0, alpha, m) / exact - 1.0)))
    rows = {f"{d0 / radius:g}": err(d0) for d0 in d0_values}
    best = minimize_scalar(err, bounds=(radius * 1.0001, 10 * radius), method="bounded")
    inv_sq = np.abs(i0 / np.maximum(d, 1e-12) ** 2 / exact - 1.0)
    return {"radius": radius, "radiance": radiance, "alpha": alpha, "max_intensity": m, "intensity": i0,
            "d0_over_r": rows, "best_d0_over_r": float(best.x / radius), "best_max_rel": float(best.fun),
            "inverse_square_rel_at": {f"{k:g}r": float(np.interp(k * radius, d, inv_sq)) for k in (1, 2, 5, 10)},
            "curve_d_over_r": (d / radius).tolist()[::50], "curve_exact": exact.tolist()[::50],
            "curve_best": ub.fore_june_falloff(d, i0, float(best.x), alpha, m).tolist()[::50]}


def distance_shaping_fit(z: np.ndarray, d: np.ndarray) -> dict[str, Any]:
    """How close the listing's distance shaping (no falloff) comes to 1/d² over the beam's receivers:
    least squares of the relative error K·D(z)·d² − 1 over (K, far, far_edge) with near = near_edge = 0 (a
    cuton only rises, 1/d² only falls); also the best constant K alone (the listing with D = 1)."""
    def rel(p: np.ndarray) -> np.ndarray:
        shape = {"near": 0.0, "near_edge": 0.0, "far": p[1], "far_edge": p[2]}
        return p[0] * ub.distance_shape_np(shape, z) * d ** 2 - 1.0
    zmin, zmax = float(z.min()), float(z.max())
    k0 = 1.0 / float(np.mean(d ** 2))
    res = least_squares(rel, np.array([k0 * 2, zmin, 2 * (zmax - zmin)]),
                        bounds=([0.0, 0.0, 1e-3], [np.inf, zmax, 20 * (zmax - zmin)]))
    k_const = float(np.sum(d ** 2) / np.sum(d ** 4))  # least squares of K d² − 1
    e_const = k_const * d ** 2 - 1.0
    e_fit = rel(res.x)
    return {"depth_range": [zmin, zmax], "K": float(res.x[0]), "far": float(res.x[1]), "far_edge": float(res.x[2]),
            "rms_rel": float(np.sqrt(np.mean(e_fit ** 2))), "max_rel": float(np.abs(e_fit).max()),
            "constant_rms_rel": float(np.sqrt(np.mean(e_const ** 2))),
            "constant_max_rel": float(np.abs(e_const).max()), "constant_K": k_const}


def fore_june_physical(radius: float, radiance: float, alpha: float = 2.0) -> dict[str, Any]:
    """Fore June's falloff with d₀ and M both free (α = 2, K = I₀/d₀²) against the disc's exact on-axis E(d)
    over d ∈ [0, 20 r]: the (d₀/r, M/(πL)) of least max relative error (Nelder–Mead on the max)."""
    from scipy.optimize import minimize

    i0, el = math.pi * radiance * radius ** 2, math.pi * radiance
    d = np.linspace(0.0, 20.0 * radius, 2001)
    exact = ur.disc_on_axis_irradiance(d, radiance, radius)

    def err(p: np.ndarray) -> float:
        d0, mm = p[0] * radius, p[1] * el
        if d0 <= 0 or mm <= i0 / d0 ** alpha:
            return 1e3
        return float(np.max(np.abs(ub.fore_june_falloff(d, i0, d0, alpha, mm) / exact - 1.0)))
    res = minimize(err, np.array([2.8, 1.0]), method="Nelder-Mead", options={"xatol": 1e-4, "fatol": 1e-6})
    return {"d0_over_r": float(res.x[0]), "M_over_piL": float(res.x[1]), "max_rel": float(res.fun)}



INTENSITY = 50.0  # W sr⁻¹ on the axis


PROJECTOR_SHAPE = {"width": 0.35, "height": 0.25, "width_edge": 0.0, "height_edge": 0.0, "roundness": 1.0}


@dataclass
class Measurements:
    settings: Settings
    data: dict[str, Any] = field(default_factory=dict)
    images: Settings = field(default_factory=dict)
    measured: dict[str, dict[str, Measured]] = field(default_factory=dict)


def projector_frame(s: Settings, shape: dict[str, float]) -> tuple[Frame, np.ndarray]:
    scene = us.projector_scene(s.width, s.height, s.fov_deg)
    tex = ur.projector_texture(projector_mask(shape, s.texture, s.fov_deg), INTENSITY, s.fov_deg)
    frame = Frame(scene, ur.render(scene, tex, 1, 2, s.seed))
    return frame, ~edge_footprint(frame, shape, s.texture, s.fov_deg)


def rolled(lum: us.Luminaire, deg: float) -> np.ndarray:
    """The light's axes rolled by ``deg`` about its forward axis (the 1° power check)."""
    axes = lum.frame()
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.stack([c * axes[0] + s * axes[1], -s * axes[0] + c * axes[1], axes[2]])


def fore_june_extra(s: Settings) -> dict[str, float]:
    """Fore June parameters matching the inverse square far field (α = 2) with a 0.5 m near field."""
    return {"d0": 0.5, "alpha": 2.0, "max_intensity": INTENSITY / 0.5 ** 2 * 4.0}


def projector_comparison(s: Settings, m: Measurements) -> None:
    """Every technique against the projector (edge widths 0); power checks for the inverse-square one."""
    frame, keep = projector_frame(s, PROJECTOR_SHAPE)
    lum = frame.scene.luminaire
    base = light_mapping(lum, INTENSITY, PROJECTOR_SHAPE, **fore_june_extra(s))
    out: dict[str, Any] = {"compared_pixels": int(keep.sum()), "edge_pixels": int((~keep).sum()),
                           "lit_pixels": int((frame.radiance > 0).sum()), "peak": frame.peak, "techniques": {}}
    wide = dict(base, width=PROJECTOR_SHAPE["width"] * 1.01)
    roll = dict(base, axes=rolled(lum, 1.0))
    for tech in family:
        call = lambda light, t=tech: family.call(t, light, frame.position, frame.normal, frame.views,  # noqa: E731
                                                 frame.material(), shadow=frame.shadow)
        approx = call(base)
        e = projector_errors(frame, approx, keep)
        pw = projector_errors(frame, call(wide), keep)["max_rel"]
        pr = projector_errors(frame, call(roll), keep)["max_rel"]
        out["techniques"][tech.name] = dict(e, power_width=pw, power_roll=pr)
        m.measured.setdefault(tech.name, {})["projector.max_rel"] = Measured(
            e["max_rel"], e["uncertainty"], pw, "width 1 % too large (one part in 100 of w)", unit="%", stat="max")
        m.measured[tech.name]["projector.mean_rel"] = Measured(e["mean_rel"], e["uncertainty"], unit="%",
                                                                         stat="mean")
        m.measured[tech.name]["projector.scaled_max_rel"] = Measured(e["scaled_max_rel"], e["uncertainty"],
                                                                              unit="%", stat="max")
        m.measured[tech.name]["projector.max_rel.roll"] = Measured(e["max_rel"], e["uncertainty"], pr,
                                                                   "light rolled 1° about its axis", unit="%",
                                                                   stat="max")
        m.images.setdefault("projector", {})[tech.name] = frame.image(approx)
    m.images["projector_ref"] = frame.ref.radiance
    m.data["projector"] = out
    m.data["distance_shaping"] = distance_shaping(frame, keep, base)


def distance_shaping(frame: Frame, keep: np.ndarray, base: dict[str, Any]) -> dict[str, Any]:
    """The listing's cutoff fitted to 1/d² over the lit receivers' depths, then rendered by the listing
    technique (intensity K·I₀, far / far_edge fitted) against the projector."""
    lum = frame.scene.luminaire
    lc, _ = frame.unshaped(lum)
    lit = keep & (frame.radiance > 0)
    d = np.linalg.norm(lc, axis=1)
    fit = distance_shaping_fit(lc[lit, 2], d[lit])
    out: dict[str, Any] = {"fit": fit}
    for label, light in (("fitted_cutoff", dict(base, intensity=INTENSITY * fit["K"], far=fit["far"],
                                                 far_edge=fit["far_edge"])),
                         ("constant", dict(base, intensity=INTENSITY * fit["constant_K"]))):
        approx = family.call("uberlight", light, frame.position, frame.normal, frame.views, frame.material(),
                             shadow=frame.shadow)
        ref = frame.radiance[lit]
        out[label] = {"max_rel_of_value": float(np.max(np.abs(approx[lit] / ref - 1.0))),
                      "rms_rel_of_value": float(np.sqrt(np.mean((approx[lit] / ref - 1.0) ** 2)))}
    return out


def barndoor_frames(ctx: Context, s: Settings) -> list[Frame]:
    def one(config: list[float]) -> ur.UberRender:
        sc = barndoor(s, *config)
        return ur.render(sc, None, s.barndoor_spp, s.barndoor_passes, s.seed)
    configs = [list(c) for c in s.barndoors]
    refs = ctx.map(one, configs, "uberlight: barn-door renders")
    return [Frame(barndoor(s, *c), ref, shadowed=False) for c, ref in zip(configs, refs, strict=True)]


def barndoor(s: Settings, radius: float, roundness: float = 0.0) -> us.UberScene:
    """The barn door with disc radius ``radius`` and aperture roundness ``roundness`` (0: rectangular hole)."""
    return us.barndoor_scene(s.barndoor_width, s.barndoor_height, radius, s.depth, tuple(s.aperture),
                             INTENSITY / (math.pi * radius ** 2), roundness)


def config_key(scene: us.UberScene) -> str:
    """``r0.025`` (rectangular hole) or ``r0.025_rounded0.6``."""
    return scene.name.removeprefix("barndoor_")


def barndoor_fits(frames: list[Frame], m: Measurements) -> None:
    """Fit per size, the edge error of the fit, of the fit with edges × 1.5 and of the hard edge; the budget."""
    disc = smoothstep_vs_disc()
    rows = []
    for f in frames:
        lum = f.scene.luminaire
        fit = fit_beam(f)
        p = np.asarray(fit["params"])
        e, u, n = edge_rms(f, p, p)
        wide = p.copy()
        wide[2:4] *= 1.5
        ew, _, _ = edge_rms(f, wide, p)
        hard = p.copy()
        hard[0:2] += p[2:4] / 2
        hard[2:4] = 0.0
        eh, _, _ = edge_rms(f, hard, p)
        zc = float(np.median(Frame.unshaped(f, lum)[0][:, 2]))
        geo = 2 * lum.radius * (1 - lum.depth / zc) / lum.depth
        rows.append({"key": config_key(f.scene), "radius": lum.radius, "aperture_roundness": lum.aperture_roundness,
                     "depth": lum.depth, "aperture": list(lum.aperture), "fit": fit,
                     "edge_rms": e, "edge_rms_uncertainty": u, "band_pixels": n, "edge_rms_wide": ew,
                     "edge_rms_hard": eh, "budget": error_budget(f, p, disc),
                     "geometric_edge": geo, "predicted_edge": geo * disc["span_over_diameter"],
                     "median_depth": zc})
        m.images.setdefault("barndoor", []).append((config_key(f.scene), f.ref.radiance, f.image(beam_model(
            *f.unshaped(lum), p))))
    m.data["barndoor"] = {"sizes": rows, "smoothstep_vs_disc": disc}


def barndoor_techniques(frames: list[Frame], m: Measurements) -> None:
    """Every technique with the fitted shape against each barn-door render: RMS of (L − L_ref)/peak."""
    for tech in family:
        worst = (0.0, 0.0)
        per: dict[str, Any] = {}
        for f, row in zip(frames, m.data["barndoor"]["sizes"], strict=True):
            light = light_mapping(f.scene.luminaire, row["fit"]["intensity"], row["fit"]["shape"],
                                     **{"d0": 0.5, "alpha": 2.0, "max_intensity": row["fit"]["intensity"] * 16.0})
            approx = family.call(tech, light, f.position, f.normal, f.views, f.material(), shadow=f.shadow)
            d = (approx - f.radiance) / f.peak
            ms = float(np.mean(d ** 2) - np.mean((f.uncertainty / f.peak) ** 2))
            val = math.sqrt(max(ms, 0.0))
            unc = math.sqrt(val * val + float(np.std(d ** 2, ddof=1) / math.sqrt(len(d)))) - val
            per[row["key"]] = {"rms_rel": val, "uncertainty": unc}
            worst = max(worst, (val, unc))
        m.data.setdefault("barndoor_techniques", {})[tech.name] = per
        m.measured.setdefault(tech.name, {})["barndoor.rms_rel"] = Measured(worst[0], worst[1], unit="%", stat="rms")


def sweeps(s: Settings, m: Measurements) -> None:
    """Book Fig. 12.3: roundness and edge-width sweeps, the inverse-square überlight against the projector."""
    out: dict[str, Any] = {"roundness": {}, "edge": {}}
    for key, values in (("roundness", s.roundness_sweep), ("edge", s.edge_sweep)):
        for val in values:
            shape = dict(PROJECTOR_SHAPE, roundness=val) if key == "roundness" else dict(
                PROJECTOR_SHAPE, width_edge=val, height_edge=val)
            frame, keep = projector_frame(s, shape)
            light = light_mapping(frame.scene.luminaire, INTENSITY, shape)
            approx = family.call("uberlight_inverse_square", light, frame.position, frame.normal, frame.views,
                                 frame.material(), shadow=frame.shadow)
            out[key][f"{val:g}"] = projector_errors(frame, approx, keep)
            m.images.setdefault("sweep", []).append((f"{key} {val:g}", frame.ref.radiance, frame.image(approx),
                                                     frame.image((approx - frame.radiance) / frame.peak)))
    m.data["sweeps"] = out


def compute(ctx: Context, s: Settings) -> Measurements:
    """The projector comparison, the barn-door fits and technique errors, the sweeps and the falloff studies."""
    m = Measurements(settings_json(s))
    projector_comparison(s, m)
    frames = barndoor_frames(ctx, s)
    barndoor_fits(frames, m)
    barndoor_techniques(frames, m)
    sweeps(s, m)
    r = frames[0].scene.luminaire
    m.data["falloff"] = {f"r{f.scene.luminaire.radius:g}": falloff_study(
        f.scene.luminaire.radius, f.scene.luminaire.radiance,
        [k * f.scene.luminaire.radius for k in s.d0_over_r]) for f in frames
        if f.scene.luminaire.aperture_roundness == 0}
    m.data["falloff_physical"] = fore_june_physical(r.radius, r.radiance)
    return m
