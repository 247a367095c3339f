"""Karis 2013's representative-point sphere light, a technique of the ``specular_arealight`` family.

Karis [1] §"Area lights", eq. 10–14: the sphere light (centre c, radius R, radiance L_e) seen from p is replaced
by a point light at the point of the sphere closest to the mirror ray r = reflect(−v, n):

    L = c − p,   C = (L·r) r − L,   P = L + C · saturate(R/‖C‖),   l = P/‖P‖          (eq. 11)

lit with the sphere's illuminance at normal incidence, E_⊥ = L_e π R²/‖L‖² (the point light of the same power),
times (n·l), through the GGX BRDF f_r(l, v) (Walter et al. 2007 eq. 20, separable Smith G, Schlick F(v·h) with
``f0``), with the energy normalisation of the widened lobe

    α′ = saturate(α + R/(2‖L‖)),   L_o = (α/α′)² f_r(l, v) (n·l) E_⊥                         (eq. 10, 14)

Without the normalisation (``representative_point_unnormalized``) the highlight of a rough-enough surface gathers
the whole sphere's power into the sharp lobe: the paper's reason for eq. 14.

Tube lights ([1] p. 16–17, "Tube lights"; ``representative_point_tube``). A tube is the segment c ± (ℓ/2)a swept by a
sphere of radius R (a capsule). With L₀ = c − (ℓ/2)a − p and L_d = ℓa, the point of the segment closest to the mirror
ray is ([1] eq. 19, the simpler of its two forms; the paper prefers it to the smallest-angle point of eq. 18)

    t = saturate( ((r·L₀)(r·L_d) − L₀·L_d) / (‖L_d‖² − (r·L_d)²) ),   L_t = L₀ + t L_d,

and the sphere's representative point (eq. 11) about L_t with the tube's radius R gives l. Energy: the segment widens
the lobe along one dimension only, so its normalisation is the square root of the sphere's (the "line" form):

    α′_line = saturate(α + saturate(ℓ/‖c − p‖)/2),   α′_sphere = saturate(α + R/(2‖c − p‖)),
    L_o = (α/α′_line) (α/α′_sphere)² f_r(l, v) (n·l) E_⊥.

Source of the exact form: the course notes' text was not among the searchable corpora; the form above is the one in
public engine code that implements [1]'s "AreaLightSpecular": FlaxEngine/FlaxEngine
``Source/Shaders/LightingCommon.hlsl`` (``lineAngle = saturate(SourceLength·invDist)``,
``energy *= m / saturate(m + 0.5·lineAngle)``, then ``energy *= Square(m / saturate(m + 0.5·sphereAngle))`` with
m = roughness² = α and invDist the inverse distance to the light's centre, before the representative point moves),
and Robert42/gl-research-toolkit (``mrp_specular_correction_factor_line`` = α/α′, α′ = saturate(α + len/(2d)); the
area factor its square). A forum thread quoting [1]'s tube code (gamedev.net, "Tube AreaLight – Falloff problem",
2014) gives the same eq. 19 closest point. Both factors use the centre distance, as those sources do.

E_⊥ of a tube. [1] lights the representative direction with the light's own point-light illuminance; for a
uniform-radiance emitter (this family's contract) the sphere's E_⊥ = L_e πR²/‖L‖² is L_e times its solid angle to
first order in R/d. The tube's analogue used here is L_e times the capsule's solid angle to first order in R/r (the
silhouette is the segment's projection widened by R — a stadium — so Ω ≈ ∫ 2R sin ψ(s)/r(s)² ds + πR²/r²):

    E_⊥ = L_e [ 2R (s₁/r₁ − s₀/r₀)/h + (πR²/2)(1/r₀² + 1/r₁²) ],

h the receiver's distance to the axis, s₀, s₁ the ends' axial coordinates from the foot of the perpendicular,
r₀, r₁ their distances (∫ h/(h² + s²)^{3/2} ds = s/(h√(h² + s²))). At ℓ = 0 the technique is exactly the sphere's.
``representative_point_tube_unnormalized`` leaves both factors out (the regression counterpart).

References
  [1] B. Karis, "Real shading in Unreal Engine 4", SIGGRAPH 2013 course (Physically Based Shading in Theory and
      Practice), pp. 14–17.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...scenes.area_lights import tube_geometry
from ..families import specular_arealight
from ..precision import constants_dr, packed_to_dr, rgb_to_np, to_np, vec_to_dr
from .common import TINY, Vec, axpy, brdf_params, dot, ggx_point_dr, unit_dr


def _receivers(points: np.ndarray, normals: np.ndarray, views: np.ndarray) -> tuple[Vec, Vec, Vec, Vec]:
    """p, unit n, unit v and the mirror direction r = 2(n·v) n − v as drjit vectors of the active dtype (one packed
    input, :func:`~..precision.packed_to_dr`)."""
    cols = [np.asarray(a, dtype=np.float64).reshape(-1, 3).T for a in (points, normals, views)]
    c = packed_to_dr(*cols[0], *cols[1], *cols[2])
    n, v = unit_dr((c[3], c[4], c[5])), unit_dr((c[6], c[7], c[8]))
    return (c[0], c[1], c[2]), n, v, axpy(2.0 * dot(n, v), n, (-v[0], -v[1], -v[2]))


def _toward_sphere(to_c: Vec, r: Vec, radius: Any) -> Vec:
    """l: the unit direction to eq. 11's representative point, P = L + C·saturate(R/‖C‖), C = (L·r) r − L."""
    import drjit as dr

    c2r = axpy(dot(to_c, r), r, (-to_c[0], -to_c[1], -to_c[2]))
    t = dr.clip(radius / dr.maximum(dr.sqrt(dot(c2r, c2r)), TINY), 0.0, 1.0)
    return unit_dr(axpy(t, c2r, to_c))


def representative_point(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
                         views: np.ndarray, who: str, normalise: bool = True) -> np.ndarray:
    """L_o of Karis's representative point (eq. 10–14), (N, 3); per receiver in drjit, in the active dtype
    (:mod:`..precision`: the family's float32)."""
    import drjit as dr

    if light.get("shape") != "sphere":
        raise ValidateError(f"technique '{who}' (specular_arealight): handles sphere lights only, got "
                            f"{light.get('shape')!r}")
    alpha0, f0 = brdf_params(brdf, who)
    r0 = float(light["radius"])
    # the light's and the BRDF's numbers opaque (a new light or α reuses the kernel), products formed in float64
    # as the literals were
    cx, cy, cz, radius, e0, alpha = constants_dr(np.r_[np.asarray(light["center"], dtype=np.float64), r0,
                                                       float(light.get("radiance", 1.0)) * np.pi * r0 ** 2, alpha0])
    p, n, v, r = _receivers(points, normals, views)
    to_c = (cx - p[0], cy - p[1], cz - p[2])
    dist2 = dot(to_c, to_c)
    l = _toward_sphere(to_c, r, radius)
    e_perp = e0 / dist2
    if normalise:
        a1 = alpha / dr.clip(alpha + radius / (2.0 * dr.sqrt(dist2)), 0.0, 1.0)
        e_perp = e_perp * a1 * a1
    return rgb_to_np(*ggx_point_dr(alpha0, f0, n, l, v, e_perp), len(np.asarray(points).reshape(-1, 3)))


@specular_arealight.register("representative_point", "Karis 2013 representative point on the sphere closest to the "
                             "mirror ray, with the (α/α′)² energy normalisation", shapes=("sphere",))
def karis_sphere(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
                 views: np.ndarray) -> np.ndarray:
    return representative_point(light, brdf, points, normals, views, "representative_point")


@specular_arealight.register("representative_point_unnormalized", "Karis 2013 representative point without the "
                             "(α/α′)² normalisation (eq. 14 left out)", shapes=("sphere",))
def karis_sphere_unnormalized(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray,
                              normals: np.ndarray, views: np.ndarray) -> np.ndarray:
    return representative_point(light, brdf, points, normals, views, "representative_point_unnormalized",
                                normalise=False)


def tube_light(light: Mapping[str, Any], who: str) -> tuple[np.ndarray, np.ndarray, float, float]:
    """(centre, unit axis, length ℓ ≥ 0, radius R > 0) of a ``'tube'`` light mapping; ValidateError otherwise."""
    if light.get("shape") != "tube":
        raise ValidateError(f"technique '{who}' (specular_arealight): handles tube lights only, got "
                            f"{light.get('shape')!r}")
    return tube_geometry(light, f"technique '{who}' (specular_arealight)")


def tube_solid_angle_dr(center: np.ndarray, axis: np.ndarray, length: float, radius: float, p: Vec) -> Any:
    """Ω ≈ 2R (s₁/r₁ − s₀/r₀)/h + (πR²/2)(1/r₀² + 1/r₁²): the capsule's solid angle to first order in R/r, at the
    receivers ``p`` (a drjit vector)."""
    import drjit as dr

    # the tube's numbers opaque (a new tube reuses the kernel), the products formed in float64 as the literals were
    k = constants_dr(np.r_[np.asarray(axis, dtype=np.float64)[:3], np.asarray(center, dtype=np.float64)[:3],
                           -0.5 * length, 0.5 * length, 2.0 * radius, 0.5 * np.pi * radius ** 2])
    ax, cen, lo, hi, two_r, cap = (k[0], k[1], k[2]), k[3:6], k[6], k[7], k[8], k[9]
    q = (p[0] - cen[0], p[1] - cen[1], p[2] - cen[2])
    s_p = dot(q, ax)
    perp = axpy(-s_p, ax, q)
    h = dr.maximum(dr.sqrt(dot(perp, perp)), TINY)
    s0, s1 = lo - s_p, hi - s_p
    r0, r1 = dr.sqrt(h * h + s0 * s0), dr.sqrt(h * h + s1 * s1)
    line = two_r * (s1 * r0 - s0 * r1) / (h * r0 * r1)
    return line + cap * (1.0 / (r0 * r0) + 1.0 / (r1 * r1))


def tube_solid_angle(center: np.ndarray, axis: np.ndarray, length: float, radius: float,
                     points: np.ndarray) -> np.ndarray:
    """:func:`tube_solid_angle_dr` at numpy ``points`` (N, 3), (N,), in the active dtype."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    return to_np(tube_solid_angle_dr(center, axis, length, radius, vec_to_dr(pts)), (len(pts),))


def representative_point_tube(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray,
                              normals: np.ndarray, views: np.ndarray, who: str, line_power: float = 1.0,
                              sphere_power: float = 2.0) -> np.ndarray:
    """L_o of Karis's tube light (eq. 19 + eq. 11 about the closest point), (N, 3), energy factor
    (α/α′_line)^line_power (α/α′_sphere)^sphere_power: (1, 2) is [1]'s, (0, 0) the unnormalised counterpart; other
    powers exist for the experiment's variants (a squared line factor: the lobe widened in both dimensions). Per
    receiver in drjit, in the active dtype (:mod:`..precision`: the family's float32)."""
    import drjit as dr

    alpha, f0 = brdf_params(brdf, who)
    c, ax, length, radius = tube_light(light, who)
    p, n, v, r = _receivers(points, normals, views)
    base = c - 0.5 * length * ax
    # the tube's and the BRDF's numbers opaque (length, axis, ends, radius, radiance, α: a new tube or α reuses the
    # kernel), the products formed in float64 as the literals were
    k = constants_dr(np.r_[[float(length * a) for a in ax], [float(x) for x in base], [float(x) for x in c],
                           length ** 2, 1e-12 * max(length, 1e-30) ** 2, length, radius,
                           float(light.get("radiance", 1.0)), alpha])
    ld, b0, cc = (k[0], k[1], k[2]), k[3:6], k[6:9]
    length2, den_floor, length_k, radius_k, radiance, alpha_k = k[9:15]
    l0 = (b0[0] - p[0], b0[1] - p[1], b0[2] - p[2])
    rl0, rld = dot(r, l0), dot(r, ld)
    den = length2 - rld * rld
    ok = den > den_floor
    t = dr.select(ok, (rl0 * rld - dot(l0, ld)) / dr.select(den > 0.0, den, 1.0), 0.5)
    lt = axpy(dr.clip(t, 0.0, 1.0), ld, l0)
    l = _toward_sphere(lt, r, radius_k)
    to_c = (cc[0] - p[0], cc[1] - p[1], cc[2] - p[2])
    dist = dr.sqrt(dot(to_c, to_c))
    e_perp = radiance * tube_solid_angle_dr(c, ax, length, radius, p)
    a_line = dr.clip(alpha_k + 0.5 * dr.clip(length_k / dist, 0.0, 1.0), 0.0, 1.0)
    a_sph = dr.clip(alpha_k + radius_k / (2.0 * dist), 0.0, 1.0)
    scale = dr.power(alpha_k / a_line, line_power) * dr.power(alpha_k / a_sph, sphere_power)
    return rgb_to_np(*ggx_point_dr(alpha, f0, n, l, v, e_perp * scale), len(np.asarray(points).reshape(-1, 3)))


@specular_arealight.register("representative_point_tube", "Karis 2013 tube light: closest point of the segment to the "
                             "mirror ray (eq. 19), the sphere representative point about it, energy (α/α′_line)"
                             "(α/α′_sphere)²", shapes=("tube",))
def karis_tube(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
               views: np.ndarray) -> np.ndarray:
    return representative_point_tube(light, brdf, points, normals, views, "representative_point_tube")


@specular_arealight.register("representative_point_tube_unnormalized", "Karis 2013 tube light without its energy "
                             "normalisation (neither the line nor the sphere factor)", shapes=("tube",))
def karis_tube_unnormalized(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray,
                            normals: np.ndarray, views: np.ndarray) -> np.ndarray:
    return representative_point_tube(light, brdf, points, normals, views, "representative_point_tube_unnormalized",
                                     line_power=0.0, sphere_power=0.0)


__all__ = ["representative_point", "representative_point_tube", "tube_light", "tube_solid_angle",
           "tube_solid_angle_dr"]
