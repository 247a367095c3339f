"""The specular part of ``arealights``: every ``specular_arealight`` technique (LTC, Karis's representative point for
spheres and tubes, plug-ins) against Mitsuba's GGX ``roughconductor`` under rectangle, disc, sphere and tube emitters.

Scenes: a receiver at the origin, normal +y; the viewer at θ_v from the normal (azimuth 0); the light's centre
at unit distance in direction (θ_l, Δφ) (Δφ = 180°: the mirror side), its size given by the half-angle σ it
subtends (sphere R = sin σ; disc of radius tan σ and square of side 2 tan σ, both facing the receiver; a tube (capsule)
of radius TUBE_RADIUS = sin 2° and length ℓ = 2 tan σ, its axis perpendicular to the direction of its centre, either
across the plane of incidence or along it — both are measured). GGX α ∈ settings, F = 1 (η = 0, k = 1 in Mitsuba;
f0 = 1 for the techniques), L_e = 1.

Reference: :func:`validate.reference.area_specular_render.reference` (Mitsuba's BSDF.eval integrated over the
emitter, Gauss–Legendre n nodes; ± |L(n) − L(n/2)|), validated first against Mitsuba's rendered radiance
(:func:`~validate.reference.area_specular_render.render`: the same plane, BSDF and area emitter, ``direct``
integrator) by a Šidák-corrected z test that must also reject a 2 % bias.

Metrics (per technique; the luminance channel, F = 1 makes all channels equal):
* ``rel_err.<shape>`` = Σ |L − L_ref| / Σ L_ref over every configuration, α and σ of the shape; also per α
  (``rel_err.<shape>.a<α>``) and per σ (``rel_err.<shape>.s<σ>``); ± Σ u_ref / Σ L_ref;
* ``bound_ratio.<shape>`` (LTC only) = max over configurations of (|L − L_ref| − u_ref) / B with
  B = L_e ∫_{S²} |E·D_ltc − f cos| dω, the misfit of the LTC actually used (table interpolated at (μ_v, α))
  integrated over the whole sphere: by the triangle inequality |∫_light (E·D − f cos)| ≤ B for every light, so
  the ratio is ≤ 1 wherever the polygon integral is exact (theorem; a disc is a 64-gon of equal area).

Tubes (Karis 2013 "Tube lights"): ``representative_point_tube`` (energy (α/α′_line)(α/α′_sphere)²) against its
unnormalised counterpart, and against two variants measured per configuration — the line factor left out
(``no_line``: the sphere's factor only) and the line factor squared (``line_squared``: the segment treated as widening
the lobe in both dimensions) — judged by the same Σ|ΔL|/ΣL.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models import family
from ...local_models.precision import family_precision
from ...local_models.registry import Technique
from ...local_models.specular_arealight.ltc import (
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
from ...local_models.specular_arealight.representative_point import representative_point_tube
from ...reference import area_specular_render as asr
from ...report import plots
from ...stats import sidak_critical
from ..base import Claim, Figure, Section, Table
from ..formatting import col
from ..techniques import Measured, technique_claims, technique_entry
from .settings import NAME, SpecularSettings

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
    return {"settings": s.to_json(), "rows": rows, "techniques": [t.name for t in techs],
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


# -- metrics ---------------------------------------------------------------------------------------
def _rel(rows: list[dict[str, Any]], tech: str, scale: float = 1.0) -> dict[str, float]:
    """Σ |scale·L − L_ref| / Σ L_ref ± Σ u / Σ L_ref over the rows the technique supports."""
    rows = [r for r in rows if tech in r["techniques"]]
    ref = sum(r["ref"] for r in rows)
    return {"value": sum(abs(scale * r["techniques"][tech] - r["ref"]) for r in rows) / ref,
            "uncertainty": sum(r["unc"] for r in rows) / ref}


def technique_metrics(m: dict[str, Any], tech: str) -> dict[str, dict[str, float]]:
    out: dict[str, dict[str, float]] = {}
    s = m["settings"]
    for shape in SHAPES:
        rows = [r for r in m["rows"] if r["shape"] == shape and tech in r["techniques"]]
        if not rows:
            continue
        out[f"rel_err.{shape}"] = _rel(rows, tech)
        for a in s["alphas"]:
            out[f"rel_err.{shape}.a{a:g}"] = _rel([r for r in rows if r["alpha"] == a], tech)
        for sg in s["sigmas_deg"]:
            out[f"rel_err.{shape}.s{sg:g}"] = _rel([r for r in rows if r["sigma_deg"] == sg], tech)
        if shape == "tube":
            for ax in TUBE_AXES:
                out[f"rel_err.tube.{ax}"] = _rel([r for r in rows if r.get("axis") == ax], tech)
        if tech == "ltc":
            out[f"bound_ratio.{shape}"] = {"value": _bound_ratio(rows, "ltc"), "uncertainty": 0.0}
    return out


def _bound_ratio(rows: list[dict[str, Any]], tech: str | None) -> float:
    def val(r: dict[str, Any]) -> float:
        return r["techniques"]["ltc"] if tech else r["ltc_alpha_as_roughness"]
    return max((abs(val(r) - r["ref"]) - r["unc"]) / r["bound"] for r in rows)


def entries(m: dict[str, Any]) -> dict[str, Any]:
    return {t.name: technique_entry(t, measured(m, t.name)) for t in family("specular_arealight")
            if t.name in m["techniques"]}


# -- claims ----------------------------------------------------------------------------------------
BIAS = 1.02
POWER_TEXT = "technique output × 1.02 (a 2 % bias)"


def measured(m: dict[str, Any], tech: str) -> dict[str, Measured]:
    """Every metric of ``tech`` with its perturbed value (output × 1.02) for declared-threshold claims."""
    out = {}
    for k, v in technique_metrics(m, tech).items():
        parts = k.split(".")
        rows = [r for r in m["rows"] if r["shape"] == parts[1]]
        if len(parts) == 3 and parts[2] in TUBE_AXES:
            rows = [r for r in rows if r.get("axis") == parts[2]]
        elif len(parts) == 3:
            key = "alpha" if parts[2].startswith("a") else "sigma_deg"
            rows = [r for r in rows if f"{r[key]:g}" == parts[2][1:]]
        pert = _rel(rows, tech, BIAS)["value"] if parts[0] == "rel_err" else None
        out[k] = Measured(v["value"], v["uncertainty"], pert, POWER_TEXT if pert is not None else "",
                          unit="%" if parts[0] == "rel_err" else "")
    return out


def claims(m: dict[str, Any]) -> list[Claim]:
    return [*_render_claims(m), *_ltc_claims(m), *_rp_claims(m), *tube_claims(m), *_declared_claims(m)]


def _render_claims(m: dict[str, Any]) -> list[Claim]:
    rc = m.get("render_check") or []
    if not rc:
        return []
    crit = sidak_critical(len(rc), RENDER_ALPHA)

    def zmax(bias: float) -> float:
        return max(abs(r["render"] - bias * r["quadrature"]) / math.hypot(r["se"], r["quadrature_unc"]) for r in rc)

    return [Claim(f"{NAME}.specular.reference_vs_render",
                  "the quadrature reference (BSDF.eval over the emitter) agrees with Mitsuba's rendered radiance "
                  f"(direct integrator) for every shape × α × configuration ({len(rc)} tests)", "max |z|", crit,
                  zmax(1.0), 0.0, unit="",
                  source=(f"two-sided z test, Šidák-corrected to family-wise {RENDER_ALPHA:g} over {len(rc)} "
                          "configurations (validate.stats.sidak_critical)"))
            .with_power("quadrature reference × 1.02 (a 2 % bias)", zmax(REFERENCE_BIAS))]


def _declared_claims(m: dict[str, Any]) -> list[Claim]:
    out: list[Claim] = []
    for t in family("specular_arealight"):
        if t.thresholds and t.name in m["techniques"]:
            out += technique_claims(NAME, t, measured(m, t.name), scope="GGX F = 1, every configuration of the shape")
    return out


def _rp_claims(m: dict[str, Any]) -> list[Claim]:
    names = m["techniques"]
    if "representative_point" not in names or "representative_point_unnormalized" not in names:
        return []
    rows = [r for r in m["rows"] if r["shape"] == "sphere"]
    a, b = _rel(rows, "representative_point"), _rel(rows, "representative_point_unnormalized")
    return [Claim(f"{NAME}.specular.representative_point.normalisation",
                  "Karis's (α/α′)² normalisation brings the representative point closer to Mitsuba (sphere lights, "
                  "Σ|ΔL|/ΣL with / without)", "error ratio", 1.0, a["value"] / b["value"], 0.0,
                  source=("Karis 2013 eq. 14: without it the widened highlight carries the whole sphere's power in "
                          "the sharp lobe (energy gain); with it the gain must fall"))
            .with_power("normalisation left out (eq. 14 omitted)", 1.0)]


TUBE = "representative_point_tube"
TUBE_UNNORMALIZED = "representative_point_tube_unnormalized"


def _tube_rel(rows: list[dict[str, Any]], variant: str) -> dict[str, float]:
    """Σ|L − L_ref|/ΣL_ref of the tube technique (``TUBE``, ``TUBE_UNNORMALIZED``) or of one of TUBE_VARIANTS."""
    if variant in TUBE_VARIANTS:
        ref = sum(r["ref"] for r in rows)
        return {"value": sum(abs(r["tube_variants"][variant] - r["ref"]) for r in rows) / ref,
                "uncertainty": sum(r["unc"] for r in rows) / ref}
    return _rel(rows, variant)


def _ratio(a: dict[str, float], b: dict[str, float]) -> tuple[float, float]:
    """a/b ± its first-order bound |a/b| (u_a/a + u_b/b) (the reference's quadrature uncertainty, propagated)."""
    r = a["value"] / b["value"]
    return r, abs(r) * (a["uncertainty"] / max(a["value"], 1e-300) + b["uncertainty"] / max(b["value"], 1e-300))


def tube_claims(m: dict[str, Any]) -> list[Claim]:
    """Karis's tube normalisation: with it vs without; its line factor vs none; α/α′_line vs (α/α′_line)²."""
    rows = [r for r in m["rows"] if r["shape"] == "tube" and TUBE in r["techniques"]]
    if not rows or not all(TUBE_UNNORMALIZED in r["techniques"] for r in rows):
        return []
    ours = _tube_rel(rows, TUBE)
    scope = f"tube lights, {len(rows)} configurations (α × length × geometry × axis), Σ|ΔL|/ΣL"
    out = []
    for cid, other, text, src, power in (
            ("normalisation", TUBE_UNNORMALIZED, "Karis's tube energy normalisation (α/α′_line)(α/α′_sphere)² "
             "brings the representative point closer to Mitsuba", "Karis 2013 eq. 14 and its line form (FlaxEngine "
             "LightingCommon.hlsl AreaLightSpecular): without it the widened highlight carries the whole tube's "
             "power in the sharp lobe", "normalisation left out (both factors)"),
            ("line_normalisation", "no_line", "the line factor α/α′_line improves on the sphere factor (α/α′_sphere)² "
             "alone", "Karis 2013 'Tube lights': the segment widens the lobe along its length, so the sphere's "
             "normalisation alone leaves the length's energy gain", "line factor left out"),
            ("line_not_squared", "line_squared", "the line factor enters once (α/α′_line), not squared as for a "
             "sphere", "Karis 2013 'Tube lights': a segment widens the lobe in one dimension only, so its "
             "normalisation is the square root of the sphere's", "line factor squared (the lobe widened in both "
             "dimensions)")):
        val, unc = _ratio(ours, _tube_rel(rows, other))
        out.append(Claim(f"{NAME}.specular.{TUBE}.{cid}", f"{text} ({scope} with / without)", "error ratio", 1.0,
                         val, unc, source=src).with_power(power, 1.0))
    return out


def _ltc_claims(m: dict[str, Any]) -> list[Claim]:
    e = m["exactness"]
    out = [Claim(f"{NAME}.specular.ltc_polygon_exact",
                 "the LTC polygon integral (clipped form factor of M⁻¹P) equals the quadrature of E·D_ltc over the "
                 "rectangle, including one crossing the horizon", "max relative difference", 1e-3, e["max_rel"], 0.0,
                 unit="%", source=("Heitz et al. 2016 eq. 11 (Lambert/Arvo's polygon form factor, exact) and eq. 3 "
                                   "(the integral of D over P equals that of D_o over M⁻¹P); 10⁻³ allows the "
                                   "Gauss–Legendre quadrature of the sharp transformed lobe"))
           .with_power("rectangle 1 % larger than the light (a size error)", e["max_rel_scaled"])]
    if "ltc" in m["techniques"]:
        for shape in SHAPES:
            rows = [r for r in m["rows"] if r["shape"] == shape]
            out.append(Claim(f"{NAME}.specular.ltc.bound_ratio.{shape}",
                             f"LTC vs Mitsuba ({shape}): every configuration's error is within the LTC's own misfit "
                             "integrated over the sphere", "max (|L − L_ref| − u)/B", 1.0, _bound_ratio(rows, "ltc"),
                             0.0, source=("triangle inequality: |∫_light (E·D − f cos)| ≤ ∫_S² |E·D − f cos| = B "
                                          "(B measured per configuration from the interpolated table)"))
                       .with_power("table looked up at roughness r = α instead of √α (the α/roughness confusion)",
                                   _bound_ratio(rows, None)))
    return out


def findings(m: dict[str, Any]) -> list[str]:
    s = m["settings"]
    out = []
    for t in m["techniques"]:
        d = technique_metrics(m, t)
        for shape in SHAPES:
            if f"rel_err.{shape}" not in d:
                continue
            by_a = ", ".join(f"α = {a:g}: {100 * d[f'rel_err.{shape}.a{a:g}']['value']:.2f} %" for a in s["alphas"])
            by_s = ", ".join(f"σ = {x:g}°: {100 * d[f'rel_err.{shape}.s{x:g}']['value']:.2f} %"
                             for x in s["sigmas_deg"])
            rows = [r for r in m["rows"] if r["shape"] == shape and t in r["techniques"]]
            bias = sum(r["techniques"][t] - r["ref"] for r in rows) / sum(r["ref"] for r in rows)
            out.append(f"{t} under a {shape} light vs Mitsuba roughconductor (GGX, F = 1): Σ|ΔL|/ΣL = "
                       f"{100 * d[f'rel_err.{shape}']['value']:.2f} ± {100 * d[f'rel_err.{shape}']['uncertainty']:.2f} "
                       f"% over {len(rows) // (len(s['alphas']) * len(s['sigmas_deg']))} configurations × "
                       f"{len(s['alphas'])} α × {len(s['sigmas_deg'])} σ "
                       f"(signed Σ ΔL/ΣL = {100 * bias:+.1f} %); by roughness {by_a}; by size {by_s}.")
    rc = m.get("render_check") or []
    if rc:
        z = [abs(r["render"] - r["quadrature"]) / max(r["se"], 1e-300) for r in rc]
        rel = max(r["se"] / r["quadrature"] for r in rc)
        out.insert(0, f"The specular reference (Mitsuba BSDF.eval integrated over the emitter) agrees with Mitsuba's "
                      f"rendered radiance in all {len(rc)} shape × α × configuration checks: max |z| = {max(z):.2f} "
                      f"(render standard errors ≤ {100 * rel:.2f} % of L).")
    out += tube_findings(m)
    t = load_table()
    out.append(f"LTC table ({t.size}×{t.size}, fitted by scripts/fit_ltc.py): fit error ∫|E·D − f cos|/E mean "
               f"{t.l1_error.mean():.3f}, median {np.median(t.l1_error):.3f}, max {t.l1_error.max():.3f} (at grazing "
               "view, mid roughness).")
    return out


def tube_findings(m: dict[str, Any]) -> list[str]:
    """Karis's tube light and its variants vs Mitsuba: by roughness, length and axis orientation."""
    rows = [r for r in m["rows"] if r["shape"] == "tube" and TUBE in r["techniques"]]
    if not rows:
        return []
    s = m["settings"]
    names = [TUBE, *(n for n in (TUBE_UNNORMALIZED,) if n in rows[0]["techniques"]), *TUBE_VARIANTS]
    ref = sum(r["ref"] for r in rows)

    def val(r: dict[str, Any], n: str) -> float:
        return r["tube_variants"][n] if n in TUBE_VARIANTS else r["techniques"][n]

    parts = []
    for n in names:
        signed = sum(val(r, n) - r["ref"] for r in rows) / ref
        by_a = ", ".join(f"{100 * _tube_rel([r for r in rows if r['alpha'] == a], n)['value']:.1f}"
                         for a in s["alphas"])
        by_l = ", ".join(f"{100 * _tube_rel([r for r in rows if r['sigma_deg'] == x], n)['value']:.1f}"
                         for x in s["sigmas_deg"])
        by_ax = ", ".join(f"{ax} {100 * _tube_rel([r for r in rows if r['axis'] == ax], n)['value']:.1f}"
                          for ax in TUBE_AXES)
        parts.append(f"{n}: {100 * _tube_rel(rows, n)['value']:.1f} % (signed {100 * signed:+.1f} %; by α "
                     f"{by_a} %; by length {by_l} %; {by_ax} %)")
    lengths = ", ".join(f"{2 * math.tan(math.radians(x)):.2f}" for x in s["sigmas_deg"])
    p_best, err_best = best_line_power(rows)
    return [f"Tube lights (capsule of radius {TUBE_RADIUS:.3f}, length ℓ = {lengths} at unit distance; α = "
            f"{', '.join(f'{a:g}' for a in s['alphas'])}; {len(rows)} configurations) vs Mitsuba, Σ|ΔL|/ΣL: "
            + "; ".join(parts) + f". Over powers p of the line factor (α/α′_line)^p on a 0.05 grid in [0, 2], "
            f"Σ|ΔL|/ΣL is smallest at p = {p_best:.2f} ({100 * err_best:.1f} %): Karis's p = 1 over-darkens these "
            "tubes on aggregate, p = 0 over-brightens them."]


def best_line_power(rows: list[dict[str, Any]]) -> tuple[float, float]:
    """(p, Σ|ΔL|/ΣL) minimising the error of L(p) = L_no_line · (L_tube / L_no_line)^p — the tube technique with its
    line factor raised to p — over p ∈ {0, 0.05, …, 2} (per row L_tube / L_no_line is the line factor itself)."""
    ref = np.array([r["ref"] for r in rows])
    base = np.array([r["tube_variants"]["no_line"] for r in rows])
    factor = np.array([r["techniques"][TUBE] for r in rows]) / np.maximum(base, 1e-300)
    ps = np.round(np.arange(0.0, 2.0 + 1e-9, 0.05), 2)
    errs = [float(np.sum(np.abs(base * factor ** p - ref)) / ref.sum()) for p in ps]
    i = int(np.argmin(errs))
    return float(ps[i]), errs[i]


def section(m: dict[str, Any], ctx: Any) -> Section:
    s = m["settings"]
    techs = m["techniques"]
    rows = []
    for shape in SHAPES:
        for a in s["alphas"]:
            for sg in s["sigmas_deg"]:
                sel = [r for r in m["rows"] if r["shape"] == shape and r["alpha"] == a and r["sigma_deg"] == sg]
                cells = []
                for t in techs:
                    if t in sel[0]["techniques"]:
                        v = _rel(sel, t)
                        cells.append(f"{100 * v['value']:.2f} ± {100 * v['uncertainty']:.2f} %")
                    else:
                        cells.append("—")
                rows.append([shape, f"{a:g}", f"{sg:g}°", *cells])
    table = Table(["shape", "α (–)", "σ (°)", *(col(t, "%") for t in techs)], rows,
                  "Σ|L − L_ref| / Σ L_ref over the configurations (θ_v, θ_l, Δφ) "
                  f"= {', '.join(str(c) for c in CONFIGS)}; ± the reference quadrature. A tube's σ is the half-angle "
                  f"of its length (ℓ = 2 tan σ; radius {TUBE_RADIUS:.3f}), both axis orientations pooled.")
    rtab = Table(["shape", "α (–)", "(θ_v, θ_l, Δφ) (°)", "Mitsuba render (W/(m²·sr))", "quadrature (W/(m²·sr))",
                  "z (–)"],
                 [[r["shape"], f"{r['alpha']:g}", str(tuple(r["config"])), f"{r['render']:.5f} ± {r['se']:.5f}",
                   f"{r['quadrature']:.5f}", f"{(r['render'] - r['quadrature']) / max(r['se'], 1e-300):+.2f}"]
                  for r in m.get("render_check", [])],
                 f"The reference checked against Mitsuba's render (σ = {RENDER_SIGMA:g}°, direct integrator, "
                 f"{s['render_pixels']}² pixels × {s['render_spp']} spp).")
    p, rel = ctx.figure_path(NAME, "specular_error_vs_alpha.png")
    series = {f"{t} {shape}": [technique_metrics(m, t)[f"rel_err.{shape}.a{a:g}"]["value"] for a in s["alphas"]]
              for t in techs for shape in SHAPES if f"rel_err.{shape}" in technique_metrics(m, t)}
    plots.save_line_plot(p, s["alphas"], series, xlabel="GGX α", ylabel="Σ|ΔL| / ΣL", title="Specular area lights "
                         "vs Mitsuba", logy=True)
    p2, rel2 = ctx.figure_path(NAME, "specular_error_vs_size.png")
    series2 = {f"{t} {shape}": [technique_metrics(m, t)[f"rel_err.{shape}.s{x:g}"]["value"] for x in s["sigmas_deg"]]
               for t in techs for shape in SHAPES if f"rel_err.{shape}" in technique_metrics(m, t)}
    plots.save_line_plot(p2, s["sigmas_deg"], series2, xlabel="light half-angle σ (degrees)", ylabel="Σ|ΔL| / ΣL",
                         title="Specular area lights vs Mitsuba", logy=True)
    return Section("Specular area lights: LTC and representative point vs Mitsuba roughconductor", [
        "GGX (F = 1) under rectangle, disc, sphere and tube (capsule) emitters of half-angle σ at unit distance; "
        "reference = Mitsuba's "
        f"BSDF.eval integrated over the emitter ({s['nodes']} Gauss–Legendre nodes per axis, ± the difference to "
        f"{s['nodes'] // 2}), itself checked against Mitsuba's rendered radiance."],
        figures=[Figure(rel, "error vs roughness", 480), Figure(rel2, "error vs light size", 480)],
        tables=[rtab, table])


__all__ = ["compute", "claims", "findings", "section", "entries", "technique_metrics", "tube_claims",
           "tube_findings"]
