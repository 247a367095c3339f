"""A Mitsuba texture that makes Mitsuba's ``spot`` emitter follow KHR_lights_punctual's cone falloff exactly.

Mitsuba 3's ``spot`` (src/emitters/spot.cpp, ``falloff_curve``) ramps *linearly in angle* from 1 at
``beam_width`` to 0 at ``cutoff_angle``; KHR_lights_punctual's reference ("Inner and Outer Cone Angles") is
quadratic in the cosine, f = clamp((cos θ − cos θ_o)/(cos θ_i − cos θ_o), 0, 1)², and three.js uses
smoothstep(cos θ_o, cos θ_i, cos θ) (lights_pars_begin.glsl ``getSpotAttenuation``). The three differ
inside the penumbra (at its middle, t = ½: 0.25, ≈ 0.5 and 0.5). So the reference sets
``beam_width = cutoff_angle = θ_o`` (Mitsuba's factor is 1 inside the cone, 0 outside) and multiplies by this
projected texture, which Mitsuba evaluates at uv = ½ + ½ (x/z, y/z)/tan θ_o of the local direction
(``direction_to_uv``): tan²θ = ((2u − 1)² + (2v − 1)²) tan²θ_o, cos θ = (1 + tan²θ)^(−½), and the profile
is evaluated analytically in float32 — no bitmap, no interpolation error.
"""

from __future__ import annotations

import math
from typing import Any

_REGISTERED: set[str] = set()
NAME = "khr_spot_profile"


def register() -> None:
    """Register the texture plugin with the current Mitsuba variant (idempotent)."""
    import drjit as dr
    import mitsuba as mi

    if mi.variant() in _REGISTERED:
        return

    class SpotProfile(mi.Texture):
        def __init__(self, props: Any) -> None:
            mi.Texture.__init__(self, props)
            self.tan_outer = float(props.get("tan_outer", 1.0))
            self.cos_inner = float(props.get("cos_inner", 1.0))
            self.cos_outer = float(props.get("cos_outer", 0.5))
            self.smooth = bool(props.get("smoothstep", False))

        def eval(self, si: Any, active: Any = True) -> Any:
            x = (2.0 * si.uv.x - 1.0) * self.tan_outer
            y = (2.0 * si.uv.y - 1.0) * self.tan_outer
            c = dr.rsqrt(1.0 + x * x + y * y)
            t = dr.clip((c - self.cos_outer) / (self.cos_inner - self.cos_outer), 0.0, 1.0)
            f = t * t * (3.0 - 2.0 * t) if self.smooth else t * t
            return mi.Color3f(f)

        def is_spatially_varying(self) -> bool:
            return True

        def to_string(self) -> str:
            return f"SpotProfile[cos_inner={self.cos_inner}, cos_outer={self.cos_outer}, smoothstep={self.smooth}]"

    mi.register_texture(NAME, lambda props: SpotProfile(props))
    _REGISTERED.add(mi.variant())


def texture_dict(inner_deg: float, outer_deg: float, profile: str) -> dict[str, Any]:
    """The ``texture`` entry of the Mitsuba ``spot`` dict (registers the plugin first)."""
    register()
    return {"type": NAME, "tan_outer": math.tan(math.radians(outer_deg)),
            "cos_inner": math.cos(math.radians(inner_deg)), "cos_outer": math.cos(math.radians(outer_deg)),
            "smoothstep": profile == "smoothstep"}
