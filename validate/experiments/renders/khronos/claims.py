"""The glTF Sample Viewer's claims, where the glTF specification gives the answer, each with its power check:

* ``furnace.energy``: white spheres (dielectric and metal over roughness) in the white furnace return radiance 1
  (energy conservation; the parent's ``FURNACE_ENERGY_TOL`` plus the 8-bit readback's rounding bound at radiance 1,
  :func:`half_lsb_at_one`); power: 1 % of the energy lost (image × 0.99) must fail it. The viewer passes by
  construction: its IBL adds Fdez-Agüera's multiple-scattering term (ibl.glsl: FssEss + FmsEms, F_avg = F0 +
  (1 − F0)/21), so white metal sums to Ess + Ems = 1 and white dielectric's diffuse takes 1 − (FssEss + FmsEms),
  whatever its LUT holds.
* ``lambert_directional.accepted``: the Lambertian sphere under a KHR directional light equals Mitsuba per pixel
  (E·ρ/π); power: E taken for E/π (image × π) and the light × 1.02.
* ``spot_plane.accepted``: the KHR spot falloff on the Lambertian plane equals Mitsuba's (KHR's reference falloff);
  power: the parent's reference with the outer cone 1° wider.
* ``point_*.accepted``: inverse-square point light; power: lumens taken for candela (× 4π), then × 1.02.
Every judgement carries the viewer's 8-bit readback σ per pixel (:func:`.compute.judged_stderr`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ....local_models.render import khronos_viewer as kv
from ....metrics.pixel_z import MIN_ACCEPTED, judge
from ...base import Claim
from .compute import KhronosPart, KhronosScene

ENGINE = "khronos_viewer"
FURNACE_ENERGY_TOL = 2e-3  # the parent's (renders.claims): 2 half-float lookups + BRDF LUT + SwiftShader trig
RULE = "Mitsuba 3 render tests: ≥ 99.75 % of pixels pass the Šidák-corrected z-test at α = 0.01"
METRIC = "fraction of pixels accepted (Šidák α = 0.01)"


def _fraction(part: KhronosPart, sr: Any, ks: KhronosScene, image: np.ndarray, key: str = "mitsuba",
              mean_se: tuple[np.ndarray, np.ndarray] | None = None) -> float:
    m, se = mean_se if mean_se is not None else (sr.references[key], sr.stderrs[key])
    b, text = part.budget(sr.kind, m)
    return judge(image, m, np.sqrt(se**2 + ks.readback_stderr**2), sr.dof, ks.mask, b, text).fraction_accepted


def _accepted(ks: KhronosScene, what: str, key: str = "mitsuba") -> Claim:
    j = ks.judgements[key]
    return Claim(f"renders.{ENGINE}.{ks.name}.accepted", f"{ENGINE}: {what} equals Mitsuba per pixel (budget "
                 f"{j.budget}; the 8-bit readback's σ in quadrature)", METRIC, MIN_ACCEPTED, j.fraction_accepted,
                 0.0, ">", "%", RULE)


def half_lsb_at_one(exposure: float) -> float:
    """The readback's rounding bound at radiance 1: half a code step of (q/255)^2.2/e around q = 255·e^(1/2.2)."""
    q = 255.0 * exposure ** (1.0 / kv.GAMMA)
    lo, hi = ((q - 0.5) / 255.0) ** kv.GAMMA / exposure, ((q + 0.5) / 255.0) ** kv.GAMMA / exposure
    return float(max(1.0 - lo, hi - 1.0))


def furnace_claim(part: KhronosPart) -> Claim | None:
    fur = [ks for ks in part.scenes.values() if ks.kind == "furnace"]
    if not fur:
        return None
    worst = max(fur, key=lambda k: abs(k.energy - 1.0))
    names = ", ".join(k.name for k in fur)
    lsb = max(half_lsb_at_one(k.info["exposure"]) for k in fur)
    c = Claim(f"renders.{ENGINE}.furnace.energy", f"{ENGINE}: white spheres in the white furnace return radiance 1 "
              f"({names}; the worst: {worst.name})", "max over scenes of |mean radiance − 1|",
              FURNACE_ENERGY_TOL + lsb, abs(worst.energy - 1.0), 0.0, "<", "",
              "energy conservation (white, non-absorbing, convex: exactly 1); budget the parent's "
              f"{FURNACE_ENERGY_TOL:g} "
              f"+ the 8-bit gamma readback's rounding bound at radiance 1 ({lsb:.2e}: every covered pixel holds the "
              "same code, so the rounding does not average out)")
    return c.with_power("1 % of the energy lost (engine image × 0.99)", abs(worst.energy * 0.99 - 1.0))


def khronos_claims(part: KhronosPart | None) -> list[Claim]:
    if part is None or not part.scenes:
        return []
    scenes = part.parent_scenes
    out = [c for c in (furnace_claim(part),) if c is not None]
    for ks in part.scenes.values():
        sr = scenes[ks.name]
        if ks.kind == "directional":
            li = sr.scene.lights[0]
            c = _accepted(ks, f"Lambertian sphere under a {li.intensity:g} lux KHR directional light")
            c.with_power("E taken for E/π (engine image × π)", _fraction(part, sr, ks, ks.image * np.pi))
            if c.power is not None and not c.power.fails:
                c.with_power("light intensity × 1.02 (engine image × 1.02)", _fraction(part, sr, ks, ks.image * 1.02))
            out.append(c)
        elif ks.kind == "point":
            li = sr.scene.lights[0]
            c = _accepted(ks, f"Lambertian {sr.scene.geometry} under a {li.intensity:g} cd KHR point light")
            c.with_power("intensity in lumens taken for candela (engine image × 4π)",
                         _fraction(part, sr, ks, ks.image * 4 * np.pi))
            if c.power is not None and not c.power.fails:
                c.with_power("light intensity × 1.02 (engine image × 1.02)", _fraction(part, sr, ks, ks.image * 1.02))
            out.append(c)
        elif ks.kind == "spot":
            li = sr.scene.lights[0]
            c = _accepted(ks, f"Lambertian plane under a {li.intensity:g} cd KHR spot light (cone "
                              f"{li.inner_deg:g}°/{li.outer_deg:g}°, KHR_lights_punctual's reference falloff)")
            label = next(k for k in sr.power_refs if k.startswith("gltf"))
            c.with_power(f"cone falloff off by a degree: Mitsuba {label}",
                         _fraction(part, sr, ks, ks.image, mean_se=sr.power_refs[label]))
            out.append(c)
    return out
