"""Claims of (g) loaders: only where glTF itself gives the answer — a Lambertian surface under a KHR_lights_punctual
light in glTF's units (directional lux, point candela, inverse square; Filament's spot: KHR's reference falloff),
read through the engine's own loader, equals Mitsuba per pixel. Power: the image × 1.02 (a light 2 % off) fails;
for Filament's orthographic scene also gltfio's own projection. three's spot (a smoothstep penumbra, the hand-built
path's known difference) is a finding, not a claim."""

from __future__ import annotations

from ....metrics.pixel_z import MIN_ACCEPTED
from ...base import Claim
from .compute import LoaderMeasurements

RULE = "Mitsuba 3 render tests: ≥ 99.75 % of pixels pass the Šidák-corrected z-test at α = 0.01"
WHAT = {"lambert_directional": "the Lambertian sphere under a KHR directional light (lux)",
        "point_plane": "the Lambertian plane under a KHR point light (candela, inverse square, no range)",
        "point_sphere": "the Lambertian sphere beside a KHR point light (candela, inverse square, no range)",
        "spot_plane": "the Lambertian plane under a KHR spot light (candela, KHR's cone falloff)"}
CLAIMED = {"three_gltf": ("lambert_directional", "point_plane", "point_sphere"),
           "filament_gltf": ("lambert_directional", "point_plane", "point_sphere", "spot_plane")}


def loader_claims(pm: LoaderMeasurements) -> list[Claim]:
    out = []
    for ls in pm.scenes:
        if ls.scene not in CLAIMED.get(ls.engine, ()) or ls.loader is None:
            continue
        c = Claim(f"renders.loaders.{ls.engine}.{ls.scene}.accepted",
                  f"{ls.engine}: {WHAT[ls.scene]}, loaded from the exported .glb by the engine's own loader, equals "
                  f"Mitsuba per pixel ({ls.loader.budget})", "fraction of pixels accepted (Šidák α = 0.01)",
                  MIN_ACCEPTED, ls.loader.fraction_accepted, 0.0, ">", "%", RULE)
        for what, frac in ls.power.items():  # the first perturbation that fails is the one shown
            c.with_power(what, frac)
            if c.power is not None and c.power.fails:
                break
        out.append(c)
    return out


__all__ = ["loader_claims"]
