"""``engines`` claims and findings, from the measurements alone.

Claims (each with its power check, a perturbation of the size a real bug would have, that must fail):

* ``engines.<tech>.equals_faces_sh9`` — below Babylon's clamp, the engine's E equals the exact
  SH9 (R&H 2001 eq. 8) of the very faces it received, to a tolerance derived from what the engine does
  differently: three.js's r⁻³ texel weights (|w/Ω − 1| ≤ ρ(N), so |ΔE| ≤ ρ(N) · max|K̃| · Φ with
  K̃(x) = 3/32 + x/2 + 15x²/32 the SH9 kernel, max K̃ = K̃(1) = 17/16, R&H JOSA 2001) plus its
  six-digit constants; Babylon's float32 uniforms and shader arithmetic. Power: the output 1 % bright.
* ``engines.<tech>.bound.max`` / ``.mean`` — where the pipeline is exact (below the clamp), the
  engine obeys SH9's directional bound: error ≤ 3/32 Φ at every normal, ≤ 3.07 % Φ on average
  (R&H 2001; every environment but near_directional, which attains it). Power: band 1's sign flipped.
* ``engines.babylon_polynomial.double_lobe`` — Babylon's spherical-polynomial path equals SH9 with band
  l scaled by A_l/π (1, 2/3, 1/4): ``ConvertCubeMapToSphericalPolynomial`` convolves the harmonics with
  A_l/π and ``SphericalPolynomial.FromHarmonics`` multiplies by A_l Y-constants/π again (1.02333 =
  (2π/3)·0.488603, 0.858086 = (π/4)·1.092548). Power: the lobe applied once (plain SH9).
* ``engines.<tech>.pi_normalisation`` — constant environment: E = πL (∫ max(0, n·ω) dω = π).
  Power: the shader's E/π taken for E.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ...local_models.registry import Technique
from ...metrics.irradiance_error import WORST_CASE_MAX, WORST_CASE_MEAN
from ..base import Claim
from .compute import BABYLON_CLAMP, SCALE_BUG, Settings, engine_techniques, three_weight_error
from ..formatting import pct
from ..techniques import Measured, technique_claims, technique_scope

K_MAX = 17.0 / 16.0  # max over x ∈ [−1, 1] of the SH9 kernel K̃(x) = 3/32 + x/2 + 15x²/32 (at x = 1)
THREE_CONSTANTS = 1e-5  # three.js's six-digit constants: ≤ 3·10⁻⁶ relative per term, Σ|terms| ≤ 3.1 Φ
BABYLON_FLOAT32 = 1e-5  # 17 float32 operations × 2⁻²⁴ × Σ|terms| ≤ 3.1 Φ → 3.1·10⁻⁶ Φ, with a 3× margin
POLYNOMIAL_TOL = 5e-5  # DC constant 0.886277 vs π·0.282095 = 0.886227: 5.6·10⁻⁵ × Φ/4 = 1.4·10⁻⁵ Φ + float32
PI_TOL = 1e-4  # covers that 5.6·10⁻⁵ DC slip and six-digit constants (4·10⁻⁷)
FACE_FLUX_TOL = 2e-3  # measured: worst 1.2·10⁻³ (ict_ennis_256x128, N = 64) over the 29 default environments
ATTAINS_BOUND = "near_directional"


@dataclass
class Measurements:
    settings: Settings
    environments: dict[str, dict[str, Any]]
    sweeps: dict[str, dict[str, Any]] = field(default_factory=dict)
    skipped: list[tuple[str, str]] = field(default_factory=list)
    named: dict[str, str] = field(default_factory=dict)  # role ("grace_probe", "brightest_sun") → env

    @property
    def rho(self) -> float:
        return three_weight_error(self.settings.face_size)




def eligible(m: Measurements, tech: Technique) -> list[str]:
    """Environments where the technique's pipeline is exact: all for three.js, below the clamp for Babylon."""
    return [n for n, r in m.environments.items()
            if tech.name in r["techniques"] and not (tech.meta.get("engine") == "babylon" and r["above_clamp"])]


def tolerance(m: Measurements, tech: Technique, envs: list[str]) -> tuple[float, str] | None:
    """The equality tolerance of an engine path and its derivation, or None (no derived tolerance)."""
    face_err = max((m.environments[e]["face_flux_error"] for e in envs), default=0.0)
    n = m.settings.face_size
    if tech.meta.get("path") == "getIrradianceAt":
        tol = K_MAX * m.rho * (1 + face_err) + THREE_CONSTANTS
        return tol, (f"|ΔE| ≤ ρ(N)·max K̃·Φ: three.js's texel weights 4/r³ normalised to 4π depart from the exact "
                     f"solid angles by ρ({n}) = {m.rho:.3g} at most (computed), max K̃ = K̃(1) = 17/16 for the SH9 "
                     f"kernel 3/32 + x/2 + 15x²/32 (R&H JOSA 2001), faces' flux within {face_err:.2g}, plus 10⁻⁵ "
                     "for six-digit constants (≤ 3·10⁻⁶ relative per term on Σ|terms| ≤ 3.1 Φ)")
    if tech.meta.get("engine") == "babylon" and tech.meta.get("path") == "sh":
        return BABYLON_FLOAT32, ("float32: exact solid angles (atan2 area element, Driscoll 2012) rescaled to 4π in "
                                 "float64; 17 float32 shader operations × 2⁻²⁴ on Σ|terms| ≤ 3.1 Φ ≤ 3.1·10⁻⁶ Φ "
                                 "(3× margin)")
    return None


def equality_claims(m: Measurements) -> list[Claim]:
    claims = []
    for tech in engine_techniques():
        envs = eligible(m, tech)
        tol = tolerance(m, tech, envs) if envs else None
        if tol is None:
            continue
        worst = max(envs, key=lambda e: m.environments[e]["techniques"][tech.name]["faces_deviation"])
        scaled = max(m.environments[e]["techniques"][tech.name]["faces_deviation_scaled"] for e in envs)
        r = m.environments[worst]["techniques"][tech.name]
        claims.append(Claim(
            f"engines.{tech.name}.equals_faces_sh9",
            f"{tech.name} = exact SH9 of the faces it received ({len(envs)} environments below the clamp; "
            f"worst: {worst})", "max |E − E_SH9(faces)| / Φ (worst channel)", tol[0], r["faces_deviation"], 0.0,
            unit="%", source=tol[1]).with_power(f"engine output × {SCALE_BUG} (1 % too bright)", scaled))
    return claims


def bound_claims(m: Measurements) -> list[Claim]:
    claims = []
    for tech in engine_techniques():
        if tech.meta.get("path") not in ("getIrradianceAt", "sh"):
            continue
        envs = [e for e in eligible(m, tech) if e != ATTAINS_BOUND]
        if not envs:
            continue
        for stat, limit, src in (("max", WORST_CASE_MAX, "R&H JOSA 2001: |K̃(x) − max(x, 0)| ≤ 3/32"),
                                 ("mean", WORST_CASE_MEAN, "R&H 2001: directional light mean error 3.07 % Φ")):
            errs = {e: m.environments[e]["techniques"][tech.name]["errors"]["flux_rgb"] for e in envs}
            worst = max(errs, key=lambda e: errs[e][stat])
            flipped = max(m.environments[e]["techniques"][tech.name]["errors_band1_flipped"]["flux_rgb"][stat]
                          for e in envs)
            claims.append(Claim(
                f"engines.{tech.name}.bound.{stat}", f"{tech.name}: {stat} error ≤ {pct(limit)} Φ on every "
                f"environment below the clamp but {ATTAINS_BOUND} (worst: {worst})", f"flux_rgb {stat} (worst channel)",
                limit, errs[worst][stat], errs[worst][f"{stat}_uncertainty"], unit="%", source=src,
            ).with_power("band 1's sign flipped (E(−n) in place of E(n))", flipped))
    return claims


def polynomial_claims(m: Measurements) -> list[Claim]:
    tech = next((t for t in engine_techniques() if t.meta.get("path") == "polynomial"), None)
    envs = [e for e in eligible(m, tech) if "polynomial_double_lobe_deviation" in m.environments[e]] if tech else []
    if not envs:
        return []
    worst = max(envs, key=lambda e: m.environments[e]["polynomial_double_lobe_deviation"])
    fixed = max(m.environments[e]["polynomial_double_lobe_fixed"] for e in envs)
    return [Claim(
        f"engines.{tech.name}.double_lobe",
        f"{tech.name} = SH9 of its faces with band l scaled by A_l/π (1, 2/3, 1/4): the cosine lobe applied "
        f"twice ({len(envs)} environments below the clamp; worst: {worst})",
        "max |E − E_SH9,A²/π(faces)| / Φ", POLYNOMIAL_TOL, m.environments[worst]["polynomial_double_lobe_deviation"],
        0.0, unit="%",
        source=("Babylon.js 9.35 sphericalPolynomial.ts FromHarmonics: x = −1.02333·l11/π with "
                "1.02333 = (2π/3)·0.488603, applied to harmonics ConvertCubeMapToSphericalPolynomial already "
                "scaled by A_l/π; tolerance: its DC constant 0.886277 (π·0.282095 = 0.886227) adds "
                "5.6·10⁻⁵ × Φ/4 = 1.4·10⁻⁵ Φ, float32 ≤ 3.1·10⁻⁶ Φ"),
    ).with_power("the lobe applied once (plain SH9 of the faces)", fixed)]


def pi_claims(m: Measurements) -> list[Claim]:
    r = m.environments.get("constant")
    if r is None:
        return []
    claims = []
    for tech in engine_techniques():
        t = r["techniques"].get(tech.name, {})
        if "pi_normalisation" not in t:
            continue
        claims.append(Claim(
            f"engines.{tech.name}.pi_normalisation", f"{tech.name}: constant environment L gives E = πL",
            "max |E/(πL) − 1|", PI_TOL, t["pi_normalisation"], 0.0, unit="%",
            source=("∫ max(0, n·ω) dω = π; 10⁻⁴ covers six-digit constants (0.886227 = π·0.282095 to 4·10⁻⁷) and "
                    "Babylon's polynomial DC constant 0.886277 (5.6·10⁻⁵)"),
        ).with_power("the shader's E/π taken for E (× π missing)", t["pi_normalisation_unscaled"]))
    return claims


def declared_claims(m: Measurements) -> list[Claim]:
    """Thresholds a technique declares (``<metric>.<stat>``), judged on its worst environment in its scope
    (:func:`.techniques.technique_scope`); power: the
    same with band 1's sign flipped."""
    from ...local_models import irradiance

    claims = []
    for tech in irradiance:
        envs = [e for e in technique_scope(tech, list(m.environments)) if tech.name in m.environments[e]["techniques"]]
        if not tech.thresholds or not envs:
            continue
        measured = {}
        for metric in ("flux_luminance", "flux_rgb", "relative", "peak"):
            for stat in ("mean", "max"):
                vals = [(m.environments[e]["techniques"][tech.name]["errors"][metric], m.environments[e]["techniques"]
                         [tech.name]["errors_band1_flipped"][metric][stat]) for e in envs]
                worst = max(vals, key=lambda v: v[0][stat])
                measured[f"{metric}.{stat}"] = Measured(worst[0][stat], worst[0][f"{stat}_uncertainty"],
                                                        max(v[1] for v in vals), "band 1's sign flipped")
        claims += technique_claims("engines", tech, measured, scope=f"worst over {len(envs)} environment(s)")
    return claims


def face_claims(m: Measurements) -> list[Claim]:
    """The faces handed to the engines carry the map's flux (the input side; needs no Node)."""
    if not m.environments:
        return []
    worst = max(m.environments, key=lambda e: m.environments[e]["face_flux_error"])
    point = max(r["point_sampled_flux_error"] for r in m.environments.values())
    return [Claim(
        "engines.faces.flux", f"cube faces (N = {m.settings.face_size}) keep the lat-long map's flux, every "
        f"environment (worst: {worst})", "max |Φ_faces/Φ − 1| (worst channel)", FACE_FLUX_TOL,
        m.environments[worst]["face_flux_error"], 0.0, unit="%",
        source=("measured margin: worst 1.2·10⁻³ (ict_ennis_256x128) and ≤ 7·10⁻⁴ on the other 28 default "
                "environments at N = 64; the hot texels are splatted with a Gauss–Legendre rule exact to ~10⁻⁶, "
                "the rest is a midpoint rule with sub-texel spacing ≤ the map's row spacing"),
    ).with_power("faces point-sampled at the texel centres (no averaging)", point)]


def claims(m: Measurements) -> list[Claim]:
    return (face_claims(m) + equality_claims(m) + bound_claims(m) + polynomial_claims(m) + pi_claims(m)
            + declared_claims(m))


def _errs(m: Measurements, env: str) -> str:
    r = m.environments[env]["techniques"]
    focus = ["sh9"] + [t.name for t in engine_techniques()]
    fl = {name: r[name]["errors"]["flux_luminance"] for name in focus if name in r}
    return "; ".join(f"{name} {pct(st['mean'])} / {pct(st['max'])}" for name, st in fl.items())


def named_findings(m: Measurements) -> list[str]:
    out = []
    roles: dict[str, list[str]] = {}
    for role, env in m.named.items():
        roles.setdefault(env, []).append(role.replace("_", " "))
    for env, names in roles.items():
        r = m.environments[env]
        out.append(f"{env} ({' and '.join(names)}; largest face texel {r['max_face_texel']:.4g} at N = "
                   f"{r['face_size']}): flux-normalised luminance error mean / max — {_errs(m, env)}.")
    return out


def clamp_findings(m: Measurements) -> list[str]:
    above = [e for e, r in m.environments.items() if r["above_clamp"] and "babylon_sh_unclamped" in r]
    if not above:
        return [f"No face texel exceeds Babylon's clamp ({BABYLON_CLAMP:g}) at N = {m.settings.face_size} on any "
                "environment here, so the clamp changed nothing."]
    out = []
    for e in above:
        r = m.environments[e]
        with_c = r["techniques"].get("babylon_sh", {}).get("errors", {}).get("flux_luminance")
        without = r["babylon_sh_unclamped"]["flux_luminance"]
        if with_c:
            out.append(f"{e}: Babylon's clamp at {BABYLON_CLAMP:g} removes {pct(r['clamp_share'])} of the faces' "
                       f"luminance flux (largest texel {r['max_face_texel']:.4g}); babylon_sh's error is "
                       f"{pct(with_c['mean'])} mean / {pct(with_c['max'])} max with it and {pct(without['mean'])} / "
                       f"{pct(without['max'])} without it.")
    for env, s in m.sweeps.items():
        if any(c > 0 for c in s["clamp_share"]):
            shares = ", ".join(f"N = {n}: {pct(c)}" for n, c in zip(s["sizes"], s["clamp_share"], strict=True))
            out.append(f"{env}: the clamped share depends on the face size ({shares}) — a larger cube puts the sun "
                       "in fewer, brighter texels (Babylon.js PR 13809 notes the same dependence).")
    return out


def polynomial_findings(m: Measurements) -> list[str]:
    tech = next((t for t in engine_techniques() if t.meta.get("path") == "polynomial"), None)
    if tech is None:
        return []
    rows = [(e, r["techniques"][tech.name]["errors"]["flux_luminance"], r["techniques"]["sh9"]["errors"]
             ["flux_luminance"]) for e, r in m.environments.items()
            if tech.name in r["techniques"] and "sh9" in r["techniques"]]
    if not rows:
        return []
    worst = max(rows, key=lambda x: x[1]["max"])
    return [f"Babylon's spherical-polynomial path (useSphericalHarmonics = false) applies the cosine lobe twice: "
            f"bands 1 and 2 come out × 2/3 and × 1/4. Its flux-normalised luminance error reaches "
            f"{pct(worst[1]['mean'])} mean / {pct(worst[1]['max'])} max on {worst[0]} where SH9 has "
            f"{pct(worst[2]['mean'])} / {pct(worst[2]['max'])}; the default path (preScaledHarmonics) is correct."]


def precision_findings(m: Measurements) -> list[str]:
    out = []
    three = [t for t in engine_techniques() if t.meta.get("path") == "getIrradianceAt"]
    for tech in three:
        envs = eligible(m, tech)
        dev = max(m.environments[e]["techniques"][tech.name]["faces_deviation"] for e in envs)
        out.append(f"{tech.name}: its r⁻³ texel weights (solid angle approximated at the texel centre, ρ(N = "
                   f"{m.settings.face_size}) = {m.rho:.3g}) move E by at most {dev:.3g} Φ from the exact SH9 of the "
                   "same faces; Babylon integrates the exact solid angle.")
    half = [(e, r) for e, r in m.environments.items() if "half_finite" in r]
    if half:
        finite = [r["half_deviation"] for _, r in half if r["half_finite"]]
        bad = [e for e, r in half if not r["half_finite"]]
        out.append(f"Half-float faces (HalfFloatType): three.js departs from its float32 result by at most "
                   f"{max(finite, default=0.0):.3g} Φ (half precision 2⁻¹¹ on each texel bounds it by "
                   f"{2.0 ** -11 * K_MAX:.3g} Φ)" + (f"; texels above 65504 overflow to ∞ and the SH is not finite on "
                                                     f"{', '.join(bad)}." if bad else
                                                     "; no face texel exceeded 65504 here."))
    face = max(m.environments.items(), key=lambda kv: kv[1]["face_flux_error"])
    out.append(f"The faces carry the map's flux to within {face[1]['face_flux_error']:.2g} (worst: {face[0]}).")
    out += sh9_findings(m)
    return out


def sh9_findings(m: Measurements) -> list[str]:
    """How far each engine lands from the suite's sh9, and how much of that the faces themselves explain."""
    parts = []
    for t in engine_techniques():
        envs = [e for e in eligible(m, t) if "sh9_deviation" in m.environments[e]["techniques"][t.name]]
        if not envs:
            continue
        worst = max(envs, key=lambda e: m.environments[e]["techniques"][t.name]["sh9_deviation"])
        r = m.environments[worst]
        faces = r.get("faces_vs_sh9")
        extra = f" (the exact SH9 of the same faces is already {faces:.3g} Φ away)" if faces is not None else ""
        parts.append(f"{t.name} {r['techniques'][t.name]['sh9_deviation']:.3g} Φ on {worst}{extra}")
    if not parts:
        return []
    return ["Largest departure from the suite's own sh9 (projection of the lat-long map) below the clamp: "
            + "; ".join(parts) + f". Where the faces explain it, it is the cube's texel size (90°/N = "
            f"{90 / m.settings.face_size:.2g}° at N = {m.settings.face_size}): a small source lands on one texel "
            "centre."]


def findings(m: Measurements) -> list[str]:
    return named_findings(m) + polynomial_findings(m) + clamp_findings(m) + precision_findings(m)


__all__ = ["Measurements", "claims", "findings", "eligible", "pct", "K_MAX", "POLYNOMIAL_TOL", "PI_TOL"]
