"""The technique families and their array contracts (one :class:`~.registry.Family` each).

Conventions shared by every family: world space is Mitsuba's, y up; directions are unit (N, 3)
float arrays; environments are lat-long radiance maps (H, W, 3) in Mitsuba's ``envmap`` convention
(see :mod:`validate.scenes.latlong`). Irradiance is E = ∫ L max(0, n·ω) dω (not E/π).

Families added later (classic lights, BRDFs, the überlight, …) call :func:`~.registry.define_family`
in their own module, the same way.
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
    "fn(shadow_map: ShadowMap (depth map rendered from the light, see local_models.shadow_map), light: DiscLight, "
    "points: (N, 3) receiver positions, normals: (N, 3)) -> (N,) visibility V' in [0, 1]",
    lambda shadow_map, light, points, normals, **_: (len(points),),
    lower=0.0, upper=1.0,
    bounds_reason="visibility is the unoccluded fraction of the light, in [0, 1]",
)

__all__ = ["irradiance", "specular", "arealight", "shadow"]
