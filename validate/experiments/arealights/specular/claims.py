"""The specular part of ``arealights``: its metrics per technique and its claims (each with a power check)."""

from __future__ import annotations

import math
from typing import Any

from ....local_models import family
from ....stats import sidak_critical
from ...base import Claim
from ...techniques import Measured, technique_claims
from ..settings import NAME
from .compute import REFERENCE_BIAS, RENDER_ALPHA, SHAPES, TUBE_AXES, TUBE_VARIANTS


# -- metrics ---------------------------------------------------------------------------------------
def rel_error(rows: list[dict[str, Any]], tech: str, scale: float = 1.0) -> dict[str, float]:
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
        out[f"rel_err.{shape}"] = rel_error(rows, tech)
        for a in s["alphas"]:
            out[f"rel_err.{shape}.a{a:g}"] = rel_error([r for r in rows if r["alpha"] == a], tech)
        for sg in s["sigmas_deg"]:
            out[f"rel_err.{shape}.s{sg:g}"] = rel_error([r for r in rows if r["sigma_deg"] == sg], tech)
        if shape == "tube":
            for ax in TUBE_AXES:
                out[f"rel_err.tube.{ax}"] = rel_error([r for r in rows if r.get("axis") == ax], tech)
        if tech == "ltc":
            out[f"bound_ratio.{shape}"] = {"value": _bound_ratio(rows, "ltc"), "uncertainty": 0.0}
    return out


def _bound_ratio(rows: list[dict[str, Any]], tech: str | None) -> float:
    def val(r: dict[str, Any]) -> float:
        return r["techniques"]["ltc"] if tech else r["ltc_alpha_as_roughness"]
    return max((abs(val(r) - r["ref"]) - r["unc"]) / r["bound"] for r in rows)



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
        pert = rel_error(rows, tech, BIAS)["value"] if parts[0] == "rel_err" else None
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
    a, b = rel_error(rows, "representative_point"), rel_error(rows, "representative_point_unnormalized")
    return [Claim(f"{NAME}.specular.representative_point.normalisation",
                  "Karis's (α/α′)² normalisation brings the representative point closer to Mitsuba (sphere lights, "
                  "Σ|ΔL|/ΣL with / without)", "error ratio", 1.0, a["value"] / b["value"], 0.0,
                  source=("Karis 2013 eq. 14: without it the widened highlight carries the whole sphere's power in "
                          "the sharp lobe (energy gain); with it the gain must fall"))
            .with_power("normalisation left out (eq. 14 omitted)", 1.0)]


TUBE = "representative_point_tube"
TUBE_UNNORMALIZED = "representative_point_tube_unnormalized"


def tube_rel_error(rows: list[dict[str, Any]], variant: str) -> dict[str, float]:
    """Σ|L − L_ref|/ΣL_ref of the tube technique (``TUBE``, ``TUBE_UNNORMALIZED``) or of one of TUBE_VARIANTS."""
    if variant in TUBE_VARIANTS:
        ref = sum(r["ref"] for r in rows)
        return {"value": sum(abs(r["tube_variants"][variant] - r["ref"]) for r in rows) / ref,
                "uncertainty": sum(r["unc"] for r in rows) / ref}
    return rel_error(rows, variant)


def _ratio(a: dict[str, float], b: dict[str, float]) -> tuple[float, float]:
    """a/b ± its first-order bound |a/b| (u_a/a + u_b/b) (the reference's quadrature uncertainty, propagated)."""
    r = a["value"] / b["value"]
    return r, abs(r) * (a["uncertainty"] / max(a["value"], 1e-300) + b["uncertainty"] / max(b["value"], 1e-300))


def tube_claims(m: dict[str, Any]) -> list[Claim]:
    """Karis's tube normalisation: with it vs without; its line factor vs none; α/α′_line vs (α/α′_line)²."""
    rows = [r for r in m["rows"] if r["shape"] == "tube" and TUBE in r["techniques"]]
    if not rows or not all(TUBE_UNNORMALIZED in r["techniques"] for r in rows):
        return []
    ours = tube_rel_error(rows, TUBE)
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
        val, unc = _ratio(ours, tube_rel_error(rows, other))
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
