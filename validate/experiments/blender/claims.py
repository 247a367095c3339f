"""Claims: Cycles agrees with Mitsuba per pixel where both describe the scene identically.

For every Cycles scene lit by a sun or a point light, the fraction of judged pixels whose Cycles value lies within
the combined uncertainty of the truth
(Mitsuba's passes, Cycles' passes, the renders budget for a tessellated sphere) must reach Mitsuba's own acceptance
rule, 99.75 % at α = 0.01 with Šidák's correction (:mod:`validate.metrics.pixel_z`). Power: Cycles' image 1 % brighter
must fail the same rule. The spot is a finding: the importer's cone (smoothstep, blend = 1 − inner/outer) as the
suite models it (reference ``blender``) misses Cycles' penumbra by a fraction of a degree. The furnace and EEVEE are
findings: Principled's multiple scattering differs from glTF's
BRDF by design, and Blender's documentation gives EEVEE no per-pixel bound.
The bpy-built world-lit spheres (:mod:`.world`): Cycles against Mitsuba under the same rule and power check (both
Lambert, one radiance function); EEVEE's world lighting read by R&H's measure is a finding — R&H's "< 1 % / < 5 %
of Φ" is a statement about SH9, not about EEVEE's L1 probe, and Blender's manual gives it no bound.
The glossy spheres over roughness (:mod:`.probes`): Cycles against Mitsuba under the same two claims per roughness
(Cycles' Glossy BSDF, GGX single scattering, and the suite's glTF BSDF at metallic 1 are one BSDF); EEVEE's sphere
probes and its irradiance volume are findings; Cycles on the volume probe's scene (a sphere on a plane, Lambert,
every bounce up to Mitsuba's path length) is judged under the same two claims; Cycles on the soft-shadow scenes (a
sphere light and a disc light past an occluder) under the agreement claim, power the truth mirrored left–right.
"""

from __future__ import annotations

from ...metrics.pixel_z import MIN_ACCEPTED
from ...reference import pathtrace
from ..base import Claim
from . import probes as pr
from . import shadows as sh
from .compute import POWER_SCALE, Measurements

AGREEING = {"directional": "mitsuba", "point": "mitsuba"}
SOURCE = ("Mitsuba 3's render tests accept an image when ≥ 99.75 % of its pixels pass the per-pixel z-test at α = 0.01 "
          "(src/python/python/test/test_renders.py); two unbiased path tracers of one scene must pass it")

BIAS_SOURCE = ("two unbiased estimators of one pixel differ by zero on average: the cross-fitted z (difference from "
               "one half of the passes over the standard error of the other, validate.stats.cross_fitted_z) has mean "
               "0 under H₀ however skewed the passes, and the mean of N independent such values lies within 4 sd/√N "
               "(4σ, central limit theorem; validate.reference.pathtrace: the sh9 cross-check's bias test)")


MIRRORED = "the truth mirrored left–right (a swapped frame)"
# the volume scene's power: nearly symmetric left–right under its noise (mirrored: 99.78 % accepted), so the other axis
FLIPPED = "the truth flipped upside down (the film's v axis inverted: rows read back bottom-up)"


def _agreement(cid: str, description: str, accepted: float, power: str, power_accepted: float) -> Claim:
    """≥ :data:`MIN_ACCEPTED` of the judged pixels accepted (:data:`SOURCE`); its power check ``power``."""
    c = Claim(id=cid, description=description, metric="fraction of pixels accepted", threshold=MIN_ACCEPTED,
              measured=accepted, uncertainty=0.0, comparison=">", unit="%", source=SOURCE)
    return c.with_power(power, power_accepted)


def _unbiased(cid: str, what: str, n_pixels: int, cy: dict) -> Claim:
    """max over channels of |mean z̃| / sd(z̃) within the 4/√N bound (:data:`BIAS_SOURCE`); power: Cycles ×
    POWER_SCALE."""
    c = Claim(id=cid, description=f"Cycles against Mitsuba on {what}: no bias, max over channels of |mean z̃| / sd(z̃) "
                                  f"(cross-fitted z) over {n_pixels} px within {pathtrace.BIAS_SIGMAS:g}/√N",
              metric="max |mean z̃| / sd (–)", threshold=cy["bias_limit"], measured=cy["bias"], uncertainty=0.0,
              comparison="<", unit="", source=BIAS_SOURCE)
    return c.with_power(f"Cycles × {POWER_SCALE:g}", cy["bias_power"])


def claims(m: Measurements) -> list[Claim]:
    out = []
    for j in m.scenes:
        ref = AGREEING.get(j.kind)
        if j.engine != "blender_cycles" or ref is None:
            continue
        pj, pw = j.judgements[ref], j.power[ref]
        out.append(_agreement(f"blender.cycles.{j.scene}.agrees_with_mitsuba",
                              f"Cycles ({j.frames} × {j.samples} spp) and Mitsuba agree per pixel on {j.scene} "
                              f"(reference {ref}; {pj.n_pixels} px judged)", pj.fraction_accepted,
                              f"Cycles × {POWER_SCALE:g}", pw.fraction_accepted))
    for w in m.world:
        if not w.cycles:
            continue
        pj = w.cycles["judgement"]
        out.append(_agreement(f"blender.cycles.world_{w.probe}.agrees_with_mitsuba",
                              f"Cycles ({w.cycles['frames']} × {m.settings.world_spp} spp) and Mitsuba "
                              f"({w.mitsuba['passes']} × {w.mitsuba['spp']} spp) agree per pixel on a white "
                              f"Lambertian sphere lit only by {w.probe} (bpy-built scene; {pj.n_pixels} px judged)",
                              pj.fraction_accepted, MIRRORED, w.cycles["mirrored"].fraction_accepted))
        out.append(_unbiased(f"blender.cycles.world_{w.probe}.unbiased_against_mitsuba",
                             f"the sphere lit by {w.probe}", pj.n_pixels, w.cycles))
    for g in m.glossy:
        cy = g.get("cycles")
        if not cy:
            continue
        pj, r = cy["judgement"], g["roughness"]
        what = (f"a white GGX sphere (roughness {r:g}, α = {g['alpha']:g}: Cycles' Glossy BSDF GGX single scattering, "
                f"Mitsuba the glTF BSDF at metallic 1 — one BSDF) lit only by {g['probe']}")
        out.append(_agreement(f"blender.cycles.glossy_{g['probe']}_r{r:g}.agrees_with_mitsuba",
                              f"Cycles ({cy['frames']} × {m.settings.glossy_spp} spp) and Mitsuba "
                              f"({g['truth']['passes']} × {g['truth']['spp']} spp) agree per pixel on {what} "
                              f"(bpy-built scene; {pj.n_pixels} px judged)",
                              pj.fraction_accepted, MIRRORED, cy["mirrored"].fraction_accepted))
        out.append(_unbiased(f"blender.cycles.glossy_{g['probe']}_r{r:g}.unbiased_against_mitsuba", what,
                             pj.n_pixels, cy))
    for label, light in (("cycles", "sphere"), (f"{sh.DISC}cycles", "disc")):
        a = m.shadows.get(label, {}).get("all")
        if a:
            out.append(_agreement(f"blender.cycles.shadow_{light}_light.agrees_with_mitsuba",
                                  f"Cycles ({m.settings.passes} × {m.settings.shadow_spp} spp) and Mitsuba agree per "
                                  f"pixel on the plane lit by a {light} light (r = 0.15 m) past a plate occluder, "
                                  f"direct light only ({a['pixels']} px judged: lit, penumbra and umbra; the plane's "
                                  "seam judged apart)", a["fraction_accepted"], MIRRORED, a["mirrored_accepted"]))
    cy = m.volume.get("cycles")
    if cy:
        pj, probe, truth = cy["judgement"], m.volume["probe"], m.volume["truth"]
        what = (f"a Lambertian sphere on a Lambertian plane (albedo {pr.VOLUME_ALBEDO:g}) lit only by {probe}, "
                f"paths of up to {truth['depth'] - 2} bounces in both")
        out.append(_agreement(f"blender.cycles.volume_{probe}.agrees_with_mitsuba",
                              f"Cycles ({cy['frames']} × {m.settings.volume_spp} spp) and Mitsuba ({truth['passes']} "
                              f"× {truth['spp']} spp) agree per pixel on {what} (bpy-built scene; {pj.n_pixels} px "
                              "judged)", pj.fraction_accepted, FLIPPED, cy["flipped"].fraction_accepted))
        out.append(_unbiased(f"blender.cycles.volume_{probe}.unbiased_against_mitsuba", what, pj.n_pixels, cy))
    return out
