"""The specular part of ``arealights``, numbers only: the reference (validated against Mitsuba's render), every
``specular_arealight`` technique per configuration × shape × α × σ, the LTC polygon's exactness (the method:
:mod:`validate.experiments.arealights.specular`)."""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from ....errors import ValidateError
from ....local_models import family
from ....local_models.precision import family_precision
from ....local_models.registry import Technique
from ....local_models.specular_arealight.ltc import (
    fit_quadrature,
    ggx_cos,
    load_table,
    local_frames,
    ltc,
    ltc_density,
    ltc_integral,
    ltc_integral_many,
    ltc_many,
)
from ....local_models.specular_arealight.representative_point import representative_point_tube
from ....reference import area_specular_render as asr
from ...base import settings_json
from .settings import SpecularSettings

# (θ_v, θ_l, Δφ) in degrees: overhead, mirror, off-mirror, grazing, side, a light crossing the horizon
CONFIGS = ((0.0, 0.0, 0.0), (40.0, 40.0, 180.0), (40.0, 60.0, 180.0), (70.0, 70.0, 180.0), (70.0, 50.0, 180.0),
           (40.0, 40.0, 90.0), (60.0, 80.0, 180.0))
SHAPES = ("rectangle", "disc", "sphere", "tube")
TUBE_RADIUS = float(np.sin(np.radians(2.0)))  # the tube's radius at unit distance (2° half-angle)
TUBE_AXES = ("across", "along")  # axis ⊥ the plane of incidence, or in it (both ⊥ the direction to the centre)
# per-row variants of the tube technique: name -> (line power, sphere power) of the energy factor
TUBE_VARIANTS = {"no_line": (0.0, 2.0), "line_squared": (2.0, 2.0)}
SIZE_ERROR = 1.01  # power of the exactness claim: the polygon 1 % too large
RENDER_CONFIGS = ((0.0, 0.0, 0.0), (40.0, 40.0, 180.0), (70.0, 50.0, 180.0))  # above the horizon: rendered too
RENDER_SIGMA = 15.0
RENDER_ALPHA = 0.01  # family-wise level of the render-vs-quadrature test
REFERENCE_BIAS = 1.02


def _dir(theta_deg: float, phi_deg: float) -> np.ndarray:
    t, p = np.radians(theta_deg), np.radians(phi_deg)
    return np.array([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)])


def light_for(shape: str, theta_l: float, dphi: float, sigma_deg: float, axis: str = "across") -> dict[str, Any]:
    """The light mapping of one configuration (centre at unit distance, facing the receiver)."""
    d = _dir(theta_l, dphi)
    s = np.radians(sigma_deg)
    base = {"shape": shape, "center": tuple(d), "normal": tuple(-d), "radiance": 1.0}
    if shape == "tube":
        across = np.cross(d, [0.0, 1.0, 0.0]) if abs(d[1]) < 0.99 else np.array([0.0, 0.0, 1.0])
        across /= np.linalg.norm(across)
        ax = across if axis == "across" else np.cross(across, d)
        return {"shape": "tube", "center": tuple(d), "axis": tuple(ax / np.linalg.norm(ax)),
                "length": 2 * float(np.tan(s)), "radius": TUBE_RADIUS, "radiance": 1.0}
    if shape == "sphere":
        return {**base, "radius": float(np.sin(s))}
    if shape == "disc":
        return {**base, "radius": float(np.tan(s))}
    tangent = np.cross(d, [0.0, 1.0, 0.0]) if abs(d[1]) < 0.99 else np.array([1.0, 0.0, 0.0])
    return {**base, "size": (2 * float(np.tan(s)),) * 2, "tangent": tuple(tangent / np.linalg.norm(tangent))}


def _receiver(theta_v: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return np.zeros((1, 3)), np.array([[0.0, 1.0, 0.0]]), _dir(theta_v, 0.0)[None, :]


@lru_cache(maxsize=256)
def misfit(mu_v: float, alpha: float, lookup_alpha: float | None = None) -> float:
    """B/L_e = ∫ |E·D_ltc − f cos| dω of the interpolated table at (μ_v, α) (fine mixture quadrature); cached: it
    depends on (μ_v, α) alone, which every shape, size and light direction of a view share."""
    m_inv, norm, _ = load_table().lookup(alpha if lookup_alpha is None else lookup_alpha, np.array([mu_v]))
    q = fit_quadrature(mu_v, alpha, 48)
    return float(np.sum(q.weights * np.abs(norm[0] * ltc_density(m_inv[0], q.dirs) - ggx_cos(q.dirs, mu_v, alpha))))


def measure_config(shape: str, alpha: float, sigma: float, cfg: tuple[float, float, float], nodes: int,
                   techs: list[Technique], axis: str = "across",
                   reference: tuple[float, float] | None = None,
                   ltc_values: tuple[float | None, float] | None = None) -> dict[str, Any]:
    """Reference and every supporting technique at one configuration; ``reference`` = (L_ref, u_ref) when already
    measured (:func:`references`), else :func:`validate.reference.area_specular_render.reference` here;
    ``ltc_values`` = (the built-in ``ltc`` technique's L, or None to call it here; the α-as-roughness LTC) when
    already measured (:func:`ltc_batch`: the same numbers, bit for bit)."""
    tv, tl, dphi = cfg
    light = light_for(shape, tl, dphi, sigma, axis)
    p, n, v = _receiver(tv)
    if reference is None:
        ref, unc = asr.reference(light, alpha, p, n, v, nodes)
        reference = float(ref[0]), float(unc[0])
    brdf = {"alpha": alpha, "f0": 1.0}
    out: dict[str, Any] = {"theta_v": tv, "theta_l": tl, "dphi": dphi, "ref": reference[0], "unc": reference[1],
                           "techniques": {}}
    for t in techs:
        if shape in tuple(t.meta.get("shapes", SHAPES)):
            if ltc_values is not None and ltc_values[0] is not None and t.fn is ltc:
                out["techniques"][t.name] = ltc_values[0]
            else:
                out["techniques"][t.name] = float(family("specular_arealight").call(t, light, brdf, p, n, v)[0, 1])
    mu = float(np.cos(np.radians(tv)))
    out["bound"] = misfit(mu, alpha)
    if ltc_values is not None:
        out["ltc_alpha_as_roughness"] = ltc_values[1]
    else:
        ff, norm, _ = ltc_integral(light, alpha * alpha, p, n, v)  # r = α instead of √α: the lookup bug
        out["ltc_alpha_as_roughness"] = float(ff[0] * norm[0])
    if shape == "tube":
        out["axis"] = axis
        out["tube_variants"] = {k: float(representative_point_tube(light, brdf, p, n, v, k, lp, sp)[0, 1])
                                for k, (lp, sp) in TUBE_VARIANTS.items()}
    return out


ConfigKey = tuple[str, float, float, tuple[float, float, float], str]  # (shape, α, σ, configuration, axis)


def ltc_batch(keys: list[ConfigKey], techs: list[Technique]) -> dict[ConfigKey, tuple[float | None, float]]:
    """What :func:`measure_config` computes with the LTC at each configuration key — (the built-in ``ltc``
    technique's L (None where ``techs`` lacks it or it does not take the shape), the α-as-roughness LTC
    F(α²)·E(α²)) — in one drjit evaluation per shape (:func:`~validate.local_models.specular_arealight.ltc.ltc_many`
    under the family's precision and output check, :func:`~validate.local_models.specular_arealight.ltc.
    ltc_integral_many`) instead of two per configuration: equal bit for bit (the same float32 operations per
    receiver; checked on every configuration of FULL and QUICK against the per-call path)."""
    fam = family("specular_arealight")
    tech = next((t for t in techs if t.fn is ltc), None)
    out: dict[ConfigKey, tuple[float | None, float]] = {}
    for shape in SHAPES:
        sel = [k for k in keys if k[0] == shape]
        if not sel:
            continue
        lights = [light_for(shape, k[3][1], k[3][2], k[2], k[4]) for k in sel]
        rec = [_receiver(k[3][0]) for k in sel]
        p, n, v = (np.concatenate([r[i] for r in rec]) for i in range(3))
        alphas = [k[1] for k in sel]
        vals: list[float | None] = [None] * len(sel)
        if tech is not None and shape in tuple(tech.meta.get("shapes", SHAPES)):
            try:
                with family_precision(fam.precision):
                    rgb = ltc_many(lights, [{"alpha": a, "f0": 1.0} for a in alphas], p, n, v)
            except ValidateError:
                raise
            except Exception as exc:  # as Family.call words it
                raise ValidateError(f"technique '{tech.name}' ({fam.name}): raised {type(exc).__name__}: {exc}"
                                    ) from None
            vals = [float(x) for x in fam.check(tech.name, rgb, (len(sel), 3))[:, 1]]
        ff, norm, _ = ltc_integral_many(lights, [a * a for a in alphas], p, n, v)  # r = α: the lookup bug
        for k, val, f, e in zip(sel, vals, ff, norm, strict=True):
            out[k] = (val, float(f * e))
    return out


RefKey = ConfigKey


def references(s: SpecularSettings, sigmas: tuple[float, ...] | None = None,
               configs: tuple[tuple[float, float, float], ...] = CONFIGS) -> dict[RefKey, tuple[float, float]]:
    """(L_ref, u_ref) of every shape × α × σ × configuration (× axis for tubes) by
    :func:`validate.reference.area_specular_render.reference_alphas`: per (shape, σ) every configuration's light
    directions once, one ``BSDF.eval`` per α — the numbers :func:`measure_config` computes alone, bit for bit."""
    out: dict[RefKey, tuple[float, float]] = {}
    for shape in SHAPES:
        for sg in s.sigmas_deg if sigmas is None else sigmas:
            keys = [(cfg, ax) for cfg in configs for ax in (TUBE_AXES if shape == "tube" else ("across",))]
            jobs = []
            for cfg, ax in keys:
                p, n, v = _receiver(cfg[0])
                jobs.append((light_for(shape, cfg[1], cfg[2], sg, ax), p[0], n[0], v[0]))
            full, unc = asr.reference_alphas(jobs, tuple(s.alphas), s.nodes)
            for ia, a in enumerate(s.alphas):
                for j, (cfg, ax) in enumerate(keys):
                    out[(shape, a, sg, cfg, ax)] = float(full[ia, j]), float(unc[ia, j])
    return out


def compute(s: SpecularSettings) -> dict[str, Any]:
    """Every configuration × shape × α × σ (JSON-able)."""
    techs = list(family("specular_arealight"))
    refs = references(s)
    keys = [(shape, a, sg, cfg, ax) for shape in SHAPES for a in s.alphas for sg in s.sigmas_deg for cfg in CONFIGS
            for ax in (TUBE_AXES if shape == "tube" else ("across",))]
    ltcs = ltc_batch(keys, techs)
    rows = [{"shape": k[0], "alpha": k[1], "sigma_deg": k[2],
             **measure_config(k[0], k[1], k[2], k[3], s.nodes, techs, k[4], refs[k], ltcs[k])} for k in keys]
    return {"settings": settings_json(s), "rows": rows, "techniques": [t.name for t in techs],
            "exactness": exactness(s.nodes), "render_check": render_check(s, refs)}


def render_check(s: SpecularSettings, refs: dict[RefKey, tuple[float, float]] | None = None) -> list[dict[str, Any]]:
    """The quadrature reference against Mitsuba's own render (direct integrator, MIS) of the same scene: every shape
    × α at σ = 15° and the configurations of RENDER_CONFIGS; z = (render − quadrature)/se. ``refs``: the references
    already measured (:func:`references`; the render's configurations are among them when σ = 15° is)."""
    need = [(sh, a, RENDER_SIGMA, c, "across") for sh in SHAPES for a in s.alphas for c in RENDER_CONFIGS]
    if refs is None or any(k not in refs for k in need):
        refs = references(s, (RENDER_SIGMA,), RENDER_CONFIGS)
    out = []
    for i, (shape, a, cfg) in enumerate((sh, a, c) for sh in SHAPES for a in s.alphas for c in RENDER_CONFIGS):
        light = light_for(shape, cfg[1], cfg[2], RENDER_SIGMA)
        p, n, v = _receiver(cfg[0])
        mean, se = asr.render(light, a, p[0], n[0], v[0], s.render_pixels, s.render_spp, seed=i)
        ref, unc = (np.array([x]) for x in refs[(shape, a, RENDER_SIGMA, cfg, "across")])
        out.append({"shape": shape, "alpha": a, "config": list(cfg), "render": mean, "se": se,
                    "quadrature": float(ref[0]), "quadrature_unc": float(unc[0])})
    return out


def exactness(nodes: int) -> dict[str, float]:
    """LTC closed-form polygon integral vs the quadrature of E·D_ltc over the same rectangle (incl. one crossing the
    horizon; D is integrated over its own support, as Heitz et al. clip M⁻¹P in the cosine's space): max relative
    difference, and the same with the polygon 1 % larger (power)."""
    worst, worst_big = 0.0, 0.0
    tab = load_table()
    for cfg in CONFIGS:
        light = light_for("rectangle", cfg[1], cfg[2], 20.0)
        p, n, v = _receiver(cfg[0])
        mu = float(np.cos(np.radians(cfg[0])))
        m_inv, norm, _ = tab.lookup(0.3, np.array([mu]))
        frame = local_frames(n, v)[0][0]  # rows X, Y, n
        dirs, w = asr.light_directions(light, p[0], nodes)
        local = dirs @ frame.T
        quad = float(np.sum(w * norm[0] * ltc_density(m_inv[0], local)))  # D's own support, as [1] clips in D_o
        closed = float(family("specular_arealight").call("ltc", light, {"alpha": 0.3, "f0": 1.0}, p, n, v)[0, 1])
        big = dict(light, size=tuple(SIZE_ERROR * x for x in light["size"]))
        closed_big = float(family("specular_arealight").call("ltc", big, {"alpha": 0.3, "f0": 1.0}, p, n, v)[0, 1])
        worst = max(worst, abs(closed - quad) / max(quad, 1e-12))
        worst_big = max(worst_big, abs(closed_big - quad) / max(quad, 1e-12))
    return {"max_rel": worst, "max_rel_scaled": worst_big}
