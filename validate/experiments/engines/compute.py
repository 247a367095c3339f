"""``engines`` compute step: numbers only, one environment per task.

Per environment (:func:`measure_environment`, through ``ctx.map``):

* the reference E(n) ± δ(n) (:func:`validate.reference.irradiance.reference_irradiance`) at N
  spherical-Fibonacci normals, and every technique of the ``irradiance`` family — the engines (those
  registered with ``engine=`` meta) beside the suite's ``sh9`` and any other built-in or plug-in — each
  through ``family.call`` and judged under every metric of :mod:`validate.metrics.irradiance_error`;
* the decomposition of each engine's error: the faces it received (their flux against the map's),
  the exact-solid-angle SH9 of those same faces (:func:`cube_faces.project_faces_sh9`) and the engine's
  largest departure from it, ``max_{n,c} |E_engine − E_faces|/Φ_c``;
* the power-check variants: each engine at −n (band 1's sign flipped: the odd band of an SH9
  irradiance is (E(n) − E(−n))/2, so E(−n) is SH9 with L1m ↦ −L1m) and its output × 1.01;
* Babylon with the 4096 clamp lifted (MAX_HDRI_VALUE = ∞) and the share of the face flux the clamp
  removes; three.js fed half-float faces (a HalfFloatType target); Babylon's polynomial path against
  SH9 of the faces with band l scaled by A_l/π (the cosine lobe applied twice);
* each engine fed from its own panorama → cube path (:func:`measure_own_faces`, issue 21 item 5): Babylon's
  PanoramaToCubeMapTools, three.js's equirect shader transcribed.

:func:`measure_face_sizes` sweeps the cube-face size on a few environments.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial
from typing import Any

import numpy as np

from ...geometry import cube_texel_directions, cube_texel_solid_angles
from ...local_models import irradiance as irradiance_family
from ...local_models.irradiance import sh as shm
from ...local_models.irradiance.engines import UNAVAILABLE, cube_faces, own_faces, worker
from ...local_models.registry import Technique
from ...metrics.irradiance_error import irradiance_errors
from ...reference.irradiance import reference_irradiance
from ...scenes import latlong
from ...scenes.environment import Environment
from ..base import Context
from ..techniques import stats_json
from .settings import Settings

BABYLON_CLAMP = 4096.0  # CubeMapToSphericalPolynomialTools.MAX_HDRI_VALUE (Babylon.js 9.35)
HALF_MAX = 65504.0  # largest finite IEEE half float
SCALE_BUG = 1.01  # power of the equality claims: the engine's output 1 % too bright
BASELINE = "sh9"
# A_l/π for l = 0, 1, 2 over the 9 coefficients: Babylon's polynomial path applies the lobe twice.
DOUBLE_LOBE = np.array([shm.clamped_cosine_al(shm.degree_of(k)) / np.pi for k in range(9)])[:, None]


def engine_techniques() -> list[Technique]:
    """Every registered irradiance technique that runs a shipping engine (meta ``engine``)."""
    return [t for t in irradiance_family if t.meta.get("engine")]


def compared_techniques() -> list[Technique]:
    """Every registered irradiance technique (the suite's SH9, the engines, any other built-in or plug-in):
    each gets its row and its results.json entry, as in every experiment of the family."""
    techs = list(irradiance_family)
    return sorted(techs, key=lambda t: t.name != BASELINE)  # SH9 first: the others are compared with it



def deviation(a: np.ndarray, b: np.ndarray, flux: np.ndarray) -> float:
    """max over normals and channels of |a_c − b_c| / Φ_c (channels with Φ_c > 0)."""
    ok = flux > 0
    return float(np.max(np.abs(a - b)[:, ok] / flux[ok])) if ok.any() else 0.0


def clamp_share(faces: np.ndarray, limit: float = BABYLON_CLAMP) -> float:
    """Luminance flux the per-channel clamp at ``limit`` removes, over the faces' luminance flux."""
    omega = cube_texel_solid_angles(faces.shape[1])
    y_all = latlong.luminance(np.einsum("fijc,ij->c", faces.astype(np.float64), omega))
    y_cut = latlong.luminance(np.einsum("fijc,ij->c", np.maximum(faces.astype(np.float64) - limit, 0.0), omega))
    return float(y_cut / y_all) if y_all > 0 else 0.0


def measure_technique(tech: Technique, env: Environment, normals: np.ndarray, e_ref: np.ndarray,
                      unc: np.ndarray, flux: np.ndarray, e_faces: np.ndarray, e_sh9: np.ndarray | None) -> dict:
    """One technique on one environment: metrics, its departure from the faces' SH9 (and from the suite's
    SH9), and the same under band 1's sign flipped and under a 1 % scale error."""
    both = irradiance_family.call(tech, env.radiance, np.concatenate([normals, -normals]))
    e, e_flip = both[: len(normals)], both[len(normals):]
    out = {"errors": stats_json(irradiance_errors(e_ref, e, flux, unc)),
           "errors_band1_flipped": stats_json(irradiance_errors(e_ref, e_flip, flux, unc)),
           "faces_deviation": deviation(e, e_faces, flux),
           "faces_deviation_scaled": deviation(SCALE_BUG * e, e_faces, flux)}
    if e_sh9 is not None:
        out["sh9_deviation"] = deviation(e, e_sh9, flux)
    if env.name == "constant":  # E = πL exactly: the π normalisation
        pil = np.pi * env.radiance[0, 0].astype(np.float64)
        out["pi_normalisation"] = float(np.max(np.abs(e / pil - 1.0)))
        out["pi_normalisation_unscaled"] = float(np.max(np.abs(e / np.pi / pil - 1.0)))
    out["_irradiance"] = e
    return out


def babylon_variants(env: Environment, normals: np.ndarray, e_ref: np.ndarray, unc: np.ndarray,
                     flux: np.ndarray, coeffs: np.ndarray, e_poly: np.ndarray | None) -> dict:
    """Babylon without its clamp; the polynomial path against the doubly convolved SH9 of the faces."""
    out: dict[str, Any] = {}
    if not any(t.meta.get("engine") == "babylon" for t in engine_techniques()):
        return out
    e_nc = worker.engine_irradiance("babylon", "sh", env.radiance, normals, worker.FaceSettings(clamp=False))
    out["babylon_sh_unclamped"] = stats_json(irradiance_errors(e_ref, e_nc, flux, unc))
    if e_poly is not None:
        e_dbl = cube_faces.render_sh9(coeffs * DOUBLE_LOBE, normals)
        out["polynomial_double_lobe_deviation"] = deviation(e_poly, e_dbl, flux)
        out["polynomial_double_lobe_fixed"] = deviation(cube_faces.render_sh9(coeffs, normals), e_dbl, flux)
    return out


def half_float(env: Environment, normals: np.ndarray, faces: np.ndarray, e_three: np.ndarray | None,
               flux: np.ndarray) -> dict:
    """three.js fed the same faces as half floats: departure from the float32 result, or overflow."""
    if e_three is None or not any(t.meta.get("engine") == "three" for t in engine_techniques()):
        return {}
    over = int((faces > HALF_MAX).any(axis=-1).sum())
    e16 = worker.engine_irradiance("three", "getIrradianceAt", env.radiance, normals,
                                   worker.FaceSettings(dtype="float16"))
    finite = bool(np.isfinite(e16).all())
    return {"half_overflow_texels": over, "half_finite": finite,
            "half_deviation": deviation(e16, e_three, flux) if finite else None}


def _output_of(techs: dict[str, dict], engine: str, path: str) -> np.ndarray | None:
    """The irradiance of the technique running ``engine`` through ``path``, if one is registered."""
    for t in engine_techniques():
        if t.meta.get("engine") == engine and t.meta.get("path") == path and t.name in techs:
            return techs[t.name]["_irradiance"]
    return None


def measure_faces(env: Environment, settings: Settings) -> dict:
    """The faces the engines receive (no Node needed): their flux against the map's, and the same for faces
    point-sampled at the texel centres (the power check of the flux claim); the largest texel; the clamp."""
    faces = worker.faces_for(env.radiance, settings.face_size)
    flux = env.total_flux()
    point = latlong.bilinear_lookup(env.radiance, cube_texel_directions(settings.face_size))  # taps widen to float64
    ok = flux > 0
    return {
        "kind": env.kind, "resolution": [env.width, env.height], "face_size": settings.face_size,
        "face_flux_error": float(np.max(np.abs(cube_faces.face_flux(faces)[ok] / flux[ok] - 1.0))),
        "point_sampled_flux_error": float(np.max(np.abs(cube_faces.face_flux(point)[ok] / flux[ok] - 1.0))),
        "max_face_texel": float(faces.max()), "max_map_texel": float(env.radiance.max()),
        "above_clamp": bool(faces.max() > BABYLON_CLAMP), "clamp_share": clamp_share(faces),
    }


OWN_PATHS = {("three", "getIrradianceAt"), ("babylon", "sh")}  # the engine paths measured on their own faces


def _faces_sh9(faces: np.ndarray, normals: np.ndarray, clamp: bool) -> np.ndarray:
    """Exact-solid-angle SH9 E of ``faces`` at ``normals`` (faces clipped to [0, 4096] per channel if ``clamp``:
    Babylon's Clamp(v, 0, MAX_HDRI_VALUE))."""
    f = np.clip(faces, 0.0, BABYLON_CLAMP) if clamp else faces
    return cube_faces.render_sh9(cube_faces.project_faces_sh9(f), normals)


def _difference(own: dict[str, float], suite: dict[str, float]) -> dict[str, float]:
    """own − suite for the mean and the max, each ± the sum of the two references' uncertainties (the same
    reference, so this bounds the difference's uncertainty from above)."""
    return {k: v for stat in ("mean", "max") for k, v in
            ((stat, own[stat] - suite[stat]), (f"{stat}_uncertainty", own[f"{stat}_uncertainty"]
                                               + suite[f"{stat}_uncertainty"]))}


def measure_own_faces(env: Environment, normals: np.ndarray, e_ref: np.ndarray, unc: np.ndarray, flux: np.ndarray,
                      suite_faces: np.ndarray, techs: dict[str, dict]) -> dict:
    """Each engine fed from its own panorama → cube path (:mod:`own_faces`) beside the same engine on the suite's
    texel-averaged faces (issue 21 item 5): the faces it made (largest texel, Babylon's clamp, flux), its errors
    with and (Babylon) without the clamp, its departure from the exact SH9 of its own faces and — the power
    check — from the exact SH9 of the suite's faces, and the error difference own − suite ± the two references'
    uncertainties."""
    out: dict[str, Any] = {}
    ok = flux > 0
    for tech in engine_techniques():
        engine, path = tech.meta.get("engine"), tech.meta.get("path")
        if (engine, path) not in OWN_PATHS or tech.name not in techs:
            continue
        babylon = engine == "babylon"
        faces = own_faces.own_faces(engine, env.radiance, suite_faces.shape[1])
        a, fit = own_faces.orientation(engine, suite_faces.shape[1])
        e = own_faces.own_irradiance(engine, env.radiance, normals, suite_faces.shape[1])
        errs = irradiance_errors(e_ref, e, flux, unc)
        suite = techs[tech.name]["errors"]
        r: dict[str, Any] = {
            "orientation": a.tolist(), "orientation_fit": fit,
            "max_face_texel": float(faces.max()), "above_clamp": bool(faces.max() > BABYLON_CLAMP),
            "clamp_share": clamp_share(faces),
            "face_flux_error": float(np.max(np.abs(cube_faces.face_flux(faces)[ok] / flux[ok] - 1.0))),
            "face_flux_ratio": float(latlong.luminance(cube_faces.face_flux(faces)) / latlong.luminance(flux))
            if latlong.luminance(flux) > 0 else 1.0,
            "errors": stats_json(errs),
            "faces_deviation": deviation(e, _faces_sh9(faces, own_faces.to_engine_frame(engine, normals), babylon),
                                         flux),
            "suite_faces_deviation": deviation(e, _faces_sh9(suite_faces, normals, babylon), flux),
            "vs_suite_faces": deviation(e, techs[tech.name]["_irradiance"], flux),
            "difference": {metric: _difference(errs[metric].to_json(), suite[metric])
                           for metric in ("flux_luminance", "flux_rgb")},
        }
        if babylon:
            r["errors_unclamped"] = stats_json(irradiance_errors(
                e_ref, own_faces.own_irradiance(engine, env.radiance, normals, suite_faces.shape[1], clamp=False),
                flux, unc))
        out[tech.name] = r
    return out


def measure_environment(env: Environment, settings: Settings) -> dict:
    """Everything the experiment measures on one environment (JSON-able but for ``_``-keys)."""
    normals = latlong.fibonacci_sphere(settings.normals)
    ref = reference_irradiance(env, normals, cells=settings.cells)
    flux = env.total_flux()
    faces = worker.faces_for(env.radiance, settings.face_size)
    coeffs = cube_faces.project_faces_sh9(faces)
    e_faces = cube_faces.render_sh9(coeffs, normals)
    techs: dict[str, dict] = {}
    e_sh9: np.ndarray | None = None
    for tech in compared_techniques():
        techs[tech.name] = measure_technique(tech, env, normals, ref.irradiance, ref.uncertainty, flux, e_faces,
                                             e_sh9)
        if tech.name == BASELINE:
            e_sh9 = techs[tech.name]["_irradiance"]
    poly = _output_of(techs, "babylon", "polynomial")
    three = _output_of(techs, "three", "getIrradianceAt")
    own = measure_own_faces(env, normals, ref.irradiance, ref.uncertainty, flux, faces, techs)
    for t in techs.values():
        t.pop("_irradiance")
    return {
        **measure_faces(env, settings),
        "flux": flux.tolist(), "flux_luminance": float(latlong.luminance(flux)),
        "convergence": ref.convergence, "techniques": techs,
        "faces_vs_sh9": deviation(e_faces, e_sh9, flux) if e_sh9 is not None else None,
        **babylon_variants(env, normals, ref.irradiance, ref.uncertainty, flux, coeffs, poly),
        **half_float(env, normals, faces, three, flux),
        "own_faces": own,
    }


def measure_face_sizes(env: Environment, settings: Settings) -> dict:
    """Each engine path at every face size of the sweep: flux-normalised luminance error against the
    reference, departure from the exact SH9 of the same faces, Babylon's clamped share."""
    normals = latlong.fibonacci_sphere(settings.normals)
    ref = reference_irradiance(env, normals, cells=settings.cells)
    flux = env.total_flux()
    paths = {t.name: (t.meta["engine"], t.meta.get("path")) for t in engine_techniques() if t.meta.get("path")}
    out: dict[str, Any] = {"sizes": list(settings.sweep_sizes), "techniques": {}, "clamp_share": [],
                           "max_face_texel": []}
    for size in settings.sweep_sizes:
        faces = worker.faces_for(env.radiance, size)
        e_faces = cube_faces.render_sh9(cube_faces.project_faces_sh9(faces), normals)
        out["clamp_share"].append(clamp_share(faces))
        out["max_face_texel"].append(float(faces.max()))
        for name, (engine, path) in paths.items():
            e = worker.engine_irradiance(engine, path, env.radiance, normals, worker.FaceSettings(size=size))
            st = irradiance_errors(ref.irradiance, e, flux, ref.uncertainty)["flux_luminance"]
            row = out["techniques"].setdefault(name, {"mean": [], "max": [], "faces_deviation": []})
            row["mean"].append(st.mean)
            row["max"].append(st.max)
            row["faces_deviation"].append(deviation(e, e_faces, flux))
    return out


def three_weight_error(n: int) -> float:
    """ρ(N) = max over texels of |w/Ω − 1| for three.js's weights w ∝ r⁻³ at the texel centre, normalised
    to Σ w = 4π, against the exact texel solid angles Ω (Driscoll 2012's atan2 area element)."""
    c = (np.arange(n) + 0.5) / n * 2.0 - 1.0
    u, v = np.meshgrid(c, c, indexing="ij")
    w = (1.0 + u * u + v * v) ** -1.5
    w *= 4.0 * np.pi / (6.0 * w.sum())
    return float(np.max(np.abs(w / cube_texel_solid_angles(n) - 1.0)))


__all__ = ["BABYLON_CLAMP", "BASELINE", "DOUBLE_LOBE", "HALF_MAX", "SCALE_BUG", "Measurements", "clamp_share",
           "compared_techniques", "compute", "deviation", "engine_techniques", "faces_only", "measure_environment",
           "measure_face_sizes", "measure_faces", "named_environments", "three_weight_error"]


@dataclass
class Measurements:
    settings: Settings
    environments: dict[str, dict[str, Any]]
    sweeps: dict[str, dict[str, Any]] = field(default_factory=dict)
    skipped: list[tuple[str, str]] = field(default_factory=list)
    named: dict[str, str] = field(default_factory=dict)  # role ("grace_probe", "brightest_sun") → env
    unavailable: str | None = None  # why no engine ran (then only the faces were measured)

    @property
    def rho(self) -> float:
        return three_weight_error(self.settings.face_size)


SWEEP_FALLBACK = ("disc_on_sky", "sunsky_30deg")  # face-size sweep when no named probe is present


def named_environments(envs: dict[str, dict[str, Any]]) -> dict[str, str]:
    """grace_probe (the paper's probe) and the probe with the brightest texel (the strongest sun), if present."""
    out = {}
    if "grace_probe" in envs:
        out["grace_probe"] = "grace_probe"
    probes = {n: r for n, r in envs.items() if r["kind"] == "probe"}
    if probes:
        out["brightest_sun"] = max(probes, key=lambda n: probes[n]["max_map_texel"])
    return out


def compute(ctx: Context, s: Settings) -> Measurements:
    """Every environment (``ctx.map``), then the face-size sweep on the named probes. Without Node (or without a
    registered engine technique) only the cube faces the engines would receive are measured (no Node needed)."""
    if UNAVAILABLE is not None or not engine_techniques():
        return faces_only(ctx, s, UNAVAILABLE or "no engine technique is registered")
    envs, skipped = ctx.environments()
    results = ctx.map(partial(measure_environment, settings=s), envs, "engines: environments")
    environments = {e.name: r for e, r in zip(envs, results, strict=True)}
    named = named_environments(environments)
    by_name = {e.name: e for e in envs}
    sweep_names = list(dict.fromkeys(named.values())) or [n for n in SWEEP_FALLBACK if n in by_name]
    sweeps = ctx.map(partial(measure_face_sizes, settings=s), [by_name[n] for n in sweep_names],
                     "engines: face sizes")
    return Measurements(s, environments, dict(zip(sweep_names, sweeps, strict=True)), list(skipped), named)


def faces_only(ctx: Context, s: Settings, reason: str) -> Measurements:
    """No engine can run: the faces they would receive, checked on every environment; ``unavailable`` says why."""
    envs, skipped = ctx.environments()
    faces = ctx.map(partial(measure_faces, settings=s), envs, "engines: faces")
    return Measurements(s, {e.name: r for e, r in zip(envs, faces, strict=True)}, skipped=list(skipped),
                        unavailable=reason)
