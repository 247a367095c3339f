"""The scene of experiment ``ibl``: its procedural environments, the key light, the materials and the BRDF cases
the ``specular`` family is compared on (each as the family's mapping and as Mitsuba's BSDF dict).

What the experiment sweeps is in :mod:`validate.experiments.ibl.settings`; the render jobs built from this scene
are :func:`validate.experiments.ibl.compute.build_scene`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ValidateError
from . import latlong, procedural
from .environment import Environment

PHONG_PLUGIN = "modphong"  # the modified-Phong BSDF's name in Mitsuba (registered by validate.reference.ibl_render)

ALBEDO = 0.8  # grey Lambertian albedo of the diffuse renders
PLASTIC_RHO = 0.5  # roughplastic's default diffuse reflectance
PLASTIC_ETA = 1.49  # coat IOR (polypropylene, Mitsuba's default int_ior), over ext_ior = 1
BLEND_WEIGHT = 0.3  # blendbsdf weight of the Phong lobe in the mixing-shader render
BLEND_EXPONENT = 100.0
CAMERA_OFFSET_DEG = 6.0  # sphere camera: 6° off the key light, so the highlight sits at θ_v ≈ 3°
DENT_CAMERA_OFFSET_DEG = 60.0  # dented sphere: lit from the side
ANGLE_BINS = np.arange(0.0, 91.0, 10.0)  # view-angle bands θ_v (degrees)
RENDER_ENV = "disc_on_sky"


@dataclass(frozen=True)
class BrdfCase:
    """One BRDF the ``specular`` family is compared on: the family's mapping and Mitsuba's BSDF dict."""

    key: str  # "phong_10", "ggx_0.3", "ggx_plastic_0.3"
    label: str
    group: str
    brdf: dict
    bsdf: dict

    @property
    def model(self) -> str:
        return str(self.brdf["model"])


def brdf_cases(exponents: tuple[float, ...], alphas: tuple[float, ...]) -> list[BrdfCase]:
    """Modified Phong at every exponent, GGX conductor (F = 1: Mitsuba's default) and plastic at every α."""
    cases = [BrdfCase(f"phong_{s:g}", f"s = {s:g}", "modified Phong", {"model": "phong", "exponent": s},
                      {"type": PHONG_PLUGIN, "exponent": s}) for s in exponents]
    for a in alphas:
        cases.append(BrdfCase(f"ggx_{a:g}", f"α = {a:g}", "roughconductor (GGX)", {"model": "ggx", "alpha": a},
                              {"type": "roughconductor", "distribution": "ggx", "alpha": a}))
        cases.append(BrdfCase(f"ggx_plastic_{a:g}", f"α = {a:g}", "roughplastic (GGX)",
                              {"model": "ggx_plastic", "alpha": a, "eta": PLASTIC_ETA, "rho": PLASTIC_RHO},
                              {"type": "roughplastic", "distribution": "ggx", "alpha": a, "int_ior": PLASTIC_ETA,
                               "ext_ior": 1.0, "diffuse_reflectance": {"type": "rgb", "value": [PLASTIC_RHO] * 3}}))
    return cases


def make_environment(name: str, scale: int) -> Environment:
    """The sweep's procedural environments at 1/scale of their full resolution."""
    if name == "disc_on_sky":
        return procedural.disc_on_sky(256 // scale)
    if name == "two_tone":
        return procedural.two_tone(256 // scale)
    if name == "near_directional":
        return procedural.near_directional(512 // scale)
    if name.startswith("sunsky_"):
        return procedural.sunsky(float(name[len("sunsky_"):-len("deg")]), height=512 // scale, supersample=4 // scale)
    raise ValidateError(f"ibl: unknown sweep environment {name!r}")


def key_direction(env: Environment) -> np.ndarray:
    """Direction of the brightest texel (the key light)."""
    best, at = -np.inf, (0, 0)
    step = max(1, (1 << 20) // env.width)  # row blocks: no full-size luminance or directions
    for s in range(0, env.height, step):
        y = latlong.luminance(env.radiance[s:s + step])
        k = int(np.argmax(y))
        if y.flat[k] > best:
            best, at = float(y.flat[k]), (s + k // env.width, k % env.width)
    return latlong.spherical_to_direction(latlong.row_theta(env.height)[at[0]], latlong.col_phi(env.width)[at[1]])


def random_rotation(seed: int) -> np.ndarray:
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q
