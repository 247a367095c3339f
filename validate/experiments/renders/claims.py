"""Claims of the ``renders`` experiment, each with its source and a power check.

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
"""

from __future__ import annotations

import numpy as np

from ...metrics.pixel_z import MIN_ACCEPTED, judge
from ..base import Claim
from .compute import Measurements, SceneResult, budget

FURNACE_ENERGY_TOL = 2e-3


def _scene(m: Measurements, kind: str) -> list[SceneResult]:
    return [s for s in m.scenes if s.kind == kind]


def directional_claims(m: Measurements) -> list[Claim]:
    out = []
    for sr in _scene(m, "directional"):
        ref_m = sr.references["mitsuba"]
        for name, er in sr.engines.items():
            j = er.judgements["mitsuba"]
            b, text = budget("directional", ref_m)
            c = Claim(f"renders.{name}.lambert_directional.accepted",
                      f"{name}: Lambertian sphere under a {m.settings.sun_lux:g} lux directional light equals Mitsuba "
                      f"per pixel (budget {text})", "fraction of pixels accepted (Šidák α = 0.01)", MIN_ACCEPTED,
                      j.fraction_accepted, 0.0, ">", "%",
                      "Mitsuba 3 render tests: ≥ 99.75 % of pixels pass the Šidák-corrected z-test at α = 0.01")
            se, dof = _stderr(sr), m.settings.passes - 1
            p102 = judge(er.image * 1.02, ref_m, se, dof, sr.mask, b, text).fraction_accepted
            ppi = judge(er.image * np.pi, ref_m, se, dof, sr.mask, b, text).fraction_accepted
            c.with_power("light intensity × 1.02 (engine image × 1.02)", p102)
            if c.power is not None and not c.power.fails:
                c.with_power("E taken for E/π (engine image × π)", ppi)
            out.append(c)
    return out


def _stderr(sr: SceneResult) -> np.ndarray:
    return sr.stderrs["mitsuba"]


def furnace_claims(m: Measurements) -> list[Claim]:
    scenes = _scene(m, "furnace")
    engines = sorted({e for s in scenes for e in s.engines})
    out = []
    for name in engines:
        dev = [abs(s.engines[name].energy - 1.0) for s in scenes if name in s.engines]
        rough = ", ".join(f"{r:g}" for r in m.settings.furnace_roughness)
        c = Claim(f"renders.{name}.furnace.energy", f"{name}: white spheres (dielectric and metal, roughness "
                  f"{rough}) in the white furnace return radiance 1",
                  "max over scenes of |mean radiance − 1|", FURNACE_ENERGY_TOL, max(dev), 0.0, "<", "",
                  "energy conservation (white, non-absorbing, convex: exactly 1); budget 2 half-float lookups + "
                  "BRDF LUT (4·2⁻¹¹) + SwiftShader trig 2e-4 ≈ 2e-3")
        metal = [s.reference_energy["model"] for s in scenes if "model" in s.reference_energy]
        worst = max(metal, key=lambda v: abs(v[0] - 1.0)) if metal else (float("nan"), 0.0)
        out.append(c.with_power("multiscatter removed: glTF single-scattering metal (Mitsuba roughconductor)",
                                abs(worst[0] - 1.0), worst[1]))
    return out


def claims(m: Measurements) -> list[Claim]:
    return furnace_claims(m) + directional_claims(m)
