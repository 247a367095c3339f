"""The technique families and their array contracts (one :class:`~.registry.Family` each).

Conventions shared by every family: world space is Mitsuba's, y up; directions are unit (N, 3)
float arrays; environments are lat-long radiance maps (H, W, 3) in Mitsuba's ``envmap`` convention
(see :mod:`validate.scenes.latlong`). Irradiance is E = ∫ L max(0, n·ω) dω (not E/π).

Every family is defined here, in the order the suite has always listed them; its techniques live in the
folder of the same name (``local_models/<family>/``, one file per technique, shared code in a module of the
family that registers nothing). A plug-in family may still call :func:`~.registry.define_family` itself.

Precision policy (:mod:`.precision`): each family states the drjit float dtype its techniques compute in,
and why; :meth:`~.registry.Family.call` makes it active, the techniques convert with ``precision.to_dr``.

================== ========= ===============================================================================
family             dtype     why
================== ========= ===============================================================================
irradiance         float32   a shader technique: the per-normal evaluation runs in a fragment shader
                             (``sh9.glsl``); per-environment set-up (the SH projection) is numpy float64
specular           float32   a shader technique (prefiltered maps, split sum: texture reads in a shader)
arealight          float64   the suite's tolerance, 10⁻⁵ of π sin²σ for a closed form (arealights'
                             CAP_QUADRATURE_TOLERANCE): a cap's zonal SH coefficients z_l ∝ P_{l−1}(cos α) −
                             P_{l+1}(cos α) cancel; per receiver in float32 they are off by 1.6·10⁻⁴ (l ≤ 2)
                             to 3.4·10⁻⁴ (l ≤ 8) of π sin²σ at sin²σ = 10⁻⁴ (4.2·10⁻⁵ at 10⁻³), the
                             horizon-clipped cap by 2.3·10⁻⁵ at 10⁻⁴ (tests/local_models/test_precision.py)
shadow             float32   a shader technique: depth and moment maps are 32-bit float textures (MSM's bias
                             α = 3·10⁻⁵ and ESM's c = 80 are sized for float32, Peters & Klein 2015, Annen 2008)
brdf               float32   a shader technique, compared with Mitsuba's float32 BSDF.eval
light              float32   a shader technique (per-fragment attenuation)
specular_arealight float32   a shader technique (LTC, representative point: per-fragment)
uberlight          float32   a shader technique (RenderMan / Orange Book uberlight shader)
================== ========= ===============================================================================
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
    precision="float32",
    precision_reason=("a shader technique: the per-normal evaluation runs in a fragment shader (sh9.glsl); per-"
                      "environment set-up (the SH projection) may be numpy float64"),
)

specular = define_family(
    "specular",
    "fn(radiance: (H, W, 3) lat-long map, brdf: mapping {'model': 'phong'|'ggx'|..., parameters}, normals: (N, 3), "
    "views: (N, 3) unit toward the viewer) -> (N, 3) outgoing radiance L_o = ∫ L f_r cos θ dω; "
    "a technique lists the BRDF models it supports as meta brdf=(...)",
    lambda radiance, brdf, normals, views, **_: (len(normals), 3),
    lower=0.0,
    bounds_reason="outgoing radiance of a non-negative environment through a non-negative BRDF is ≥ 0",
    precision="float32",
    precision_reason="a shader technique: prefiltered maps and the split sum are texture reads in a fragment shader",
)

arealight = define_family(
    "arealight",
    "fn(light: mapping {'shape': 'disc'|'sphere'|'rectangle', 'center': (3,), 'normal': (3,), 'radius' or "
    "'size', 'radiance': float}, points: (N, 3), normals: (N, 3) unit) -> (N,) irradiance at each receiver; "
    "may be negative",
    lambda light, points, normals, **_: (len(points),),
    bounds_reason=NEGATIVE_ALLOWED,
    precision="float64",
    precision_reason=("the suite's tolerance, 1e-5 of π sin²σ for a closed form (arealights "
                      "CAP_QUADRATURE_TOLERANCE): in float32 a cap's zonal SH coefficients z_l ∝ P_{l−1}(cos α) − "
                      "P_{l+1}(cos α) cancel, off by 1.6e-4 (l ≤ 2) to 3.4e-4 (l ≤ 8) of π sin²σ at sin²σ = 1e-4, "
                      "4.2e-5 at 1e-3, and the horizon-clipped cap by 2.3e-5 at 1e-4; float64 holds 1e-11"),
)

shadow = define_family(
    "shadow",
    "fn(shadow_map: ShadowMap (depth map rendered from the light, see local_models.shadow.shadow_map), "
    "light: DiscLight, "
    "points: (N, 3) receiver positions, normals: (N, 3)) -> (N,) visibility V' in [0, 1]",
    lambda shadow_map, light, points, normals, **_: (len(points),),
    lower=0.0, upper=1.0,
    bounds_reason="visibility is the unoccluded fraction of the light, in [0, 1]",
    precision="float32",
    precision_reason=("a shader technique: depth and moment maps are 32-bit float textures (MSM's α = 3e-5 and ESM's c "
                      "= 80 are sized for float32)"),
)

brdf = define_family(
    "brdf",
    "fn(params: mapping of physical parameters (albedo, ks, exponent, phong_exponent, alpha, distribution, eta, k, "
    "sigma, minnaert_k), normals: (N, 3) unit, lights: (N, 3) unit towards the light, views: (N, 3) unit towards "
    "the viewer) -> (N, 3) cosine-weighted BRDF f_r(l, v)·max(0, n·l) (= Mitsuba's BSDF.eval with wi = v, wo = l)",
    lambda params, normals, lights, views, **_: (len(normals), 3),
    lower=0.0,
    bounds_reason="a BRDF times a clamped cosine is non-negative",
    precision="float32",
    precision_reason="a shader technique, compared with Mitsuba's float32 BSDF.eval",
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
    precision="float32",
    precision_reason="a shader technique (per-fragment attenuation)",
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
    precision="float32",
    precision_reason="a shader technique (LTC, representative point: per-fragment)",
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
    precision="float32",
    precision_reason="a shader technique (the RenderMan / Orange Book uberlight shader)",
)

__all__ = ["irradiance", "specular", "arealight", "shadow", "brdf", "light", "specular_arealight", "uberlight"]
