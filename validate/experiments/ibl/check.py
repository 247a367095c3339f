"""Experiment ``ibl``: prefiltered environment maps against Mitsuba path-traced BRDF integrals.

The pipeline, one module per stage:

* :mod:`.ibl_setup` — settings (quick and full are data), BRDF cases, the scene and render jobs;
* :mod:`.ibl_compute` — measurements: the irradiance quadrature, the diffuse-map sweep, every
  ``irradiance`` technique and map on a rendered Lambertian sphere, every ``specular`` technique on every
  BRDF case it declares (modified Phong, GGX conductor, GGX plastic), the mixing shader, the dented sphere;
* :mod:`.ibl_checks` — χ² and white-furnace checks of the reference BSDFs, split sum under a constant
  environment, the independent bound for the Phong map at normal incidence;
* :mod:`.ibl_claims` — claims with sources and power checks; technique entries and declared thresholds;
* :mod:`.ibl_report` — findings and report sections.

Errors on rendered pixels are relative luminance errors with the renders' Monte Carlo standard errors
(:mod:`validate.metrics.image_error`), FLIP beside them; the map sweep uses the peak-normalised error
|Y(E′) − Y(E)| / max Y(E) of :mod:`validate.metrics.irradiance_error`.

:func:`check_specular` is the ``validate.testing`` entry point for a specular technique.
"""

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
from . import reference_checks as chk
from . import compute as cmp
from ..base import Context, ExperimentResult, register_experiment
from .claims import all_claims, technique_results
from .report import findings, sections
from .scene import (
    CAMERA_OFFSET_DEG,
    EXP,
    PLASTIC_ETA,
    PLASTIC_RHO,
    Scene,
    Settings,
    build_scene,
    key_direction,
    render_all,
    settings_for,
)
from ..techniques import CheckResult, Stat

__all__ = ["run", "compute", "check_specular", "settings_for"]


def phong_ni(st: Settings, scene: Scene, renders: Mapping[str, rr.Render],
             run: cmp.SpecularRun) -> dict[str, dict[str, float]]:
    """Per Phong exponent: Σ|ΔY| of the s + 1 map (and of the same-exponent map) over the θ_v ≤ 5° crop,
    and Σσ_Y, each over Σ Y(U) of the independent bound (:func:`.ibl_checks.phong_bound`)."""
    out = {}
    for case in (c for c in run.cases if c.model == "phong"):
        rc = renders[case.key + "_ni"]
        a, b = (run.normal_incidence[t][case.key] for t in ("phong_prefiltered", "phong_prefiltered_s"))
        sel = np.isfinite(a.error) & np.isfinite(b.error)
        n, v = rc.normal[sel], rc.view[sel]
        u = chk.luminance_sum(chk.phong_bound(scene.render_env.radiance, case.brdf["exponent"], n, v))
        out[f"{case.brdf['exponent']:g}"] = {
            "ratio": float(np.sum(np.abs(a.y_app[sel] - a.y_ref[sel]))) / u,
            "ratio_s": float(np.sum(np.abs(b.y_app[sel] - b.y_ref[sel]))) / u,
            "ratio_u": float(np.sum(a.y_se[sel])) / u, "pixels": int(sel.sum())}
    return out


def compute(ctx: Context, st: Settings) -> cmp.IblMeasurements:
    """Every number of the experiment (no claims, no prose)."""
    scene = build_scene(st, ctx.seed)
    renders = render_all(ctx, scene)
    refs = cmp.reference_all(ctx, st, scene, renders)
    maps = cmp.diffuse_maps(ctx, st, scene, refs)
    spec = cmp.specular_run(ctx, st, scene, renders)
    return cmp.IblMeasurements(
        st, scene, renders, maps, cmp.diffuse_render(st, scene, renders, refs, maps), spec,
        cmp.mix_shader(st, scene, renders, refs, maps), cmp.concave(st, scene, renders, refs, maps),
        chk.phong_chi2(st), chk.phong_furnace(st), chk.split_sum_constant(st), phong_ni(st, scene, renders, spec))


def data(m: cmp.IblMeasurements) -> dict[str, Any]:
    """The JSON part of the result (besides claims, findings, sections and techniques)."""
    z = {name: {"labels": c.labels, "measured": c.measured.tolist(), "expected": c.expected.tolist(),
                "stderr": c.stderr.tolist(), "allowance": c.allowance.tolist(), "z": c.z().tolist(),
                "z_perturbed": c.z(c.perturbed).tolist(), "critical": c.critical}
         for name, c in (("furnace", m.furnace), ("split_sum_constant", m.split_constant))}
    comps = (m.diffuse.maps + list(m.diffuse.techniques.values()) + [m.mix.comparison]
             + [c for d in m.specular.comparisons.values() for c in d.values()])
    return {"resolution_sweep": m.maps.sweeps, "reported_face": m.maps.face, "reported_height": m.maps.height,
            "sh_vs_convolution": {k: {"max_flux_fraction": v[0], "uncertainty": v[1]} for k, v in m.maps.sh.items()},
            "phong_normal_incidence": m.phong_ni, "concave": m.concave.data,
            "mix": {"bias": m.mix.bias, "predicted": m.mix.predicted, "sigma": m.mix.sigma, "z": m.mix.z(),
                    "bias_unlit": m.mix.bias_unlit, "z_unlit": m.mix.z(m.mix.bias_unlit)},
            "chi2": {"exponents": m.chi2.exponents, "cos_views": m.chi2.cos_views, "p_values": m.chi2.p_values,
                     "p_values_off_by_one": m.chi2.p_values_off_by_one, "level": m.chi2.level},
            **z, "comparisons": [c.row() for c in comps]}


@register_experiment(EXP, "IBL convolution: irradiance maps, Phong-prefiltered and split-sum GGX maps vs Mitsuba",
                     "Diffuse irradiance maps (cube 4…256, lat-long, SH), every irradiance and specular technique "
                     "(Phong-prefiltered maps, split-sum GGX, plug-ins), the seed's mixing shader, against Mitsuba "
                     "path-traced BRDF integrals.", order=40)
def run(ctx: Context) -> ExperimentResult:
    st = settings_for(ctx.quick)
    m = compute(ctx, st)
    techniques, _ = technique_results(m)
    return ExperimentResult(
        name=EXP, title="IBL convolution vs Mitsuba",
        summary=("Diffuse irradiance maps, specular techniques (Phong-prefiltered maps, split-sum GGX, plug-ins), the "
                 "seed's mixing shader against the irradiance quadrature and Mitsuba path-traced renders of a sphere "
                 f"and a dented sphere under {m.scene.render_env.name} (maps: faces {m.maps.claim_face}²)."),
        claims=all_claims(m), findings=findings(m), sections=sections(m, ctx), data=data(m), techniques=techniques,
        settings={"quick": st.quick, "environments": list(st.sweep_envs), "render_environment": m.scene.render_env.name,
                  "faces": list(st.faces), "heights": list(st.heights), "image": st.size, "spp": st.spp,
                  "passes": st.passes, "exponents": list(st.exponents), "alphas": list(st.alphas),
                  "camera_offset_deg": CAMERA_OFFSET_DEG, "seed": ctx.seed})


# ---------------------------------------------------------------------------------------------
# validate.testing
# ---------------------------------------------------------------------------------------------

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
    as :func:`validate.testing.load_named_environment` does; a missing probe raises there)."""
    if isinstance(env, Environment):
        return env
    if env in procedural.BUILTIN_NAMES:
        return procedural.builtin_environment(env, quick=True)
    from ...testing import load_named_environment

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
            s = ie.relative_error(r.mean, r.stderr_y, cmp.masked_image(r, vals), r.mask).stats
            key = env.name if len(brdfs) == 1 else f"{env.name}/{b['model']}_" + "_".join(
                f"{v:g}" for k, v in b.items() if k != "model" and isinstance(v, (int, float)))
            out[key] = {"relative": Stat(s.mean, s.max, s.mean_uncertainty, s.max_uncertainty),
                        "bias": Stat(s.bias, abs(s.bias), s.bias_uncertainty, s.bias_uncertainty)}
    return CheckResult(label, "specular", out)
