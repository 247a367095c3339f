"""The technique families and their array contracts (one :class:`~.registry.Family` each).

Conventions shared by every family: world space is Mitsuba's, y up; directions are unit (N, 3)
float arrays; environments are lat-long radiance maps (H, W, 3) in Mitsuba's ``envmap`` convention
(see :mod:`validate.scenes.latlong`). Irradiance is E = ∫ L max(0, n·ω) dω (not E/π).

Every family is defined here, in the order the suite has always listed them; its techniques live in the
folder of the same name (``local_models/<family>/``, one file per technique, shared code in a module of the
family that registers nothing). A plug-in family may still call :func:`~.registry.define_family` itself.
"""

from __future__ import annotations

from .registry import define_family

NEGATIVE_ALLOWED = ("no lower bound: truncated-SH approximations legitimately go below zero (R&H 2001's "
                    "order-2 clamped cosine 3/32 + x/2 + 15x²/32 reaches −0.040 at x = −8/15); that error is "
                    "measured by the metrics, not refused")


irradiance = define_family(
    "irradiance",
    "fn(radiance: (H, W, 3) lat-long map, normals: (N, 3) unit) -> (N, 3) irradiance E at each normal "
    "(E = ∫ L max(0, n·ω) dω, not E/π); may be negative",
    lambda radiance, normals, **_: (len(normals), 3),
    bounds_reason=NEGATIVE_ALLOWED,
)

specular = define_family(
    "specular",
    "fn(radiance: (H, W, 3) lat-long map, brdf: mapping {'model': 'phong'|'ggx'|..., parameters}, normals: (N, 3), "
    "views: (N, 3) unit toward the viewer) -> (N, 3) outgoing radiance L_o = ∫ L f_r cos θ dω; "
    "a technique lists the BRDF models it supports as meta brdf=(...)",
    lambda radiance, brdf, normals, views, **_: (len(normals), 3),
    lower=0.0,
    bounds_reason="outgoing radiance of a non-negative environment through a non-negative BRDF is ≥ 0",
)

arealight = define_family(
    "arealight",
    "fn(light: mapping {'shape': 'disc'|'sphere'|'rectangle', 'center': (3,), 'normal': (3,), 'radius' or "
    "'size', 'radiance': float}, points: (N, 3), normals: (N, 3) unit) -> (N,) irradiance at each receiver; "
    "may be negative",
    lambda light, points, normals, **_: (len(points),),
    bounds_reason=NEGATIVE_ALLOWED,
)

shadow = define_family(
    "shadow",
    "fn(shadow_map: ShadowMap (depth map rendered from the light, see local_models.shadow.shadow_map), "
    "light: DiscLight, "
    "points: (N, 3) receiver positions, normals: (N, 3)) -> (N,) visibility V' in [0, 1]",
    lambda shadow_map, light, points, normals, **_: (len(points),),
    lower=0.0, upper=1.0,
    bounds_reason="visibility is the unoccluded fraction of the light, in [0, 1]",
)

brdf = define_family(
    "brdf",
    "fn(params: mapping of physical parameters (albedo, ks, exponent, phong_exponent, alpha, distribution, eta, k, "
    "sigma, minnaert_k), normals: (N, 3) unit, lights: (N, 3) unit towards the light, views: (N, 3) unit towards "
    "the viewer) -> (N, 3) cosine-weighted BRDF f_r(l, v)·max(0, n·l) (= Mitsuba's BSDF.eval with wi = v, wo = l)",
    lambda params, normals, lights, views, **_: (len(normals), 3),
    lower=0.0,
    bounds_reason="a BRDF times a clamped cosine is non-negative",
)

light = define_family(
    "light",
    "fn(light: mapping {'type': point|spot|directional|rectangle|disk|sphere, 'position', 'intensity' (W/sr) | "
    "'irradiance' (W/m²) | 'radiance' (W/(m² sr)), 'direction', 'cutoff_angle', 'beam_width', 'exponent', "
    "'normal', 'axes', 'radius', …}, points: (N, 3), normals: (N, 3) unit, visible=None (shadow-ray test "
    "(origins, normals, targets) -> bool)) -> (N,) irradiance E in W/m² (not E/π); a technique lists the light "
    "types it models as meta lights=(...)",
    lambda light, points, normals, **_: (len(points),),
    lower=0.0,
    bounds_reason="the irradiance from a light of non-negative power is ≥ 0",
)

specular_arealight = define_family(
    "specular_arealight",
    "fn(light: mapping {'shape': 'rectangle'|'disc'|'sphere'|'tube', 'center', 'normal', 'radius' or 'size' + "
    "'tangent', 'axis' + 'length' (tube capsule), 'radiance'}, brdf: mapping {'alpha': GGX α, 'f0': F0}, points: "
    "(N, 3), normals: (N, 3) unit, views: (N, 3) unit towards the viewer) -> (N, 3) outgoing radiance "
    "∫_light L_e f_r (n·l) dω of a GGX microfacet BRDF",
    lambda light, brdf, points, normals, views, **_: (len(points), 3),
    lower=0.0,
    bounds_reason="reflected radiance of a non-negative emitter through a non-negative BRDF is ≥ 0",
)

uberlight = define_family(
    "uberlight",
    "fn(light: mapping {'position': (3,), 'axes': (3, 3) rows x, y, z (forward), 'intensity', 'width', 'height', "
    "'width_edge', 'height_edge', 'roundness', 'near', 'far', 'near_edge', 'far_edge', …}, points: (N, 3), "
    "normals: (N, 3) unit, views: (N, 3) unit toward the viewer, material: {'albedo': (N,) or float, 'ks', "
    "'specular_exponent'}, shadow: (N,) in [0, 1] or None) -> (N,) outgoing radiance",
    lambda light, points, normals, views, material, **_: (len(points),),
    lower=0.0,
    bounds_reason="a non-negative light through a non-negative reflection gives radiance ≥ 0",
)

__all__ = ["irradiance", "specular", "arealight", "shadow", "brdf", "light", "specular_arealight", "uberlight"]
