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
* ``engines.<tech>.own_faces.equals_faces_sh9`` (three_sh, babylon_sh) — fed from the engine's *own*
  panorama → cube path (:mod:`validate.local_models.irradiance.engines.own_faces`), the engine equals the exact
  SH9 of the faces it made (Babylon's clipped to [0, 4096]), to the tolerances above. Power: the same against
  the suite's texel-averaged faces (faces from the other source).
* ``engines.babylon_sh.own_faces.clamp_lowers_error`` — only where Babylon's own faces exceed 4096: the clamp
  lowers its max error (without − with > 0 beyond both reference uncertainties): its nearest-sampled faces
  over-count a hit sun. Power: the same on the suite's faces. Full run only (``Settings.clamp_claim``: in quick
  the one such environment exceeds the clamp on both face sources, so the power check cannot discriminate).
"""

from __future__ import annotations

from typing import Any

from ...local_models import irradiance
from ...local_models.registry import Technique
from ...metrics.irradiance_error import WORST_CASE_MAX, WORST_CASE_MEAN
from ..base import Claim
from ..formatting import pct
from ..techniques import Measured, technique_claims, technique_scope
from .compute import SCALE_BUG, Measurements, engine_techniques

K_MAX = 17.0 / 16.0  # max over x ∈ [−1, 1] of the SH9 kernel K̃(x) = 3/32 + x/2 + 15x²/32 (at x = 1)
THREE_CONSTANTS = 1e-5  # three.js's six-digit constants: ≤ 3·10⁻⁶ relative per term, Σ|terms| ≤ 3.1 Φ
BABYLON_FLOAT32 = 1e-5  # 17 float32 operations × 2⁻²⁴ × Σ|terms| ≤ 3.1 Φ → 3.1·10⁻⁶ Φ, with a 3× margin
POLYNOMIAL_TOL = 5e-5  # DC constant 0.886277 vs π·0.282095 = 0.886227: 5.6·10⁻⁵ × Φ/4 = 1.4·10⁻⁵ Φ + float32
PI_TOL = 1e-4  # covers that 5.6·10⁻⁵ DC slip and six-digit constants (4·10⁻⁷)
FACE_FLUX_TOL = 2e-3  # measured: worst 1.2·10⁻³ (ict_ennis_256x128, N = 64) over the 29 default environments
ATTAINS_BOUND = "near_directional"


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
                                                        max(v[1] for v in vals), "band 1's sign flipped",
                                                        unit="%", stat=stat)
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


def _own(m: Measurements, tech: Technique) -> dict[str, dict[str, Any]]:
    return {e: r["own_faces"][tech.name] for e, r in m.environments.items() if tech.name in r.get("own_faces", {})}


def own_faces_claims(m: Measurements) -> list[Claim]:
    """Issue 21 item 5: each engine fed from its *own* panorama → cube path. The engine equals the exact SH9 of
    the faces it made itself (Babylon's clipped to [0, 4096], its clamp), to the tolerance of
    :func:`tolerance`; power: the same against the suite's texel-averaged faces (faces from the other source),
    which must fail — so the face source is measurable. For Babylon, where its own faces exceed 4096 on some
    environment, :func:`clamp_bias_claims`."""
    out = []
    for tech in engine_techniques():
        own = _own(m, tech)
        if not own:
            continue
        babylon = tech.meta.get("engine") == "babylon"
        worst = max(own, key=lambda e: own[e]["faces_deviation"])
        face_err = max(r["face_flux_error"] for r in own.values())
        if babylon:
            tol, src = BABYLON_FLOAT32, ("float32 shader arithmetic (17 operations × 2⁻²⁴ on Σ|terms| ≤ 3.1 Φ, 3× "
                                         "margin); exact SH9 of Babylon's own faces clipped per channel to [0, 4096] "
                                         "as Clamp(v, 0, MAX_HDRI_VALUE) does")
        else:
            tol = K_MAX * m.rho * (1 + face_err) + THREE_CONSTANTS
            src = (f"|ΔE| ≤ ρ(N)·max K̃·Φ_faces + 10⁻⁵: ρ({m.settings.face_size}) = {m.rho:.3g} (three.js's 4/r³ "
                   f"weights vs exact solid angles), max K̃ = 17/16 (R&H JOSA 2001), its own faces' flux within "
                   f"{face_err:.2g} of the map's")
        out.append(Claim(
            f"engines.{tech.name}.own_faces.equals_faces_sh9",
            f"{tech.name} fed from its own panorama → cube path = exact SH9 of those faces"
            f"{' (clamped at 4096)' if babylon else ''} ({len(own)} environments; worst: {worst})",
            "max |E − E_SH9(own faces)| / Φ (worst channel)", tol, own[worst]["faces_deviation"], 0.0, unit="%",
            source=src).with_power("faces from the other source (the suite's texel-averaged faces)",
                                   max(r["suite_faces_deviation"] for r in own.values())))
        if babylon and m.settings.clamp_claim:
            out += clamp_bias_claims(m, tech, own)
    return out


def clamp_bias_claims(m: Measurements, tech: Technique, own: dict[str, dict[str, Any]]) -> list[Claim]:
    """Where Babylon's own faces exceed 4096: its max flux-normalised luminance error without the clamp minus with
    it exceeds 0, beyond the two errors' reference uncertainties, on every such environment — nearest sampling
    gives a sun texel the radiance of the one pixel it hit over the texel's whole solid angle, so the faces
    over-count the sun's flux and the clamp takes flux away. Power: the same difference on the suite's
    texel-averaged faces (clamp and no clamp), on the same environments."""
    above = [e for e, r in own.items() if r["above_clamp"]]
    if not above:
        return []

    def gain(clamped: dict, free: dict) -> tuple[float, float]:
        a, b = clamped["flux_luminance"], free["flux_luminance"]
        return b["max"] - a["max"], a["max_uncertainty"] + b["max_uncertainty"]

    gains = {e: gain(own[e]["errors"], own[e]["errors_unclamped"]) for e in above}
    worst = min(gains, key=lambda e: gains[e][0] - gains[e][1])
    over = min(own[e]["face_flux_error"] for e in above)
    claim = Claim(
        f"engines.{tech.name}.own_faces.clamp_lowers_error",
        f"Babylon's own faces exceed its 4096 clamp on {len(above)} environment(s) ({', '.join(above)}); there the "
        f"clamp lowers {tech.name}'s max error (least: {worst})",
        "max error without the clamp − with it (flux_luminance, least over those environments)", 0.0,
        gains[worst][0], gains[worst][1], comparison=">", unit="%",
        source=("sign test: nearest-sampled faces over-count a hit sun's flux (their flux error is ≥ "
                f"{over:.2g} on these environments, measured) and the clamp "
                "(CubeMapToSphericalPolynomialTools.MAX_HDRI_VALUE = 4096) removes flux; the difference must clear "
                "0 by more than the two errors' reference uncertainties"))
    suite = {e: gain(m.environments[e]["techniques"][tech.name]["errors"], m.environments[e]["babylon_sh_unclamped"])
             for e in above if "babylon_sh_unclamped" in m.environments[e]}
    if suite:
        ws = min(suite, key=lambda e: suite[e][0] - suite[e][1])
        claim = claim.with_power("the same on the suite's texel-averaged faces (the other face source)",
                                 suite[ws][0], suite[ws][1])
    return [claim]


def claims(m: Measurements) -> list[Claim]:
    if m.unavailable is not None:  # only the faces were measured
        return face_claims(m)
    return (face_claims(m) + equality_claims(m) + bound_claims(m) + polynomial_claims(m) + pi_claims(m)
            + declared_claims(m) + own_faces_claims(m))


__all__ = ["claims", "eligible", "pct", "K_MAX", "POLYNOMIAL_TOL", "PI_TOL"]
