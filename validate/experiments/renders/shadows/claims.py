"""(e) Shadows: claims per scene × engine × shadow type, each with its power check.

* ``lit``: the fully lit region (the whole light visible, 2 px or more from any pixel that is not) equals Mitsuba per
  pixel — Mitsuba's ≥ 99.75 % rule; power: the light's intensity × 1.02 (the engine image × 1.02).
* ``umbra``: the umbra is dark — its pixels accepted against the truth 0 (every sample of the light blocked) with the
  same rule, i.e. no pixel brighter than the budget (0.25 % of the peak); power: a leak of 2 % of the unshadowed
  radiance added over the umbra must fail. An engine type that leaks keeps it as a regression (``LEAK_REGRESSIONS``;
  three issue 23551, "shadow light leaks no bias fixes"); its power check is the corrected behaviour, the truth.
* Every judgement takes the engine's readback uncertainty (Filament's 8-bit canvas) as a known term
  (:func:`~validate.experiments.renders.shadows.compute.judged_budget`); 0 for three and Babylon.
* ``penumbra``: the 10–90 % transition W (px) against the path tracer's, stated as the regression each engine type
  has (``PENUMBRA``: a shadow map filters by a fixed width in shadow-map texels, the truth's penumbra grows with the
  light's angular size and the occluder–receiver distance [Fernando 2005]); the claim is W_engine/W_truth below 1
  (narrower) or above 1 (wider) beyond the truth's redraw uncertainty; power: the truth's own image as the engine
  (ratio 1).
"""

from __future__ import annotations

import numpy as np

from ....metrics.pixel_z import MIN_ACCEPTED, judge
from ....scenes.render_scenes import DirectionalLight
from ...base import Claim
from .compute import ShadowEngineResult, ShadowSceneResult, judged_budget

RULE = "Mitsuba 3 render tests: ≥ 99.75 % of pixels pass the Šidák-corrected z-test at α = 0.01"
METRIC = "fraction of pixels accepted (Šidák α = 0.01)"
LEAK_POWER = 0.02  # a leak of 2 % of the unshadowed radiance over the umbra
# (engine, shadow type) → what leaks; the claim passes while the engine keeps it. Measured (FULL, 64²): Babylon 9.35
# PCSS lights 100 % of the umbra, mean shadow factor 14.8 % (directional) and 12.0 % (spot); Filament 1.53.4 PCF's
# spot lights 100 % of it, mean shadow factor 100.02 ± 0.01 % (no shadow drawn; its directional umbra: 0 %); every
# other type 0 %. Keys (engine, type) hold for every scene, (engine, type, scene) for that scene only.
LEAK_REGRESSIONS: dict[tuple[str, ...], str] = {
    ("babylon", "pcss"): "PCSS lets light into the umbra: its shader mixes the filtered shadow towards 1 by the "
                         "blocker–receiver depth gap (computeShadowWithPCSS: mix(shadow, 1, depthMetric − "
                         "avgBlockerDepth))",
    ("filament", "pcf", "shadow_spot"): "its spot light casts no shadow from a caster outside the camera's view (the "
                                        "whole umbra lit; with the view widened to take the box in, it casts: "
                                        "filament_shadows.mjs)",
}
# (engine, shadow type) → lit-region defects kept as regressions, claimed once over the scenes (the worst). Measured
# (FULL, 64², SwiftShader): three 0.187's VSM darkens whole columns of the fully lit plane far from any shadow
# (directional: 3 columns, s ≥ 0.956, 95.7 % of the lit pixels accepted; spot: 2 columns, s ≥ 0.892, 96.9 %; QUICK,
# 32²: directional 0 columns, 100 %; spot 2 columns, 93.9 %); every other type (Filament PCF included) accepts
# 100 % of the lit pixels.
# Deterministic (the same pixels in the same page, after the other types, and in a fresh browser); the runs differ by
# resolution only. Cause (docs/experiments/renders.md, "three.js VSM columns"): three's VSM renders every receiving
# mesh into its shadow map (WebGLShadowMap.renderObject: castShadow || (receiveShadow && VSM)), so the plane
# self-shadows at bias 0 against its own moments, stored as RG16F: where the half-float mean rounds below the
# fragment's depth, Chebyshev's bound with the light-bleeding remap (p − 0.3)/0.65 darkens it. Switched off one at a
# time, each removes every dark pixel of both scenes (64² and 32²): the receiver kept out of the map, RG32F moments,
# or bias −2e-4 (< one half-float ulp at depth ½).
LIT_REGRESSIONS: dict[tuple[str, str], str] = {
    ("three", "vsm"): "VSM darkens full-height columns of the fully lit plane far from any shadow (s down to 0.89): "
                      "it renders the receiver into its map (receiveShadow under VSM) and the plane, at bias 0, "
                      "self-shadows where its half-float mean depth rounds below the fragment's"}
# (engine, shadow type) whose penumbra is wider than the path tracer's (measured: Babylon PCSS 3.3× directional,
# 1.4× spot); every other type's is narrower (three/Babylon PCF 0.14–0.40×, Filament PCF 0.19× directional; Basic,
# ESM, blurred ESM 0: hard; Filament's spot 0: no shadow at all)
PENUMBRA_WIDER: set[tuple[str, str]] = {("babylon", "pcss")}


def _fraction(sr: ShadowSceneResult, region: str, image: np.ndarray, r: ShadowEngineResult) -> float:
    m = sr.regions[region]
    with np.errstate(divide="ignore", invalid="ignore"):  # the umbra's truth is 0: its relative errors are NaN
        b = judged_budget(sr, m, r.readback_stderr)
        return judge(image, sr.mean, sr.stderr, sr.dof, m, b, "").fraction_accepted


def _keyed(table: dict, sr: ShadowSceneResult, r: ShadowEngineResult):  # noqa: ANN202 - the table's value type
    """``table``'s entry for (engine, type, scene) or else (engine, type); None when neither is there."""
    return table.get((r.engine, r.shadow_type, sr.scene.name), table.get((r.engine, r.shadow_type)))


def _id(sr: ShadowSceneResult, r: ShadowEngineResult, what: str) -> str:
    return f"renders.{r.engine}.{sr.scene.name}.{r.shadow_type}.{what}"


def lit_claim(sr: ShadowSceneResult, r: ShadowEngineResult) -> Claim | None:
    """The fully lit region equals Mitsuba (types in ``LIT_REGRESSIONS`` are claimed once over the scenes)."""
    if (r.engine, r.shadow_type) in LIT_REGRESSIONS:
        return None
    j = r.judgements["lit"]
    c = Claim(_id(sr, r, "lit"), f"{r.engine} ({r.shadow_type} shadows): the fully lit plane of {sr.scene.name} equals "
              f"Mitsuba per pixel (budget {j.budget})", METRIC + " (fully lit region)", MIN_ACCEPTED,
              j.fraction_accepted, 0.0, ">", "%", RULE)
    return c.with_power("light intensity × 1.02 (engine image × 1.02)", _fraction(sr, "lit", r.image * 1.02, r))


def lit_regression_claims(shadows: list[ShadowSceneResult]) -> list[Claim]:
    """One claim per (engine, type) of ``LIT_REGRESSIONS``: the least accepted fully lit region over the scenes is
    below the rule (where the artefact lands depends on the resolution, so the claim takes the worst scene)."""
    out = []
    for (engine, shadow_type), what in LIT_REGRESSIONS.items():
        found = [(sr, r) for sr in shadows for r in sr.results if (r.engine, r.shadow_type) == (engine, shadow_type)]
        if not found:
            continue
        worst = min(r.judgements["lit"].fraction_accepted for _, r in found)
        names = ", ".join(sr.scene.name for sr, _ in found)
        c = Claim(f"renders.{engine}.shadows.{shadow_type}.lit.regression", f"{engine} {shadow_type} keeps a known "
                  f"defect: {what} (the least accepted of {names})", METRIC + " (fully lit region, worst scene)",
                  MIN_ACCEPTED, worst, 0.0, "<", "%", RULE + "; below it the engine darkens the lit plane")
        out.append(c.with_power("corrected engine behaviour: the truth itself", 1.0))
    return out


def umbra_claim(sr: ShadowSceneResult, r: ShadowEngineResult) -> Claim | None:
    if "umbra" not in r.judgements:
        return None
    j, known = r.judgements["umbra"], _keyed(LEAK_REGRESSIONS, sr, r)
    um = sr.regions["umbra"]
    leaked = r.image + np.where(um, LEAK_POWER * sr.unshadowed, 0.0)[..., None]
    if known is not None:
        c = Claim(_id(sr, r, "umbra.regression"), f"{r.engine} {r.shadow_type} keeps a known defect (light leak, "
                  f"three issue 23551's kind): {known}", METRIC + " (umbra, truth 0)", MIN_ACCEPTED,
                  j.fraction_accepted, 0.0, "<", "%", RULE + "; below it light leaks into the umbra")
        return c.with_power("corrected engine behaviour: the truth itself (a dark umbra)",
                            _fraction(sr, "umbra", np.where(um[..., None], 0.0, r.image), r))
    c = Claim(_id(sr, r, "umbra"), f"{r.engine} ({r.shadow_type} shadows): the umbra of {sr.scene.name} is dark (no "
              f"pixel above the budget {j.budget}; three issue 23551: no light leak)", METRIC + " (umbra, truth 0)",
              MIN_ACCEPTED, j.fraction_accepted, 0.0, ">", "%", RULE)
    return c.with_power(f"a light leak of {LEAK_POWER:.0%} of the unshadowed radiance over the umbra",
                        _fraction(sr, "umbra", leaked, r))


def penumbra_claim(sr: ShadowSceneResult, r: ShadowEngineResult) -> Claim:
    wt, ut = sr.truth_width
    wider = _keyed(dict.fromkeys(PENUMBRA_WIDER, True), sr, r) is not None
    ratio, unc = r.width_px / wt, r.width_px * ut / wt**2
    li = sr.scene.light_size
    size = f"{li:g}° angular radius" if isinstance(sr.scene.light, DirectionalLight) else f"{li:g} m radius"
    c = Claim(_id(sr, r, "penumbra.regression"), f"{r.engine} {r.shadow_type} keeps a known difference: its penumbra "
              f"in {sr.scene.name} is {'wider' if wider else 'narrower'} than the path-traced one of a light of {size} "
              "(a fixed filter in shadow-map texels, not the light's size)", "penumbra width ratio W_engine/W_truth "
              "(10–90 % transition, px)", 1.0, ratio, unc, ">" if wider else "<", "",
              "W_truth ± the s.d. of W over 64 parametric redraws of the reference noise; a shadow with the truth's "
              "penumbra has ratio 1 within it")
    return c.with_power("corrected engine behaviour: the path tracer's own image as the engine", 1.0, ut / wt)


def shadow_claims(shadows: list[ShadowSceneResult]) -> list[Claim]:
    out: list[Claim] = []
    for sr in shadows:
        for r in sr.results:
            out += [c for c in (lit_claim(sr, r), umbra_claim(sr, r), penumbra_claim(sr, r)) if c is not None]
    return out + lit_regression_claims(shadows)
