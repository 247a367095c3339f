"""``sh9`` compute step: numbers (and the arrays behind the figures), one environment per task.

Per environment (:func:`analyse_environment`, run through ``ctx.map``):

* the reference E(n) ± δ(n) (:func:`validate.reference.irradiance.reference_irradiance`) at N
  spherical-Fibonacci normals, a lat-long grid of normals (heat map) and the pixels of a sphere;
* SH9 of the environment (R&H 2001 eq. 12, :mod:`validate.local_models.irradiance.sh`) and its error under
  every metric of :mod:`validate.metrics.irradiance_error`, the error against the order l_max = 0…8;
* the same metrics under three model perturbations, the power checks of the claims made on SH9:
  ``cs_phase`` (a Condon–Shortley phase mismatch between projection and evaluation: L1m1, L11, L2m1,
  L21 sign-flipped), ``order4`` (l_max = 4, the neighbouring order with non-zero A_l) and
  ``error_x1.5`` (E + 1.5 (E_SH9 − E): the approximation's error grown by half);
* every registered ``irradiance`` technique through ``family.call`` (output contract checked), at the
  normals and at the normals mirrored x → −x (a handedness bug: the power check of its claims);
* the closed form where one exists (:mod:`.closed_forms`), the published coefficients where the
  probe is one of the paper's (:mod:`validate.metrics.published`), or why not;
* Filament cmgen's automatic window (:mod:`validate.local_models.irradiance.cmgen_window`, technique
  ``sh9_cmgen_auto``): the cut-off it picks for this map, the Hölder bound of that map's kernel, and the
  windowed irradiance's minimum over :data:`DENSE_NORMALS` normals (float64) at the chosen cut-off, at the
  smallest cut-off the bisection rejected and without a window (:func:`cmgen_check`);
* the sun share: the fraction of the luminance flux within :data:`SUN_CAP_DEG` of the brightest texel
  (:func:`sun_share`; picks the strongest-sun probe for the findings).

:func:`pathtrace_crosscheck` judges the reference by a path-traced Lambertian sphere.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial
from typing import Any

import numpy as np

from ...local_models import irradiance as irradiance_family
from ...local_models.irradiance import cmgen_window
from ...local_models.irradiance import sh as shm
from ...local_models.irradiance.windowed_sh import kernel_bound
from ...metrics.irradiance_error import irradiance_errors
from ...metrics.published import fit_exposure
from ...reference import pathtrace
from ...reference.irradiance import reference_irradiance
from ...scenes import latlong
from ...scenes.environment import Environment
from ...scenes.probes import published_status, read_aliases, read_published_sh9
from ..base import Context
from ..techniques import stats_json
from .closed_forms import closed_form
from .settings import Settings

# Model perturbations (power checks of the SH9 claims); values: what the report says.
CS_FLIP = np.array([1, -1, 1, -1, 1, -1, 1, -1, 1], dtype=np.float64)[:, None]  # m = ±1 of l = 1, 2
PERTURBATIONS = {
    "cs_phase": "Condon–Shortley phase mismatch (L1m1, L11, L2m1, L21 sign-flipped)",
    "order4": "l_max = 4 instead of 2 (the neighbouring order with non-zero A_l)",
    "error_x1.5": "SH9 error × 1.5 (E + 1.5 (E_SH9 − E))",
}
MIRROR = np.array([-1.0, 1.0, 1.0])  # x → −x: a handedness bug
MIRRORED = "normals mirrored x → −x (a handedness bug)"
REFERENCE_BIAS = 0.01  # power of the reference claims: the reference biased by 1 %
CROSSCHECK_BIAS = 0.02  # power of the path-traced bias claim: the quadrature biased by 2 %
CROSSCHECK_FLIP = "quadrature image flipped upside down (the film's v axis inverted)"
CMGEN = "sh9_cmgen_auto"
# normals of the non-negativity check: 20 000 spherical-Fibonacci points (mean spacing 1.6°); the windowed
# irradiance is a quadratic on the sphere, so its negative lobes (tens of degrees wide) cannot slip between them
DENSE_NORMALS = 20000
SUN_CAP_DEG = 5.0  # the sun (0.27° radius) and its aureole



def sphere_normals(res: int) -> tuple[np.ndarray, np.ndarray]:
    """Front view of a unit sphere from +z (orthographic): normals (res, res, 3), NaN outside; mask."""
    t = (np.arange(res) + 0.5) / res * 2 - 1
    yy, xx = np.meshgrid(-t, t, indexing="ij")
    r2 = xx**2 + yy**2
    mask = r2 < 1.0
    n = np.stack([xx, yy, np.sqrt(np.clip(1 - r2, 0, 1))], axis=-1)
    n[~mask] = np.nan
    return n, mask


def _grid_normals(grid: tuple[int, int]) -> np.ndarray:
    gh, gw = grid
    th = (np.arange(gh) + 0.5) * np.pi / gh
    ph = (np.arange(gw) + 0.5) * 2 * np.pi / gw
    tt, pp = np.meshgrid(th, ph, indexing="ij")
    return latlong.spherical_to_direction(tt, pp).reshape(-1, 3)


def order_sweep(coeffs: np.ndarray, normals: np.ndarray, e_ref: np.ndarray, flux: np.ndarray, unc: np.ndarray,
                max_order: int) -> dict[str, list[float]]:
    """flux_luminance mean/max of SH irradiance truncated at l_max = 0…max_order."""
    out: dict[str, list[float]] = {"lmax": list(range(max_order + 1)), "mean": [], "max": []}
    for lm in range(max_order + 1):
        e = shm.render_irradiance(coeffs[: shm.n_coeffs(lm)], normals, lm)
        st = irradiance_errors(e_ref, e, flux, unc)["flux_luminance"]
        out["mean"].append(st.mean)
        out["max"].append(st.max)
    return out


def sh9_perturbed(coeffs: np.ndarray, normals: np.ndarray, e_ref: np.ndarray, e_sh9: np.ndarray,
                  flux: np.ndarray, unc: np.ndarray) -> dict[str, dict]:
    """Every metric of SH9 under each of :data:`PERTURBATIONS`."""
    variants = {
        "cs_phase": shm.render_irradiance_rh2001(CS_FLIP * coeffs[:9], normals),
        "order4": shm.render_irradiance(coeffs[:25], normals, 4),
        "error_x1.5": e_ref + 1.5 * (e_sh9 - e_ref),
    }
    return {k: stats_json(irradiance_errors(e_ref, e, flux, unc)) for k, e in variants.items()}


def measure_techniques(env: Environment, normals: np.ndarray, e_ref: np.ndarray, flux: np.ndarray,
                       unc: np.ndarray, extra: np.ndarray | None = None) -> tuple[dict, dict, dict]:
    """Every registered irradiance technique: metrics at the normals and at the mirrored normals, and its
    irradiance at the ``extra`` normals (the sphere image), in one call per technique through the family's
    output contract."""
    extra = np.zeros((0, 3)) if extra is None else extra
    k = len(normals)
    both = np.concatenate([normals, normals * MIRROR, extra])
    metrics, mirrored, at_extra = {}, {}, {}
    for tech in irradiance_family:
        e = irradiance_family.call(tech, env.radiance, both)
        metrics[tech.name] = stats_json(irradiance_errors(e_ref, e[:k], flux, unc))
        mirrored[tech.name] = stats_json(irradiance_errors(e_ref, e[k:2 * k], flux, unc))
        at_extra[tech.name] = e[2 * k:]
    return metrics, mirrored, at_extra


def worst_negative(coeffs: np.ndarray, cutoff: float, normals: np.ndarray, flux: np.ndarray) -> float:
    """max over channels with Φ_c > 0 of −min_n E′_c(n) / Φ_c for the sinc⁴ window at ``cutoff`` (float64)."""
    e = cmgen_window.render_windowed_exact(coeffs, cutoff, normals)
    return float(max(-e[:, c].min() / flux[c] for c in range(3) if flux[c] > 0))


def cmgen_check(env: Environment, flux: np.ndarray) -> dict | None:
    """cmgen's auto window on this map: cut-off, weights, the kernel's Hölder bound and the windowed
    irradiance's worst negative value at the chosen / the smallest rejected / no window (None when the
    technique is not registered or the map has no flux)."""
    if CMGEN not in irradiance_family or not np.any(flux > 0):
        return None
    coeffs = shm.project_environment(env.radiance, 2)  # as the technique does
    win = cmgen_window.auto_window(coeffs)
    dense = latlong.fibonacci_sphere(DENSE_NORMALS)
    return {"cutoff": win.cutoff, "rejected": win.rejected, "weights": win.weights.tolist(),
            "brackets": [list(b) for b in win.brackets], "kernel_bound": kernel_bound(win.weights),
            "negative": worst_negative(coeffs, win.cutoff, dense, flux),
            "negative_rejected": None if win.rejected is None else worst_negative(coeffs, win.rejected, dense, flux),
            "negative_unwindowed": worst_negative(coeffs, np.inf, dense, flux)}


SUN_SHARE_BLOCK_TEXELS = 1 << 20  # texels per row block of :func:`sun_share` (~24 MiB of float64 directions)


def sun_share(env: Environment, cap_deg: float = SUN_CAP_DEG) -> float:
    """Fraction of the luminance flux Φ_Y within ``cap_deg`` of the brightest texel (by luminance),
    Σ_{d_ij·d_peak ≥ cos cap} Y_ij Ω_i / Σ Y_ij Ω_i, in two passes over row blocks (no full-size temporaries:
    memory stays a small multiple of the map on 8k probes)."""
    h, w = env.height, env.width
    rad = env.radiance
    step = max(1, SUN_SHARE_BLOCK_TEXELS // w)
    omega, theta, phi = latlong.row_solid_angles(h, w), latlong.row_theta(h), latlong.col_phi(w)
    total, best, peak_at = 0.0, -np.inf, (0, 0)
    for s in range(0, h, step):
        y = latlong.luminance(np.asarray(rad[s:s + step], dtype=np.float64))
        total += float(y.sum(axis=1) @ omega[s:s + step])
        k = int(np.argmax(y))
        if y.flat[k] > best:
            best, peak_at = float(y.flat[k]), (s + k // w, k % w)
    if total <= 0:
        return 0.0
    peak = latlong.spherical_to_direction(theta[peak_at[0]], phi[peak_at[1]])
    cos_cap, inside = np.cos(np.radians(cap_deg)), 0.0
    for s in range(0, h, step):
        d = latlong.spherical_to_direction(theta[s:s + step, None], phi[None, :])
        y = latlong.luminance(np.asarray(rad[s:s + step], dtype=np.float64)) * omega[s:s + step, None]
        inside += float(y[d @ peak >= cos_cap].sum())
    return inside / total


def closed_form_check(env: Environment, normals: np.ndarray, e_ref: np.ndarray, unc: np.ndarray) -> dict | None:
    """max |E − E_exact| / norm ± max δ / norm, and the same with the reference biased by 1 %."""
    cf = closed_form(env, normals)
    if cf is None:
        return None
    norm = np.broadcast_to(cf.norm, e_ref.shape)
    err = np.abs(e_ref - cf.exact) / norm
    biased = np.abs((1 + REFERENCE_BIAS) * e_ref - cf.exact) / norm
    return {"metric": cf.metric, "formula": cf.formula, "max": float(err.max()),
            "uncertainty": float((unc / norm).max()), "biased": float(biased.max())}


def published_check(env: Environment, published: dict, aliases: dict) -> dict:
    """The rh2001 coefficients against the table row (fit + the z-mirrored-frame power check), or why not."""
    key, why = published_status(env, aliases)
    if key is None:
        return {"published_note": why} if why else {}
    if key not in published:
        return {"published_note": f"{env.source.name if env.source else env.name}: table row {key!r} is missing "
                                  "from sh9_coefficients.csv; coefficients not compared"}
    table = np.array([published[key][c] for c in shm.SH9_NAMES])
    ours = shm.project_angular_rh2001(env.angular, 2)
    fit = fit_exposure(ours, table, key).to_json()
    z_flip = np.array([1, 1, -1, 1, 1, -1, 1, -1, 1], dtype=np.float64)[:, None]  # Mitsuba frame (−z forward)
    fit["z_mirrored_max_deviation"] = fit_exposure(z_flip * ours, table, key).max_deviation
    return {"published": fit}


def _figure_arrays(env: Environment, ref_sph: np.ndarray, sh_sph: np.ndarray, mask: np.ndarray,
                   err_grid: np.ndarray) -> dict[str, np.ndarray]:
    thumb = env.radiance[:: max(1, env.height // 128), :: max(1, env.width // 256)]
    ref_img = np.full(mask.shape + (3,), np.nan)
    sh_img = np.full(mask.shape + (3,), np.nan)
    ref_img[mask] = ref_sph / np.pi
    sh_img[mask] = sh_sph / np.pi
    return {"thumb": np.ascontiguousarray(thumb), "sphere_reference": ref_img, "sphere_sh9": sh_img,
            "error_grid": err_grid}


def analyse_environment(env: Environment, settings: Settings, published: dict | None = None,
                        aliases: dict | None = None) -> dict:
    """Everything measured on one environment: JSON-able numbers, plus ``_arrays`` for the figures. The
    published table defaults to none, the aliases to the shipped ones."""
    published, aliases = published or {}, read_aliases() if aliases is None else aliases
    n_fib = latlong.fibonacci_sphere(settings.normals)
    n_grid = _grid_normals(settings.grid)
    sph, mask = sphere_normals(settings.sphere_px)
    alln = np.concatenate([n_fib, n_grid, sph[mask]])
    ref = reference_irradiance(env, alln, cells=settings.cells)
    flux = env.total_flux()
    k1, k2 = len(n_fib), len(n_fib) + len(n_grid)
    e_ref, unc = ref.irradiance[:k1], ref.uncertainty[:k1]

    coeffs = shm.project_environment(env.radiance, settings.max_order)
    e_sh9_all = shm.render_irradiance_rh2001(coeffs[:9], alln)
    e_sh9 = e_sh9_all[:k1]
    models, mirrored, tech_sphere = measure_techniques(env, n_fib, e_ref, flux, unc, sph[mask])
    peak = float(ref.irradiance.max())
    out: dict[str, Any] = {
        "kind": env.kind, "description": env.description, "layout": env.layout,
        "source": str(env.source) if env.source else None, "notes": list(env.notes),
        "resolution": [env.width, env.height],
        "flux": flux.tolist(), "flux_luminance": float(latlong.luminance(flux)),
        "coefficients": coeffs[:9].tolist(),
        "errors": stats_json(irradiance_errors(e_ref, e_sh9, flux, unc)),
        "perturbed": sh9_perturbed(coeffs, n_fib, e_ref, e_sh9, flux, unc),
        "convergence": ref.convergence,
        # |1.01 E_2H − E_H| ≥ 0.01 E_2H − |E_2H − E_H|: a lower bound of the convergence measure had the
        # finer pass been 1 % off, at the peak normal
        "convergence_biased": REFERENCE_BIAS - ref.convergence if peak > 0 else 0.0,
        "order_sweep": order_sweep(coeffs, n_fib, e_ref, flux, unc, settings.max_order),
        "models": models,
        "models_mirrored": mirrored,
    }
    cf = closed_form_check(env, n_fib, e_ref, unc)
    if cf is not None:
        out["closed_form"] = cf
    cm = cmgen_check(env, flux)
    if cm is not None:
        out["cmgen_auto"] = cm
    out["sun_share"] = sun_share(env)
    out.update(published_check(env, published, aliases))
    gh, gw = settings.grid
    err_grid = (np.abs(latlong.luminance(e_sh9_all[k1:k2]) - latlong.luminance(ref.irradiance[k1:k2]))
                / latlong.luminance(flux)).reshape(gh, gw)
    out["_arrays"] = _figure_arrays(env, ref.irradiance[k2:], e_sh9_all[k2:], mask, err_grid)
    out["_arrays"]["technique_spheres"], out["_arrays"]["technique_errors"] = _technique_images(
        tech_sphere, ref.irradiance[k2:], mask, float(latlong.luminance(flux)))
    return out


def _technique_images(at_sphere: dict[str, np.ndarray], ref_sphere: np.ndarray, mask: np.ndarray,
                      flux_y: float) -> tuple[dict, dict]:
    """Per technique: its sphere E′/π and the error map |Y(E′) − Y(E)| / Φ_Y over the sphere's pixels."""
    spheres, errors = {}, {}
    for name, e in at_sphere.items():
        img = np.full(mask.shape + (3,), np.nan)
        img[mask] = e / np.pi
        err = np.full(mask.shape, np.nan)
        err[mask] = np.abs(latlong.luminance(e) - latlong.luminance(ref_sphere)) / max(flux_y, 1e-300)
        spheres[name], errors[name] = img, err
    return spheres, errors


def pathtrace_crosscheck(env: Environment, settings: Settings, seed: int) -> dict:
    """Path-traced white Lambertian sphere vs the quadrature (validate.reference.pathtrace), plus the same
    test against a quadrature biased by 2 % and against the upside-down quadrature image (power)."""
    render = pathtrace.render_lambertian_sphere(env, settings.pathtrace_px, settings.spp, settings.passes, seed)
    expected, unc = pathtrace.quadrature_sphere(env, render)
    cc = pathtrace.compare(render, expected, unc)
    biased = pathtrace.compare(render, (1 + CROSSCHECK_BIAS) * expected, (1 + CROSSCHECK_BIAS) * unc)
    flipped = pathtrace.compare(render, expected[::-1], unc[::-1])
    return {
        "n_pixels": cc.n_pixels, "max_abs_z": cc.max_abs_z, "critical_z": cc.critical_z, "mean_z": cc.mean_z,
        "max_abs_mean_z": float(np.max(np.abs(cc.mean_z_channels))), "bias_limit": cc.bias_limit,
        "chi2_per_dof": cc.chi2_per_dof, "p_value": cc.p_value, "max_rel_diff": cc.max_rel_diff,
        "rel_masked_fraction": cc.rel_masked_fraction,
        "passed": cc.passed, "alpha": cc.alpha, "settings": cc.settings,
        "biased_max_abs_mean_z": float(np.max(np.abs(biased.mean_z_channels))),
        "flipped_max_abs_z": flipped.max_abs_z,
        "_arrays": {"render": cc.render, "quadrature": cc.quadrature, "z_image": cc.z_image},
    }


@dataclass
class Measurements:
    """What :func:`validate.experiments.sh9.compute` returns: numbers and the arrays for figures."""

    settings: Settings
    environments: dict[str, dict[str, Any]]
    crosschecks: dict[str, dict[str, Any]] = field(default_factory=dict)
    skipped: list[tuple[str, str]] = field(default_factory=list)


def _task(item: tuple[str, Environment], settings: Settings, published: dict, aliases: dict, seed: int) -> dict:
    """One task of :func:`compute`: ``("analyse", env)`` → :func:`analyse_environment`, ``("pathtrace", env)`` →
    :func:`pathtrace_crosscheck` (one ``ctx.map`` for both, so the cross-checks fill the workers the last
    environments leave idle)."""
    kind, env = item
    if kind == "pathtrace":
        return pathtrace_crosscheck(env, settings, seed)
    return analyse_environment(env, settings, published, aliases)


def compute(ctx: Context, s: Settings) -> Measurements:
    """Every environment, then the path-traced cross-checks of the reference, in one ``ctx.map`` (in this
    order: a cross-check reuses its environment's cached quadrature nodes; results keep the items' order)."""
    envs, skipped = ctx.environments()
    published, aliases = read_published_sh9(), read_aliases()
    by_name = {e.name: e for e in envs}
    checked = [n for n in s.pathtrace if n in by_name]
    items = [("analyse", e) for e in envs] + [("pathtrace", by_name[n]) for n in checked]
    out = ctx.map(partial(_task, settings=s, published=published, aliases=aliases, seed=ctx.seed), items,
                  "sh9: environments and path-traced cross-checks")
    results, cross = out[:len(envs)], out[len(envs):]
    return Measurements(s, {e.name: r for e, r in zip(envs, results, strict=True)},
                        dict(zip(checked, cross, strict=True)), list(skipped))
