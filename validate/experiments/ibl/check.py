"""``validate.testing.check_specular``: a specular technique against Mitsuba renders of a unit sphere."""


from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...local_models import specular
from ...local_models.registry import Technique
from ...metrics import image_error as ie
from ...reference import ibl_render as rr
from ...scenes import procedural
from ...scenes.environment import Environment
from ...scenes.ibl_scenes import CAMERA_OFFSET_DEG, PLASTIC_ETA, PLASTIC_RHO, key_direction
from ..inputs import load_named_environment
from ..techniques import CheckResult, Stat
from .compute import masked_image


def _mitsuba_bsdf(brdf: Mapping[str, Any]) -> dict:
    """The Mitsuba BSDF that a specular-family BRDF mapping describes (one-line error otherwise)."""
    model = brdf.get("model")
    if model == "phong":
        return {"type": rr.PHONG_PLUGIN, "exponent": float(brdf["exponent"]),
                "reflectance": float(brdf.get("reflectance", 1.0))}
    if model == "ggx" and float(brdf.get("f0", 1.0)) == 1.0:
        return {"type": "roughconductor", "distribution": "ggx", "alpha": float(brdf["alpha"])}
    if model == "ggx_plastic":
        return {"type": "roughplastic", "distribution": "ggx", "alpha": float(brdf["alpha"]),
                "int_ior": float(brdf.get("eta", PLASTIC_ETA)), "ext_ior": 1.0,
                "diffuse_reflectance": {"type": "rgb", "value": [float(brdf.get("rho", PLASTIC_RHO))] * 3}}
    raise ValidateError(f"check_specular: BRDF {dict(brdf)!r}: expected model 'phong' (exponent), 'ggx' (alpha, "
                        "f0 = 1: Mitsuba's default conductor) or 'ggx_plastic' (alpha, eta, rho)")


def _environment(env: str | Environment) -> Environment:
    """An Environment as given, a built-in by name (quick resolution) or a probe by name (found and loaded
    by :func:`..inputs.load_named_environment`; a missing probe raises there)."""
    if isinstance(env, Environment):
        return env
    if env in procedural.BUILTIN_NAMES:
        return procedural.builtin_environment(env, quick=True)
    return load_named_environment(env)


BrdfArg = Mapping[str, Any] | Iterable[Mapping[str, Any]]


def check_specular(fn: Callable[..., np.ndarray] | Technique | str,
                   brdf: BrdfArg = ({"model": "phong", "exponent": 10.0},),
                   environments: Iterable[str | Environment] = ("disc_on_sky",), size: int = 32, spp: int = 256,
                   passes: int = 4, seed: int = 1234, name: str | None = None) -> CheckResult:
    """Measure a specular technique (a function with the ``specular`` contract, a registered technique or
    its name) against Mitsuba renders of a unit sphere under each environment (a built-in name at quick
    resolution, a probe name as in ``check_irradiance``, or an :class:`Environment`), for each BRDF mapping
    (``{'model': 'phong', 'exponent': s}``, ``{'model': 'ggx', 'alpha': α}`` = Mitsuba's F = 1
    ``roughconductor``, ``{'model': 'ggx_plastic', 'alpha': α, 'eta': η, 'rho': ρ}``); orthographic camera
    6° off the environment's brightest texel, ``size``² pixels, ``spp`` paths in ``passes`` passes.

    Returns per ``<environment>`` (one BRDF) or ``<environment>/<model>_<parameter>`` a :class:`Stat` for
    ``relative`` (mean and max over pixels of |Y(A) − Y(R)|/Y(R), ± the Monte Carlo uncertainty) and
    ``bias`` (mean: the luminance-weighted bias Σ(Y(A) − Y(R))/ΣY(R); max: its absolute value; ± its
    standard error). The output contract is checked as in every experiment (one-line ``ValidateError``)."""
    brdfs = [brdf] if isinstance(brdf, Mapping) else list(brdf)
    label = name or (fn.name if isinstance(fn, Technique) else fn if isinstance(fn, str) else
                     getattr(fn, "__name__", "technique"))
    out: dict[str, dict[str, Stat]] = {}
    for env in map(_environment, environments):
        cam = rr.camera_towards(key_direction(env), CAMERA_OFFSET_DEG, size)
        for b in brdfs:
            r = rr.render(env, rr.RenderSpec("sphere", _mitsuba_bsdf(b), cam, spp=spp, passes=passes, seed=seed))
            n, v = r.normal[r.mask], r.view[r.mask]
            if isinstance(fn, (Technique, str)):
                vals = specular.call(fn, env.radiance, b, n, v)
            else:
                vals = specular.check(label, fn(env.radiance, b, n, v), (len(n), 3))
            s = ie.relative_error(r.mean, r.stderr_y, masked_image(r, vals), r.mask).stats
            key = env.name if len(brdfs) == 1 else f"{env.name}/{b['model']}_" + "_".join(
                f"{v:g}" for k, v in b.items() if k != "model" and isinstance(v, (int, float)))
            out[key] = {"relative": Stat(s.mean, s.max, s.mean_uncertainty, s.max_uncertainty),
                        "bias": Stat(s.bias, abs(s.bias), s.bias_uncertainty, s.bias_uncertainty)}
    return CheckResult(label, "specular", out)


__all__ = ["check_specular"]
