"""The textbooks' classic lights as a technique family ``light``: directional, point, spot [1, 2].

Family contract (checked by ``light.call``)::

    fn(light: mapping, points: (N, 3), normals: (N, 3) unit, visible=None) -> (N,) irradiance E (W m⁻²)

``light`` describes one source in physical units (:meth:`validate.scenes.light_scenes.Light.as_mapping`):
``type`` ∈ point | spot | directional | rectangle | disk | sphere; ``position`` (3,); ``intensity``
I (W sr⁻¹, point/spot, on the axis for a spot); ``direction`` (unit, where the light travels: a
directional light's rays or a spot's axis); ``irradiance`` E⊥ (W m⁻², directional); ``radiance`` L
(W m⁻² sr⁻¹, area lights); spot ``cutoff_angle``/``beam_width`` (degrees) and ``exponent`` f;
rectangle ``normal`` and ``axes`` (2, 3) half-edge vectors; disc ``normal``, ``radius`` and ``axes``
(2, 3) unit in-plane vectors; sphere ``radius``. Techniques may read extra keys (``grid``,
``range``, …) and state them. ``visible``, when given, is the scene's shadow-ray test
``visible(origins (M, 3), normals (M, 3), targets (M, 3)) -> (M,) bool`` (True: the segment from the
receiver, lifted along its normal, to the target is free); ``None`` means unshadowed.

Each technique declares the light types it models as meta ``lights=(...)``; an experiment gives it
only those. E is the irradiance on the receiver's surface (a Lambertian receiver of albedo ρ
reflects L_o = ρ E / π), not E/π. It is ≥ 0: every classic model is.

The formulas, receiver at x with unit normal n, light position p, d = |p − x|, ω = (p − x)/d:

* directional [1, ch. 7]: E = E⊥ max(0, n·(−direction)) V;
* point, inverse square [2, eq. 6.37–6.40]: E = I max(0, n·ω) / d² · V;
* point, two-sided (Red Book ex. 7.11, the back face lit with −n): E = I |n·ω| / d² · V;
* spot [1, ch. 7; 2, eq. 6.41]: I(α) = I₀ cos^f α for α < cutoff, 0 beyond, with
  cos α = (−ω)·axis; E = I(α) max(0, n·ω) / d² · V;
* spot with Mitsuba's profile (src/emitters/spot.cpp ``falloff_curve``): I(α) = I₀ for α ≤ beam,
  I₀ (cutoff − α)/(cutoff − beam) between, 0 beyond the cutoff (linear in α).

References
  [1] D. Shreiner et al., *OpenGL Programming Guide* ("Red Book"), 8th ed., ch. 7 (Light and
      Shadow), Examples 7.3–7.8 and 7.11.
  [2] F. Ganovelli et al., *Introduction to Computer Graphics*, CRC 2014, §6.7 (eq. 6.37–6.43).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from ..families import light
from ..precision import packed_to_dr
from .common import DIRECTIONAL_REACH, Visible, as_points, opaque, point_irradiance, require, shadow


@light.register("directional", "directional light: E = E⊥ max(0, n·l) V (Red Book ch. 7)", lights=("directional",),
                thresholds={"directional.max": 1e-4},
                source="float32 rounding of n·l (ε = 6·10⁻⁸, ≤ 10⁻⁵ relative) in Mitsuba's directional emitter and "
                       "here, 10× margin (PBRT 4th ed. §12.4: E = E⊥ cos θ)")
def directional(light_map: Mapping[str, Any], points: Any, normals: Any, visible: Visible | None = None) -> np.ndarray:
    """E = E⊥ max(0, n·l) V, l = −direction [1, ch. 7]."""
    import drjit as dr

    require(light_map, "direction", "irradiance", kinds=("directional",))
    p, n = as_points(points, normals)
    to_light = -np.asarray(light_map["direction"], dtype=np.float64)
    to_light /= np.linalg.norm(to_light)
    *lk, e_perp = opaque(*to_light, float(light_map["irradiance"]))
    cols = packed_to_dr(*(n[:, k] for k in range(3)))  # one packed input (precision.packed_to_dr)
    cos_t = sum(cols[k] * lk[k] for k in range(3))
    out = np.array(e_perp * dr.maximum(cos_t, 0.0), dtype=np.float64)
    lit = out > 0
    if visible is not None and lit.any():
        out[lit] *= shadow(visible, p[lit], n[lit], p[lit] + DIRECTIONAL_REACH * to_light)
    return out


@light.register("point_inverse_square", "point light, E = I max(0, n·ω)/d² V (Ganovelli eq. 6.37–6.40)",
                lights=("point",), thresholds={"point.max": 1e-4},
                source="float32 rounding: positions and distances in float32 (ε = 6·10⁻⁸) through ≈ 20 operations "
                       "in Mitsuba's point emitter and here, ≤ 10⁻⁵ relative; 10⁻⁴ leaves 10× margin while a 1 % "
                       "intensity error is 100× above it (PBRT 4th ed. §12.1: E = I cos θ / r²)")
def point_inverse_square(light_map: Mapping[str, Any], points: Any, normals: Any,
                         visible: Visible | None = None) -> np.ndarray:
    """E = I max(0, n·ω) / d² · V [2, eq. 6.37–6.40]."""
    require(light_map, kinds=("point",))
    return point_irradiance(light_map, points, normals, visible)


@light.register("point_two_sided", "point light with two-sided lighting: E = I |n·ω|/d² V (Red Book ex. 7.11)",
                lights=("point",))
def point_two_sided(light_map: Mapping[str, Any], points: Any, normals: Any,
                    visible: Visible | None = None) -> np.ndarray:
    """E = I |n·ω| / d² · V: the back face is lit as if its normal were flipped [1, ex. 7.11]."""
    require(light_map, kinds=("point",))
    return point_irradiance(light_map, points, normals, visible, two_sided=True)


def spot_cos_profile(exponent: float, cutoff_deg: float) -> Callable[[Any], Any]:
    """I(α)/I₀ = cos^f α for cos α > cos(cutoff), else 0 [1, ch. 7; 2, eq. 6.41]."""
    import drjit as dr

    from ..brdf.common import power_dr  # noqa: PLC0415

    def profile(cos_a: Any) -> Any:
        (cos_cut,) = opaque(float(np.cos(np.radians(cutoff_deg))))  # opaque: a new cutoff reuses the kernel
        return dr.select(cos_a > cos_cut, power_dr(dr.maximum(cos_a, 0.0), float(exponent)), 0.0)
    return profile


def spot_mitsuba_profile(beam_deg: float, cutoff_deg: float) -> Callable[[Any], Any]:
    """Mitsuba's ``falloff_curve``: 1 inside the beam, (cutoff − α)/(cutoff − beam) to the cutoff, 0 beyond."""
    import drjit as dr

    cut, beam = float(np.radians(cutoff_deg)), float(np.radians(beam_deg))
    inv_width = 1.0 / (cut - beam) if cut > beam else 0.0
    cos_cut, cos_beam = float(np.cos(cut)), float(np.cos(beam))

    def profile(cos_a: Any) -> Any:
        k_cut, k_inv, k_cos_cut, k_cos_beam = opaque(cut, inv_width, cos_cut, cos_beam)  # a new spot, same kernel
        ramp = (k_cut - dr.acos(dr.clip(cos_a, -1.0, 1.0))) * k_inv
        return dr.select(cos_a > k_cos_cut, dr.select(cos_a >= k_cos_beam, 1.0, ramp), 0.0)
    return profile


@light.register("spot_cos_f", "spot light I₀ cos^f α inside the cutoff (Red Book ch. 7, Ganovelli eq. 6.41)",
                lights=("spot",))
def spot_cos_f(light_map: Mapping[str, Any], points: Any, normals: Any, visible: Visible | None = None) -> np.ndarray:
    """I(α) = I₀ cos^f α for α < cutoff, 0 beyond; f = ``exponent`` (default 1) [1, ch. 7; 2, eq. 6.41]."""
    require(light_map, "direction", "cutoff_angle", kinds=("spot",))
    prof = spot_cos_profile(float(light_map.get("exponent", 1.0)), float(light_map["cutoff_angle"]))
    return point_irradiance(light_map, points, normals, visible, profile=prof)


@light.register("spot_mitsuba", "spot light with Mitsuba's linear-in-angle falloff between beam width and cutoff",
                lights=("spot",), thresholds={"spot.max": 1e-4},
                source="float32 rounding as for point_inverse_square (≤ 10⁻⁵ relative; Mitsuba spot.cpp "
                       "falloff_curve reproduced term by term), 10× margin")
def spot_mitsuba(light_map: Mapping[str, Any], points: Any, normals: Any, visible: Visible | None = None) -> np.ndarray:
    """Mitsuba's spot: I₀ · falloff_curve(α) (src/emitters/spot.cpp)."""
    require(light_map, "direction", "cutoff_angle", "beam_width", kinds=("spot",))
    prof = spot_mitsuba_profile(float(light_map["beam_width"]), float(light_map["cutoff_angle"]))
    return point_irradiance(light_map, points, normals, visible, profile=prof)
