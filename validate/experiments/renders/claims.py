"""Claims of the ``renders`` experiment, each with its source and a power check.

Per-engine facts are the registered engines' (:mod:`validate.local_models.render.registry`): a known defect an
engine states for a topic (:func:`defect`) is claimed as the regression it keeps, its power check the corrected
behaviour; an engine stating none is claimed against the truth. Nothing here names an engine.

(c) Lambertian sphere under a directional light, per engine: the fraction of judged pixels whose three
channels pass the Šidák-corrected z-test (α = 0.01) is ≥ 99.75 % — Mitsuba's acceptance rule for its own
renders (:mod:`validate.metrics.pixel_z` [2]). Power: the engine image × 1.02 (the light intensity × 1.02;
radiance is linear in intensity) must fail, and so must the image × π (E taken for E/π, the classic
units bug of KHR_lights_punctual ports).

(a) Furnace energy, per engine: over the three roughnesses and both materials, the largest |mean
radiance − 1| over the judged pixels is below ``FURNACE_ENERGY_TOL``. Source: energy conservation of a
white non-absorbing surface in a radiance-1 furnace (exactly 1), with the engines' half-float storage
budget: 2 lookups × 2⁻¹¹ + SwiftShader trig 2e-4 = 1.2e-3, rounded up to 0.2 % for the DFG/BRDF LUT
(three: a 16-bit float 2D LUT; Babylon: a 16-bit environment BRDF texture), i.e. 2 × 2⁻¹¹ more.
Power: the same claim on the glTF single-scattering metal (Mitsuba ``roughconductor``, the engine
model with its multiscatter term removed) must fail.

(c) Point and spot lights in KHR_lights_punctual units, per engine and scene: the same ≥ 99.75 % rule against
Mitsuba's ``point`` / ``spot`` (intensity in candela read as W/sr). Power (point): the intensity in lumens taken
for candela — the engine image × 4π (Φ = 4π I for a point light) — must fail, else × 1/π. Spot: each engine is
judged against the falloff profile it implements (its engine's ``facts["spot_reference"]``: Babylon's
FALLOFF_GLTF is KHR's reference formula, three.js's getSpotAttenuation is smoothstep); power: the same image against
that profile with the outer cone 1° wider (a cone falloff off by a degree). three.js's difference from KHR's
reference formula is stated as the regression it has (its ``defects["spot.khr_falloff"]``); its power check is
three.js with the KHR profile (its image × f_KHR/f_smoothstep per pixel), which must be accepted.

(f) Hemisphere light, per engine: the same rule against Mitsuba's two-value environment (sky radiance above the
horizon, ground below). Power: the light's colour read as radiance where it is irradiance (or the reverse) —
the engine image × 1/π — must fail.

(b) Probe, per engine: the Lambertian sphere under the probe (the diffuse-dominated limit) returns Mitsuba's mean
radiance to ``PROBE_DIFFUSE_TOL`` = 1 % (R&H 2001's average error of order-2 SH irradiance); power: image × 1.02.
Babylon's diffuse IBL of the probe is stated as the regression it has (its ``defects["probe_lambert"]``; power: three's
image, within the bound). White metal at roughness 0.25 and 0.5 (three issues
17911/26796, PR 32311): the contrast ratio std_px(engine)/std_px(truth) is stated as the regression each engine has
(below 1: blurrier than glTF's GGX path-traced); power: the path tracer's own image as the engine (c = 1).

(d) Rectangular area light, three.js and Babylon.js (Babylon's shader with Heitz's tables, its engine's ``notes``):
per scene the regression each keeps (its ``defects[<scene>]``; power: the corrected behaviour — the truth on three's
plane, which it leaves dark, else the image × exact/clipped-sphere form factor) and, where the image is not dark, the
units claim (three issue 19214; Babylon's photometric scale 1 for area lights) — with its form factor approximation
divided out, the pixels where the rectangle is wholly above the horizon equal Mitsuba's area emitter of radiance =
intensity (≥ 99.75 %); power: × 1.02, else the intensity read as lumens (image × 1/(πA)).
"""

from __future__ import annotations

import numpy as np

from ...local_models.render import registry
from ...local_models.render.hosted import LTC_CLIPPED_SPHERE
from ...metrics.pixel_z import MIN_ACCEPTED, judge
from ..base import Claim
from . import kinds as K
from .compute import EngineResult, Measurements, SceneResult, budget, with_readback
from .kinds import SceneKind

FURNACE_ENERGY_TOL = 2e-3


def _scene(m: Measurements, kind: SceneKind) -> list[SceneResult]:
    return [s for s in m.scenes if s.kind is kind]


def defect(name: str, topic: str) -> str | None:
    """The known defect the engine ``name`` states for ``topic`` (its ``defects``), or None (none, or no such
    registered engine): a topic stated is claimed as the regression the engine keeps."""
    e = registry.find(name)
    return e.defects.get(topic) if e is not None else None


def fact(name: str, key: str, default: str) -> str:
    """A fact the engine ``name`` states (its ``facts``), else ``default``."""
    e = registry.find(name)
    return e.facts.get(key, default) if e is not None else default


def directional_claims(m: Measurements) -> list[Claim]:
    out = []
    for sr in _scene(m, K.DIRECTIONAL):
        ref_m = sr.references["mitsuba"]
        for name, er in sr.engines.items():
            j = er.judgements["mitsuba"]
            b, text = budget(K.DIRECTIONAL, ref_m)
            c = Claim(f"renders.{name}.lambert_directional.accepted",
                      f"{name}: Lambertian sphere under a {m.settings.sun_lux:g} lux directional light equals Mitsuba "
                      f"per pixel (budget {text})", "fraction of pixels accepted (Šidák α = 0.01)", MIN_ACCEPTED,
                      j.fraction_accepted, 0.0, ">", "%",
                      "Mitsuba 3 render tests: ≥ 99.75 % of pixels pass the Šidák-corrected z-test at α = 0.01")
            se, dof = with_readback(_stderr(sr), er), m.settings.passes - 1
            p102 = judge(er.image * 1.02, ref_m, se, dof, sr.mask, b, text).fraction_accepted
            ppi = judge(er.image * np.pi, ref_m, se, dof, sr.mask, b, text).fraction_accepted
            c.with_power("light intensity × 1.02 (engine image × 1.02)", p102)
            if c.power is not None and not c.power.fails:
                c.with_power("E taken for E/π (engine image × π)", ppi)
            out.append(c)
    return out


def _stderr(sr: SceneResult) -> np.ndarray:
    return sr.stderrs["mitsuba"]


# Engines that keep a furnace defect (their ``defects["furnace"]``, measurements in their modules), stated as the
# regression they have (issue 21 item 4): the claim passes while the engine keeps it, and its power check is the
# corrected behaviour (an energy-conserving engine).


def _furnace_claim(m: Measurements, name: str, dev: list[float], others: list[float]) -> Claim:
    rough = ", ".join(f"{r:g}" for r in m.settings.furnace_roughness)
    source = ("energy conservation (white, non-absorbing, convex: exactly 1); budget 2 half-float lookups + "
              "BRDF LUT (4·2⁻¹¹) + SwiftShader trig 2e-4 ≈ 2e-3")
    known = defect(name, "furnace")
    if known is not None:
        c = Claim(f"renders.{name}.furnace.regression", f"{name} keeps a known defect: "
                  f"{known} (roughness {rough})", "max over scenes of |mean radiance − 1|",
                  FURNACE_ENERGY_TOL, max(dev), 0.0, ">", "", source + "; beyond it the engine loses or adds energy")
        return c.with_power("corrected engine behaviour: an energy-conserving engine (the best other engine "
                            "measured here)", min(others) if others else 0.0, 0.0)
    c = Claim(f"renders.{name}.furnace.energy", f"{name}: white spheres (dielectric and metal, roughness "
              f"{rough}) in the white furnace return radiance 1",
              "max over scenes of |mean radiance − 1|", FURNACE_ENERGY_TOL, max(dev), 0.0, "<", "", source)
    metal = [s.reference_energy["model"] for s in _scene(m, K.FURNACE) if "model" in s.reference_energy]
    worst = max(metal, key=lambda v: abs(v[0] - 1.0)) if metal else (float("nan"), 0.0)
    return c.with_power("multiscatter removed: glTF single-scattering metal (Mitsuba roughconductor)",
                        abs(worst[0] - 1.0), worst[1])


def furnace_claims(m: Measurements) -> list[Claim]:
    scenes = _scene(m, K.FURNACE)
    engines = sorted({e for s in scenes for e in s.engines})
    dev = {e: [abs(s.engines[e].energy - 1.0) for s in scenes if e in s.engines] for e in engines}
    return [_furnace_claim(m, e, dev[e], [max(d) for o, d in dev.items()
                                          if o != e and defect(o, "furnace") is None]) for e in engines]


# The spot profile each engine implements, from its shader source: the reference it is judged against is its
# ``facts["spot_reference"]`` ("smoothstep": three.js 0.187's getSpotAttenuation), else KHR's reference ("mitsuba":
# Babylon 9.35 FALLOFF_GLTF, Filament 1.53 getAngleAttenuation); a difference from KHR's is its
# ``defects["spot.khr_falloff"]``.
RULE = "Mitsuba 3 render tests: ≥ 99.75 % of pixels pass the Šidák-corrected z-test at α = 0.01"
METRIC = "fraction of pixels accepted (Šidák α = 0.01)"


def _accepted(sr: SceneResult, name: str, kind: str, what: str) -> Claim:
    j = sr.engines[name].judgements[kind]
    _, text = budget(sr.kind, sr.references[kind])
    return Claim(f"renders.{name}.{sr.scene.name}.accepted", f"{name}: {what} equals Mitsuba per pixel (budget {text})",
                 METRIC, MIN_ACCEPTED, j.fraction_accepted, 0.0, ">", "%", RULE)


def _fraction(sr: SceneResult, image: np.ndarray, mean: np.ndarray, se: np.ndarray) -> float:
    b, text = budget(sr.kind, mean)
    return judge(image, mean, se, sr.dof, sr.mask, b, text).fraction_accepted


def point_claims(m: Measurements) -> list[Claim]:
    out = []
    for sr in _scene(m, K.POINT):
        ref, s_ref = sr.references["mitsuba"], sr.stderrs["mitsuba"]
        li = sr.scene.lights[0]
        for name, er in sr.engines.items():
            se = with_readback(s_ref, er)
            c = _accepted(sr, name, "mitsuba", f"Lambertian {sr.scene.geometry} under a {li.intensity:g} cd point "
                                                  "light (KHR_lights_punctual, inverse square, no range)")
            c.with_power("intensity in lumens taken for candela (engine image × 4π)",
                         _fraction(sr, er.image * 4 * np.pi, ref, se))
            if c.power is not None and not c.power.fails:
                c.with_power("E/π units slip (engine image × 1/π)", _fraction(sr, er.image / np.pi, ref, se))
            out.append(c)
    return out


def spot_claims(m: Measurements) -> list[Claim]:
    out = []
    for sr in _scene(m, K.SPOT):
        li = sr.scene.lights[0]
        for name, er in sr.engines.items():
            kind = fact(name, "spot_reference", "mitsuba")
            profile = "smoothstep" if kind == "smoothstep" else "gltf"
            c = _accepted(sr, name, kind, f"Lambertian plane under a {li.intensity:g} cd spot light (cone "
                                             f"{li.inner_deg:g}°/{li.outer_deg:g}°, {profile} falloff)")
            label = next(k for k in sr.power_refs if k.startswith(profile))
            p_mean, p_se = sr.power_refs[label]
            c.with_power(f"cone falloff off by a degree: Mitsuba {label}",
                         _fraction(sr, er.image, p_mean, with_readback(p_se, er)))
            out.append(c)
            if defect(name, "spot.khr_falloff") is not None:
                out.append(_spot_regression(sr, name))
    return out


def _spot_regression(sr: SceneResult, name: str) -> Claim:
    er, ref = sr.engines[name], sr.references["mitsuba"]
    se = with_readback(sr.stderrs["mitsuba"], er)
    c = Claim(f"renders.{name}.{sr.scene.name}.khr_falloff.regression", f"{name} keeps a known difference: "
              f"{defect(name, 'spot.khr_falloff')}", METRIC + " against the KHR reference falloff", MIN_ACCEPTED,
              er.judgements["mitsuba"].fraction_accepted, 0.0, "<", "%",
              RULE + "; below it the engine's penumbra is not KHR's")
    smooth = sr.references[fact(name, "spot_reference", "mitsuba")]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(smooth > 0, ref / np.where(smooth > 0, smooth, 1.0), 0.0)
    return c.with_power("corrected engine behaviour: the engine's image × f_KHR/f_smoothstep per pixel",
                        _fraction(sr, er.image * ratio, ref, se))


def hemisphere_claims(m: Measurements) -> list[Claim]:
    out = []
    for sr in _scene(m, K.HEMISPHERE):
        ref, se = sr.references["mitsuba"], sr.stderrs["mitsuba"]
        for name, er in sr.engines.items():
            c = _accepted(sr, name, "mitsuba", "Lambertian sphere under a hemisphere light (sky / ground radiance)")
            out.append(c.with_power("colour read as irradiance where it is radiance (engine image × 1/π)",
                                    _fraction(sr, er.image / np.pi, ref, se)))
    return out


# The diffuse-dominated limit's bound: Ramamoorthi & Hanrahan 2001 (SIGGRAPH, §4) — order-2 SH irradiance, the
# coarsest diffuse IBL in real-time use, averages under 1 % error on natural probes — so an engine's diffuse IBL of a
# probe is held to |mean engine / mean Mitsuba − 1| < 1 % over the judged pixels.
PROBE_DIFFUSE_TOL = 0.01
PROBE_DIFFUSE_SOURCE = ("Ramamoorthi & Hanrahan 2001 §4: order-2 SH irradiance averages < 1 % error on natural probes "
                        "(the coarsest diffuse IBL in real-time use)")


def _energy_ratio(sr: SceneResult, image: np.ndarray) -> tuple[float, float]:
    """mean engine / mean Mitsuba over the judged pixels, ± the reference's standard error of its mean."""
    ref_mean, ref_se = sr.reference_energy["mitsuba"]
    r = float(image[sr.mask].mean()) / ref_mean
    return r, r * ref_se / ref_mean


def probe_lambert_claims(m: Measurements) -> list[Claim]:
    """(b) the diffuse-dominated limit: the Lambertian sphere under the probe, per engine."""
    out = []
    for sr in _scene(m, K.PROBE_LAMBERT):
        for name, er in sr.engines.items():
            if defect(name, "probe_lambert") is not None:
                out.append(_probe_lambert_regression(sr, name))
                continue
            r, u = _energy_ratio(sr, er.image)
            c = Claim(f"renders.{name}.probe_lambert.energy", f"{name}: the Lambertian sphere under the probe "
                      f"({m.probe_note}) returns Mitsuba's mean radiance", "|mean engine / mean Mitsuba − 1|",
                      PROBE_DIFFUSE_TOL, abs(r - 1.0), u, "<", "%", PROBE_DIFFUSE_SOURCE)
            r2, u2 = _energy_ratio(sr, er.image * 1.02)
            out.append(c.with_power("probe radiance × 1.02 (engine image × 1.02)", abs(r2 - 1.0), u2))
    return out


# Engines whose diffuse IBL keeps a known difference from the exact irradiance (``defects["probe_lambert"]``), stated
# as the regression they have: the claim passes while the engine keeps it; power = the corrected behaviour (the image
# of the engine its ``facts["probe_lambert.corrected_by"]`` names, within the bound; else the truth).


def _probe_lambert_regression(sr: SceneResult, name: str) -> Claim:
    what, fixed = defect(name, "probe_lambert"), fact(name, "probe_lambert.corrected_by", "truth")
    r, u = _energy_ratio(sr, sr.engines[name].image)
    c = Claim(f"renders.{name}.probe_lambert.regression", f"{name} keeps a known difference: {what}",
              "|mean engine / mean Mitsuba − 1|", PROBE_DIFFUSE_TOL, abs(r - 1.0), u, ">", "%",
              PROBE_DIFFUSE_SOURCE + "; beyond it the engine's diffuse IBL is not the probe's irradiance")
    if fixed not in sr.engines:  # the corrected engine was not rendered: the power is the perfect engine (truth)
        return c.with_power("corrected engine behaviour: the truth itself", 0.0, u)
    rf, uf = _energy_ratio(sr, sr.engines[fixed].image)
    return c.with_power(f"corrected engine behaviour: {fixed}'s image", abs(rf - 1.0), uf)


# three issues 17911 / 26796 ("rough reflections too shiny", roughness 0.2–0.3) and PR 32311 ("PMREM blur too crisp
# at middle roughness"): the contrast ratio c = std_px(engine)/std_px(truth) (compute.contrast_ratio) on the white
# metal under the probe against glTF's GGX (reference (i)). c = 1 ± σ for an engine with the path tracer's blur.
SHARPNESS_ROUGHNESS = (0.25, 0.5)


def sharpness_claims(m: Measurements) -> list[Claim]:
    from .compute import contrast_ratio

    out = []
    for sr in (s for s in _scene(m, K.PROBE) if s.scene.material.roughness in SHARPNESS_ROUGHNESS):
        ref, se, r = sr.references["mitsuba"], sr.stderrs["mitsuba"], sr.scene.material.roughness
        for name, er in sr.engines.items():
            cv, cu = contrast_ratio(er.image, ref, se, sr.mask, m.settings.seed)
            blurrier = cv < 1.0
            c = Claim(f"renders.{name}.{sr.scene.name}.contrast.regression",
                      f"{name} keeps a known difference: its roughness-{r:g} white metal under the probe is "
                      f"{'blurrier' if blurrier else 'crisper'} than glTF's GGX path-traced (contrast ratio "
                      f"{'below' if blurrier else 'above'} 1; three 17911/26796, PR 32311)",
                      "contrast ratio std_px(engine)/std_px(truth)", 1.0, cv, cu, "<" if blurrier else ">", "",
                      "an engine with the path tracer's blur has c = 1 within the stated uncertainty (parametric "
                      "redraws of the reference noise)")
            own, ou = contrast_ratio(ref, ref, se, sr.mask, m.settings.seed)
            out.append(c.with_power("corrected engine behaviour: the path tracer's own image as the engine",
                                    own, ou))
    return out


# (d) the known differences of an engine's RectAreaLight from the exact Lambertian integral, each stated as the
# regression it has (power: the corrected behaviour): its ``defects[<scene>]`` (three.js r187 and Babylon 9.35: the
# clipped-sphere form factor, :data:`validate.local_models.render.hosted.LTC_CLIPPED_SPHERE`, unless stated
# otherwise); a defect whose corrected behaviour is the truth itself (three's dark plane: the image is 0) says so in
# ``facts["<scene>.corrected_by"]``; where the light's unit is stated: ``facts["rect_units"]``.


def _rect_fraction(sr: SceneResult, image: np.ndarray, mask: np.ndarray) -> float:
    ref, se = sr.references["mitsuba"], sr.stderrs["mitsuba"]
    b, text = budget(sr.kind, ref)
    return judge(image, ref, se, sr.dof, mask, b, text).fraction_accepted


def _rect_engine(name: str, er: EngineResult) -> str:
    """The engine's name with the substitution it was rendered with (its engine's ``notes``), if any."""
    note = er.info.get("note")
    return f"{name} ({note})" if note else name


def rect_claims(m: Measurements) -> list[Claim]:
    """(d) per scene and engine: the regression it keeps; where its image is not 0, its units (three issue 19214,
    Babylon's photometric scale: nits, not lumens)."""
    from ...scenes.render_scenes import rect_above_horizon, rect_form_factors

    out = []
    for sr in _scene(m, K.RECT):
        li = sr.scene.lights[0]
        mask = sr.mask & rect_above_horizon(sr.scene)
        for name, er in sr.engines.items():
            who = _rect_engine(name, er)
            what = defect(name, sr.scene.name) or LTC_CLIPPED_SPHERE
            c = Claim(f"renders.{name}.{sr.scene.name}.regression", f"{who} keeps a known difference: {what}",
                      METRIC + " (rectangle wholly above the horizon)",
                      MIN_ACCEPTED, _rect_fraction(sr, er.image, mask), 0.0, "<", "%",
                      RULE + "; below it the engine is not the exact Lambertian integral of the rectangle")
            exact, sphere = rect_form_factors(sr.scene)
            with np.errstate(divide="ignore", invalid="ignore"):
                fixed = er.image * np.where(sphere > 0, exact / np.where(sphere > 0, sphere, 1.0), 1.0)[..., None]
            if fact(name, f"{sr.scene.name}.corrected_by", "") == "truth":
                out.append(c.with_power("corrected engine behaviour: the truth itself (the exact integral)", 1.0))
                continue
            out.append(c.with_power("corrected engine behaviour: the engine's image × F·n / clipped-sphere form factor",
                                    _rect_fraction(sr, fixed, mask)))
            shape = "sphere" if sr.scene.geometry == "sphere" else "plane"
            u = Claim(f"renders.{name}.{sr.scene.name}.units", f"{who}: RectAreaLight.intensity = {li.intensity:g} is "
                      f"luminance (nits): with its form factor approximation divided out, the Lambertian {shape} "
                      f"under the {li.width:g} × {li.height:g} m light equals Mitsuba's area emitter of radiance "
                      f"{li.intensity:g} per pixel (rectangle wholly above the horizon)", METRIC, MIN_ACCEPTED,
                      _rect_fraction(sr, fixed, mask), 0.0, ">", "%",
                      f"{RULE}; the unit: {fact(name, 'rect_units', 'the engine source')}")
            u.with_power("intensity × 1.02", _rect_fraction(sr, fixed * 1.02, mask))
            if u.power is not None and not u.power.fails:
                u.with_power(f"intensity read as luminous power (three 19214): L = Φ/(πA), image × 1/(π·{li.area():g})",
                             _rect_fraction(sr, fixed / (np.pi * li.area()), mask))
            out.append(u)
    return out


# ---------------------------------------------------------------- (b) glTF materials (metalness × roughness)
# The glTF BSDF (reference (i), validate.reference.gltf_bsdf) is checked before it judges anything:
# χ² of its sampler against its pdf (Mitsuba's ChiSquareTest, α = 0.01 Šidák over the cases; power: the sampler's
# α × 1.1 — the pdf does not contain F₀, so a Fresnel slip is invisible to χ² and is the albedo check's power);
# its directional albedo through its own sample() against a float64 quadrature of Appendix B's formulas
# (|z| below the Šidák critical value over cases × channels; power: the quadrature with the dielectric's F₀ 0.04 →
# 0.05); metallic 1 against Mitsuba's roughconductor × G₂/(G₁G₁) (the height-correlated V of B.3.2 from Mitsuba's
# own GGX D and G₁) to float32 rounding (power: roughconductor as is, the separable masking of the suite's older
# reference (i)).
BSDF_ALPHA = 0.01
# float32 evaluation of D = α²/(π t²), t = (N·H)²(α² − 1) + 1: a rounding of (N·H)² by ε = 2⁻²⁴ moves t by ≤ 2ε at
# the peak, where t = α², so D by ≤ 4ε/α² relatively; ×4 for the other roundings (V, the G₁ ratio) → 16ε/α²,
# α = the smallest checked (roughness 0.25: 2.4e-4)
F32_EPS = 2.0**-24


def bsdf_claims(m: Measurements) -> list[Claim]:
    from ...stats import sidak_critical

    b = m.bsdf_checks
    if not b:
        return []
    k = len(b["chi2"])
    level = 1.0 - (1.0 - BSDF_ALPHA) ** (1.0 / k)
    cases = "; ".join(f"metallic {c['metallic']:g}, roughness {c['roughness']:g}, μ_i {c['mu_i']:g}" for c in b["chi2"])
    c1 = Claim("renders.gltf_bsdf.chi2", f"the glTF BSDF's sampler matches its pdf ({cases}; {b['samples']} samples, "
               "Mitsuba ChiSquareTest 61 × 31 cells)", "smallest χ² p-value over the cases", level,
               min(c["p_value"] for c in b["chi2"]), 0.0, ">", "",
               f"Mitsuba's χ² harness, α = {BSDF_ALPHA} Šidák-corrected over {k} cases")
    c1.with_power("sampler's α × 1.1 (pdf unchanged)", b["chi2_power"]["p_value"])
    zs = [abs(z) for a in b["albedo"] for z in a["z"]]
    zp = [abs(z) for a in b["albedo"] for z in a["z_power"]]
    zc = sidak_critical(len(zs), BSDF_ALPHA)
    c2 = Claim("renders.gltf_bsdf.albedo", "the glTF BSDF's directional albedo through its own sample() equals a "
               "float64 quadrature of glTF 2.0 Appendix B's formulas (baseColor (0, 0.5, 1), "
               f"{len(b['albedo'])} metallic × roughness cases, μ_i = {b['albedo'][0]['mu_i']:g})",
               "max |z| over cases × channels", zc, max(zs), 0.0, "<", "",
               f"two-sided z-test, α = {BSDF_ALPHA} Šidák-corrected over {len(zs)} tests (uncertainty: Monte Carlo "
               "standard error ⊕ quadrature 192 vs 96 nodes)")
    c2.with_power("dielectric F₀ 0.04 → 0.05 in the quadrature", max(zp))
    metal = b["metal_vs_roughconductor"]
    rough = ", ".join(f"{x['roughness']:g}" for x in metal)
    tol = 16 * F32_EPS / max(min(x["roughness"] for x in metal) ** 2, 1e-4) ** 2
    c3 = Claim("renders.gltf_bsdf.metal_vs_roughconductor", "the glTF BSDF at metallic 1, baseColor 1 equals Mitsuba's "
               "roughconductor with its separable masking replaced by glTF's height-correlated G₂ (pointwise, "
               f"roughness {rough})",
               "max relative difference over direction pairs", tol, max(x["max_rel_diff"] for x in metal), 0.0, "<",
               "", "float32 rounding of D at the lobe's peak: 16 ε/α² (ε = 2⁻²⁴, α of roughness 0.25)")
    c3.with_power("roughconductor as is (separable G₁G₁: the suite's older reference (i))",
                  min(x["separable_max_rel_diff"] for x in metal))
    return [c1, c2, c3]


# glTF's material = mix(dielectric_brdf, metal_brdf, metallic) [B.2.1] is linear in metallic, and so is three's IBL
# after PR 32190 (multiscatter computed apart for the dielectric and the metal path, then mixed by metalness; before
# it, on the blended F₀ — "energy lost at intermediate metalness"). The claim: an engine's image at metalness 0.5
# equals the mix ½(image(0) + image(1)) of its own images, per pixel within 2 × the probe budget (each side carries
# the half-float budget), ≥ 99.75 % of pixels. Engines that keep the blended-F₀ behaviour are stated as the
# regression they have (their ``defects["probe_material.mix"]``, measured in their modules; power: the corrected
# behaviour, the mix itself). three.js 0.187 equals the mix to 0.00 % (every pixel).
METALNESS_SLIP = 0.05  # power: metalness 0.5 read as 0.45


def _mix_fraction(sr: SceneResult, image: np.ndarray, mix: np.ndarray) -> float:
    from .compute import PROBE_BUDGET_REL

    b = 2 * PROBE_BUDGET_REL * mix
    return judge(image, mix, np.zeros_like(mix), sr.dof, sr.mask, b, "2 × the probe budget").fraction_accepted


def mix_claims(m: Measurements) -> list[Claim]:
    from .compute import linear_mix

    scenes = _scene(m, K.PROBE_MATERIAL)
    mids = [s for s in scenes if 0.0 < s.scene.material.metallic < 1.0]
    out = []
    for name in sorted({e for s in mids for e in s.engines}):
        got, slip = [], []
        for sr in mids:
            mix = linear_mix(scenes, sr, name)
            if mix is None or name not in sr.engines:
                continue
            img = sr.engines[name].image
            ends = [s for s in scenes if s.scene.material.roughness == sr.scene.material.roughness
                    and s.scene.material.metallic in (0.0, 1.0)]
            i0, i1 = (next(s for s in ends if s.scene.material.metallic == v).engines[name].image for v in (0.0, 1.0))
            got.append(_mix_fraction(sr, img, mix))
            slip.append(_mix_fraction(sr, img - METALNESS_SLIP * (i1 - i0), mix))
        if not got:
            continue
        rough = ", ".join(f"{s.scene.material.roughness:g}" for s in mids)
        what = (f"white spheres under the probe at metalness {mids[0].scene.material.metallic:g} equal the mix "
                f"of its own metalness-0 and metalness-1 images (roughness {rough})")
        source = (RULE + " against glTF 2.0 B.2.1's mix (linear in metallic; three PR 32190), budget 2 × "
                  "the probe's (2 half-float lookups + SwiftShader trig) per side")
        known = defect(name, "probe_material.mix")
        if known is not None:
            c = Claim(f"renders.{name}.probe_material.mix.regression", f"{name} keeps a known difference: "
                      f"{known}", METRIC + ", worst roughness", MIN_ACCEPTED, min(got), 0.0, "<", "%",
                      source + "; below it the engine is not linear in metalness")
            out.append(c.with_power("corrected engine behaviour: the mix itself", 1.0))
            continue
        c = Claim(f"renders.{name}.probe_material.mix", f"{name}: {what}", METRIC + ", worst roughness",
                  MIN_ACCEPTED, min(got), 0.0, ">", "%", source)
        out.append(c.with_power(f"metalness 0.5 read as {0.5 - METALNESS_SLIP:g} (image − "
                                f"{METALNESS_SLIP:g}·(image(1) − image(0))), worst roughness", min(slip)))
    return out


# three PR 32190's own test: white spheres at metalness 0.5 in the white furnace return 1 (a white non-absorbing
# surface; the mix of two energy-conserving lobes conserves energy), with the furnace claim's budget. Power: the
# multiscatter removed — glTF's single scattering, reference (i) (the suite's gltf_metallic_roughness in Mitsuba).
# Engines keeping a deviation (``defects["furnace_material"]``, measured in their modules) are stated as the
# regression they have (power: the best other engine). three.js 0.187 returns 1 to 4.4e-9.


def furnace_material_claims(m: Measurements) -> list[Claim]:
    scenes = _scene(m, K.FURNACE_MATERIAL)
    if not scenes:
        return []
    mt = scenes[0].scene.material.metallic
    rough = ", ".join(f"{s.scene.material.roughness:g}" for s in scenes)
    engines = sorted({e for s in scenes for e in s.engines})
    dev = {e: max(abs(s.engines[e].energy - 1.0) for s in scenes if e in s.engines) for e in engines}
    single = max((s.reference_energy["gltf"] for s in scenes), key=lambda v: abs(v[0] - 1.0))
    source = ("energy conservation (white, non-absorbing, convex: exactly 1; glTF B.2.1 mixes two such lobes); "
              "budget as renders.<engine>.furnace.energy ≈ 2e-3")
    out = []
    for name in engines:
        known = defect(name, "furnace_material")
        if known is not None:
            c = Claim(f"renders.{name}.furnace_material.regression", f"{name} keeps a known defect: "
                      f"{known} (roughness {rough})", "max over scenes of |mean radiance − 1|",
                      FURNACE_ENERGY_TOL, dev[name], 0.0, ">", "", source + "; beyond it the engine loses or adds "
                      "energy at intermediate metalness")
            others = [v for e, v in dev.items() if e != name and defect(e, "furnace_material") is None]
            out.append(c.with_power("corrected engine behaviour: the best other engine", min(others) if others else 0.0,
                                    0.0))
            continue
        c = Claim(f"renders.{name}.furnace_material.energy", f"{name}: white spheres at metalness {mt:g} (roughness "
                  f"{rough}) in the white furnace return radiance 1 (three PR 32190)",
                  "max over scenes of |mean radiance − 1|", FURNACE_ENERGY_TOL, dev[name], 0.0, "<", "", source)
        out.append(c.with_power("multiscatter removed: glTF's single scattering (reference (i))",
                                abs(single[0] - 1.0), single[1]))
    return out


def material_claims(m: Measurements) -> list[Claim]:
    return bsdf_claims(m) + furnace_material_claims(m) + mix_claims(m)


def claims(m: Measurements) -> list[Claim]:
    return (furnace_claims(m) + directional_claims(m) + point_claims(m) + spot_claims(m) + hemisphere_claims(m)
            + probe_lambert_claims(m) + sharpness_claims(m) + rect_claims(m) + material_claims(m))
