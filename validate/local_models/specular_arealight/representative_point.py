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
from ...geometry import unit
from ...scenes.area_lights import tube_geometry
from ..brdf.common import Geometry, fresnel_schlick, ggx_d, smith_g1
from ..families import specular_arealight
from .common import brdf_params


def representative_point(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
                         views: np.ndarray, who: str, normalise: bool = True) -> np.ndarray:
    """L_o of Karis's representative point (eq. 10–14), (N, 3)."""
    if light.get("shape") != "sphere":
        raise ValidateError(f"technique '{who}' (specular_arealight): handles sphere lights only, got "
                            f"{light.get('shape')!r}")
    alpha, f0 = brdf_params(brdf, who)
    n, v = unit(np.asarray(normals, dtype=np.float64)), unit(np.asarray(views, dtype=np.float64))
    radius = float(light["radius"])
    to_c = np.asarray(light["center"], dtype=np.float64) - np.asarray(points, dtype=np.float64)
    dist = np.linalg.norm(to_c, axis=-1)
    r = 2.0 * np.sum(n * v, -1, keepdims=True) * n - v
    c2r = np.sum(to_c * r, -1, keepdims=True) * r - to_c
    t = np.clip(radius / np.maximum(np.linalg.norm(c2r, axis=-1, keepdims=True), 1e-300), 0.0, 1.0)
    l = unit(to_c + c2r * t)
    g = Geometry(n, l, v)
    spec = (ggx_d(g.ch, alpha) * smith_g1(g.cl, alpha, "ggx") * smith_g1(g.cv, alpha, "ggx")
            / (4.0 * np.maximum(g.cv, 1e-12)))  # f_r (n·l) with F = 1
    e_perp = float(light.get("radiance", 1.0)) * np.pi * radius ** 2 / dist ** 2
    scale = (alpha / np.clip(alpha + radius / (2.0 * dist), 0.0, 1.0)) ** 2 if normalise else np.ones_like(dist)
    return g.finish(fresnel_schlick(g.vh, f0) * (spec * e_perp * scale)[:, None])


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


def _ggx_point(alpha: float, f0: np.ndarray, n: np.ndarray, l: np.ndarray, v: np.ndarray,
               e_scaled: np.ndarray) -> np.ndarray:
    """F(v·h) f_r(l, v) (n·l) · e_scaled, (N, 3): GGX D, separable Smith G, Schlick F."""
    g = Geometry(n, l, v)
    spec = (ggx_d(g.ch, alpha) * smith_g1(g.cl, alpha, "ggx") * smith_g1(g.cv, alpha, "ggx")
            / (4.0 * np.maximum(g.cv, 1e-12)))
    return g.finish(fresnel_schlick(g.vh, f0) * (spec * e_scaled)[:, None])


def tube_light(light: Mapping[str, Any], who: str) -> tuple[np.ndarray, np.ndarray, float, float]:
    """(centre, unit axis, length ℓ ≥ 0, radius R > 0) of a ``'tube'`` light mapping; ValidateError otherwise."""
    if light.get("shape") != "tube":
        raise ValidateError(f"technique '{who}' (specular_arealight): handles tube lights only, got "
                            f"{light.get('shape')!r}")
    return tube_geometry(light, f"technique '{who}' (specular_arealight)")


def tube_solid_angle(center: np.ndarray, axis: np.ndarray, length: float, radius: float,
                     points: np.ndarray) -> np.ndarray:
    """Ω ≈ 2R (s₁/r₁ − s₀/r₀)/h + (πR²/2)(1/r₀² + 1/r₁²): the capsule's solid angle to first order in R/r, (N,)."""
    q = np.asarray(points, dtype=np.float64) - center
    s_p = q @ axis
    h = np.maximum(np.linalg.norm(q - s_p[:, None] * axis, axis=-1), 1e-300)
    s0, s1 = -0.5 * length - s_p, 0.5 * length - s_p
    r0, r1 = np.hypot(h, s0), np.hypot(h, s1)
    line = 2.0 * radius * (s1 * r0 - s0 * r1) / (h * r0 * r1)
    return line + 0.5 * np.pi * radius ** 2 * (1.0 / r0 ** 2 + 1.0 / r1 ** 2)


def representative_point_tube(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray,
                              normals: np.ndarray, views: np.ndarray, who: str, line_power: float = 1.0,
                              sphere_power: float = 2.0) -> np.ndarray:
    """L_o of Karis's tube light (eq. 19 + eq. 11 about the closest point), (N, 3), energy factor
    (α/α′_line)^line_power (α/α′_sphere)^sphere_power: (1, 2) is [1]'s, (0, 0) the unnormalised counterpart; other
    powers exist for the experiment's variants (a squared line factor: the lobe widened in both dimensions)."""
    alpha, f0 = brdf_params(brdf, who)
    c, ax, length, radius = tube_light(light, who)
    p = np.asarray(points, dtype=np.float64)
    n, v = unit(np.asarray(normals, dtype=np.float64)), unit(np.asarray(views, dtype=np.float64))
    r = 2.0 * np.sum(n * v, -1, keepdims=True) * n - v
    l0 = c - 0.5 * length * ax - p
    ld = length * ax
    rl0, rld = np.sum(r * l0, -1), r @ ld
    den = length ** 2 - rld ** 2
    t = np.where(den > 1e-12 * max(length, 1e-300) ** 2, (rl0 * rld - l0 @ ld) / np.where(den > 0.0, den, 1.0), 0.5)
    lt = l0 + np.clip(t, 0.0, 1.0)[:, None] * ld
    c2r = np.sum(lt * r, -1, keepdims=True) * r - lt
    s = np.clip(radius / np.maximum(np.linalg.norm(c2r, axis=-1, keepdims=True), 1e-300), 0.0, 1.0)
    l = unit(lt + c2r * s)
    dist = np.linalg.norm(c - p, axis=-1)
    e_perp = float(light.get("radiance", 1.0)) * tube_solid_angle(c, ax, length, radius, p)
    a_line = np.clip(alpha + 0.5 * np.clip(length / dist, 0.0, 1.0), 0.0, 1.0)
    a_sph = np.clip(alpha + radius / (2.0 * dist), 0.0, 1.0)
    scale = (alpha / a_line) ** line_power * (alpha / a_sph) ** sphere_power
    return _ggx_point(alpha, f0, n, l, v, e_perp * scale)


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


__all__ = ["representative_point", "representative_point_tube", "tube_light", "tube_solid_angle"]
