"""(e) Shadows: claims per scene × engine × shadow type, each with its power check.

* ``lit``: the fully lit region (the whole light visible, 2 px or more from any pixel that is not) equals Mitsuba per
  pixel — Mitsuba's ≥ 99.75 % rule; power: the light's intensity × 1.02 (the engine image × 1.02).
* ``umbra``: the umbra is dark — its pixels accepted against the truth 0 (every sample of the light blocked) with the
  same rule, i.e. no pixel brighter than the budget (0.25 % of the peak); power: a leak of 2 % of the unshadowed
  radiance added over the umbra must fail. An engine type that leaks keeps it as a regression (its engine's
  ``defects["shadows.<type>.umbra"]``;
  three issue 23551, "shadow light leaks no bias fixes"); its power check is the corrected behaviour, the truth.
* Every judgement takes the engine's readback uncertainty (Filament's 8-bit canvas) as a known term
  (:func:`~validate.experiments.renders.shadows.compute.judged_budget`); 0 for three and Babylon.
* ``penumbra``: the 10–90 % transition W (px) against the path tracer's, stated as the regression each engine type
  has (a shadow map filters by a fixed width in shadow-map texels, the truth's penumbra grows with the
  light's angular size and the occluder–receiver distance [Fernando 2005]); the claim is W_engine/W_truth below 1
  (narrower) or above 1 (wider) beyond the truth's redraw uncertainty; power: the truth's own image as the engine
  (ratio 1).
"""

from __future__ import annotations

import numpy as np

from ....local_models.render import registry
from ....metrics.pixel_z import MIN_ACCEPTED, judge
from ....scenes.render_scenes import DirectionalLight
from ...base import Claim
from .compute import ShadowEngineResult, ShadowSceneResult, judged_budget

RULE = "Mitsuba 3 render tests: ≥ 99.75 % of pixels pass the Šidák-corrected z-test at α = 0.01"
METRIC = "fraction of pixels accepted (Šidák α = 0.01)"
LEAK_POWER = 0.02  # a leak of 2 % of the unshadowed radiance over the umbra
# An engine's known shadow defects are its ``defects`` (texts and measurements in its module), stated as the
# regression it has: "shadows.<type>.umbra" (light leaks into the umbra, every scene) or "shadows.<type>.<scene>.umbra"
# (that scene only); "shadows.<type>.lit" (the fully lit region darkened, claimed once over the scenes, the worst:
# where the artefact lands depends on the resolution). Its penumbra is claimed narrower than the path tracer's unless
# its ``facts["shadows.<type>.penumbra"]`` is "wider" (a shadow map filters by a fixed width in shadow-map texels).


def _engine_defects(engine: str) -> dict[str, str]:
    e = registry.find(engine)
    return e.defects if e is not None else {}


def leak_defect(sr: ShadowSceneResult, r: ShadowEngineResult) -> str | None:
    """The light leak the engine states for this type in this scene (or every scene), or None."""
    d = _engine_defects(r.engine)
    return d.get(f"shadows.{r.shadow_type}.{sr.scene.name}.umbra", d.get(f"shadows.{r.shadow_type}.umbra"))


def lit_defect(engine: str, shadow_type: str) -> str | None:
    """The lit-region defect the engine states for the type, or None."""
    return _engine_defects(engine).get(f"shadows.{shadow_type}.lit")


def penumbra_wider(r: ShadowEngineResult) -> bool:
    e = registry.find(r.engine)
    return e is not None and e.facts.get(f"shadows.{r.shadow_type}.penumbra") == "wider"


def _fraction(sr: ShadowSceneResult, region: str, image: np.ndarray, r: ShadowEngineResult) -> float:
    m = sr.regions[region]
    with np.errstate(divide="ignore", invalid="ignore"):  # the umbra's truth is 0: its relative errors are NaN
        b = judged_budget(sr, m, r.readback_stderr)
        return judge(image, sr.mean, sr.stderr, sr.dof, m, b, "").fraction_accepted


def _id(sr: ShadowSceneResult, r: ShadowEngineResult, what: str) -> str:
    return f"renders.{r.engine}.{sr.scene.name}.{r.shadow_type}.{what}"


def lit_claim(sr: ShadowSceneResult, r: ShadowEngineResult) -> Claim | None:
    """The fully lit region equals Mitsuba (types with a lit defect are claimed once over the scenes)."""
    if lit_defect(r.engine, r.shadow_type) is not None:
        return None
    j = r.judgements["lit"]
    c = Claim(_id(sr, r, "lit"), f"{r.engine} ({r.shadow_type} shadows): the fully lit plane of {sr.scene.name} equals "
              f"Mitsuba per pixel (budget {j.budget})", METRIC + " (fully lit region)", MIN_ACCEPTED,
              j.fraction_accepted, 0.0, ">", "%", RULE)
    return c.with_power("light intensity × 1.02 (engine image × 1.02)", _fraction(sr, "lit", r.image * 1.02, r))


def lit_regression_claims(shadows: list[ShadowSceneResult]) -> list[Claim]:
    """One claim per (engine, type) with a lit defect: the least accepted fully lit region over the scenes is
    below the rule (where the artefact lands depends on the resolution, so the claim takes the worst scene)."""
    out = []
    pairs = dict.fromkeys((r.engine, r.shadow_type) for sr in shadows for r in sr.results)
    for engine, shadow_type in sorted(pairs):
        what = lit_defect(engine, shadow_type)
        if what is None:
            continue
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
    j, known = r.judgements["umbra"], leak_defect(sr, r)
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
    wider = penumbra_wider(r)
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
