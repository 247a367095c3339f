"""Findings and report sections of the ``renders`` experiment: a table per scene (engine × metric) and the
images truth | engine | error."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...format import pm as fpm
from ...local_models.render import registry
from ...metrics.pixel_z import PixelJudgement, judge
from ..base import Figure, NotRun, Section, Table, settings_json
from ..formatting import pct, pm
from . import kinds as K
from .compute import Measurements, SceneResult, budget
from .settings import Settings

PUNCTUAL_NOTE = ("Point and spot lights in KHR_lights_punctual units (candela, inverse square, no range) on a "
                 "Lambertian plane and sphere, against Mitsuba's point and spot emitters (no Monte Carlo noise: delta "
                 "lights with next-event estimation, so the judgement rests on the budget). Mitsuba's spot ramps "
                 "linearly in angle (src/emitters/spot.cpp falloff_curve), KHR's reference falloff is "
                 "clamp((cos θ − cos θ_o)/(cos θ_i − cos θ_o))²: the reference disables Mitsuba's ramp (beam width = "
                 "cutoff) and projects an analytic texture with KHR's formula (reference 'mitsuba'); three.js's "
                 "smoothstep profile is a second reference ('smoothstep'), kept apart.")
HEMISPHERE_NOTE = ("Hemisphere light on a Lambertian sphere against Mitsuba's two-value environment (radiance sky "
                   "above the horizon, ground below; path-traced, per-pixel standard error from 8 passes). three's "
                   "HemisphereLight takes colour = irradiance (radiance L enters as intensity π), the LightProbe is "
                   "built as three's removed HemisphereLightProbe built its SH (radiance, intensity 1), Babylon's "
                   "HemisphericLight takes colour = radiance (its PBR term has no 1/π).")
REFERENCE_NOTE = ("Two references, kept apart: 'energy' — a white non-absorbing sphere in a radiance-1 furnace "
                  "returns exactly 1 (what a physically complete multiple-scattering model gives); 'model' — "
                  "glTF 2.0's single-scattering metal (Appendix B) path-traced by Mitsuba (roughconductor), so the "
                  "distance to it is the engine's approximation *plus* its multiscatter compensation; 'mitsuba' — "
                  "the Lambertian sphere under a directional light (exact model, exact integral).")


def scene_table(sr: SceneResult) -> Table:
    rows: list[list[Any]] = []
    for name, er in sr.engines.items():
        for kind, j in er.judgements.items():
            rows.append([name, kind, j.n_pixels, f"{100 * j.fraction_accepted:.2f}",
                         f"{j.max_abs_z:.2f} / {j.critical_z:.2f}", fpm(j.mean_rel, j.mean_rel_unc, scale=100),
                         fpm(j.max_rel, j.max_rel_unc, scale=100), f"{100 * j.mean_signed_rel:+.3f}",
                         f"{er.energy:.5f}",
                         f"{sr.reference_energy[kind][0]:.5f} ± {sr.reference_energy[kind][1]:.1e}",
                         f"{flip_mean(sr, er.image, sr.references[kind]):.4f}"])
    for name, why in sr.skipped.items():
        rows.append([name, "skipped", why, "", "", "", "", "", "", "", ""])
    return Table(["engine", "reference", "pixels (px)", "accepted (%)", "max|z| / z* (–)", "mean rel. err. (%)",
                  "max rel. err. (%)", "mean rel. bias (%)", "engine mean (W/(m²·sr))", "reference mean (W/(m²·sr))",
                  "mean HDR-FLIP (–)"], rows, caption=sr.scene.name + " — " + FLIP_NOTE)


FLIP_NOTE = ("FLIP: HDR-FLIP (flip_evaluator, ACES tone mapper, exposures from the reference's own range, 67 px per "
             "degree) of the engine against the reference mean over the judged pixels; display only, no claim")


def _flip_openmp() -> Any:
    """flip_evaluator's bundled libgomp (``flip_evaluator.libs/libgomp-*.so``, already loaded by the import), or None.

    ctypes opens the loaded library by its path, so ``omp_set_num_threads`` sets the calling thread's
    nthreads-var of the very runtime FLIP's parallel loops use (OpenMP 5.2 §3.2.1: it governs the parallel regions
    this thread starts)."""
    import ctypes
    import glob
    import os

    import flip_evaluator

    libs = glob.glob(os.path.join(os.path.dirname(os.path.dirname(flip_evaluator.__file__)), "flip_evaluator.libs",
                                  "libgomp*.so*"))
    try:
        return ctypes.CDLL(libs[0]) if libs else None
    except OSError:
        return None


_FLIP_OMP: list[Any] = []


def _flip_one_thread(fn: Any, *args: Any, **kw: Any) -> Any:
    """``fn(*args, **kw)`` with FLIP's OpenMP team at one thread, then the previous count again. A 64² image is
    a few milliseconds of work: on 2 shared cores libgomp's spinning team costs ~8× the CPU and ~5× the wall
    (measured, 20 HDR-FLIP calls: 2.80 s CPU / 13.7 s wall with 2 threads, 0.36 s / 2.9 s with 1), and the map
    and mean are bit-identical (per-pixel work; the same exposures)."""
    if not _FLIP_OMP:
        _FLIP_OMP.append(_flip_openmp())
    lib = _FLIP_OMP[0]
    if lib is None:
        return fn(*args, **kw)
    before = int(lib.omp_get_max_threads())
    lib.omp_set_num_threads(1)
    try:
        return fn(*args, **kw)
    finally:
        lib.omp_set_num_threads(before)


def flip_result(sr: SceneResult, image: np.ndarray, reference: np.ndarray) -> Any:
    """HDR-FLIP (:func:`validate.metrics.flip.flip_hdr`) of ``image`` against ``reference`` on the judged pixels
    (negative values, none in these images, clamped); one OpenMP thread (:func:`_flip_one_thread`)."""
    from ...metrics.flip import flip_hdr

    return _flip_one_thread(flip_hdr, np.nan_to_num(reference), image, sr.mask, negatives="clamp")


def flip_mean(sr: SceneResult, image: np.ndarray, reference: np.ndarray) -> float:
    return flip_result(sr, image, reference).mean


def flip_cell(sr: SceneResult, image: np.ndarray, reference: np.ndarray) -> str:
    """"mean (exposures start…stop stops, tone mapper)" — the parameters flip_evaluator used."""
    r = flip_result(sr, image, reference)
    p, nan = r.parameters, float("nan")
    return (f"{r.mean:.4f} (exposure {p.get('startExposure', nan):+.2f}…{p.get('stopExposure', nan):+.2f} stops, "
            f"{p.get('tonemapper', '?')})")


def scene_figure(sr: SceneResult, ctx: Any) -> Figure | None:
    from ...figures import plots

    if not sr.engines:
        return None
    kind = "mitsuba" if "mitsuba" in sr.references else ("model" if "model" in sr.references else "energy")
    images, titles = [np.nan_to_num(sr.references[kind])], [f"truth ({kind})"]
    for name, er in sr.engines.items():
        images.append(er.image)
        titles.append(name)
        j = er.judgements[kind]
        z = np.nan_to_num(j.z_image) / j.critical_z  # the per-pixel test: white = rejected (|z| ≥ z*)
        images.append(np.repeat(z[..., None], 3, axis=-1))
        titles.append(f"{name} |z| / z*")
    path, rel_path = ctx.figure_path("renders", f"{sr.scene.name}_r{sr.scene.resolution}.png")
    plots.save_image_grid(path, images, titles, exposure=1.0)
    return Figure(rel_path, f"{sr.scene.name}: truth | engine | z-map: the per-pixel |z| over the Šidák critical z* "
                            "(white: rejected, |z| ≥ z*; black: the engine equals the truth)")


def findings(m: Measurements) -> list[str]:
    out = []
    for sr in (x for x in m.scenes if x.kind is not K.PROBE_MATERIAL):  # the probe material rows: material_findings
        for name, er in sr.engines.items():
            for kind, j in er.judgements.items():
                out.append(f"{sr.scene.name}, {name} vs {kind}: {pct(j.fraction_accepted)} of {j.n_pixels} pixels "
                           f"accepted (z* = {j.critical_z:.2f}), mean |rel| {pm(j.mean_rel, j.mean_rel_unc)}, max "
                           f"{pm(j.max_rel, j.max_rel_unc)}, bias {j.mean_signed_rel:+.3%}.")
    out += punctual_findings(m) + hemisphere_findings(m) + probe_findings(m) + rect_findings(m)
    out += material_findings(m)
    metal = [s for s in m.scenes if "model" in s.reference_energy]
    if metal:
        loss = ", ".join(f"r {s.scene.material.roughness:g}: {s.reference_energy['model'][0]:.4f} ± "
                         f"{s.reference_energy['model'][1]:.1e}" for s in metal)
        out.append(f"glTF single-scattering white metal in the furnace (Mitsuba roughconductor) keeps {loss} of the "
                   "energy; an engine at 1 adds that much by its multiscatter term (three PR 32190).")
    return out


def _bias(j: PixelJudgement) -> str:
    return fpm(j.mean_signed_rel, j.mean_rel_unc, "%")


def point_findings(sr: SceneResult) -> list[str]:
    """KHR candela read as candela (three issue 24788): the engine/Mitsuba bias and three's light.power."""
    li, out = sr.scene.lights[0], []
    for name, er in sr.engines.items():
        j = er.judgements["mitsuba"]
        power = (er.info.get("light_power_lm") or [None])[0]
        extra = (f"; three's PointLight.power = {power:.4g} lm = 4π × {li.intensity:g} cd" if power is not None else "")
        out.append(f"{sr.scene.name}, {name} (three issue 24788, KHR candela vs lumens): with intensity = "
                   f"{li.intensity:g} cd the engine/Mitsuba bias is {_bias(j)} over {j.n_pixels} px — the engine reads "
                   f"candela; read as lumens (I/4π cd) the image would be × {1 / (4 * np.pi):.4f}{extra}.")
    return out


def spot_findings(sr: SceneResult) -> list[str]:
    """Penumbra (inner < θ < outer) and the rest judged apart against KHR's falloff; three's SpotLight.power."""
    from ...scenes.render_scenes import spot_penumbra

    li, pen, out = sr.scene.lights[0], spot_penumbra(sr.scene), []
    ref, se = sr.references["mitsuba"], sr.stderrs["mitsuba"]
    b, text = budget(sr.kind, ref)
    for name, er in sr.engines.items():
        jp = judge(er.image, ref, se, sr.dof, sr.mask & pen, b, text)
        jo = judge(er.image, ref, se, sr.dof, sr.mask & ~pen, b, text)
        out.append(f"{sr.scene.name}, {name} vs KHR's reference falloff: penumbra ({li.inner_deg:g}°–"
                   f"{li.outer_deg:g}°, {jp.n_pixels} px) {pct(jp.fraction_accepted)} accepted, mean rel. err. "
                   f"{fpm(jp.mean_rel, jp.mean_rel_unc, '%')}, max {fpm(jp.max_rel, jp.max_rel_unc, '%')}, bias "
                   f"{_bias(jp)}; outside it ({jo.n_pixels} px) {pct(jo.fraction_accepted)} accepted, max "
                   f"{fpm(jo.max_rel, jo.max_rel_unc, '%')}.")
        power = (er.info.get("light_power_lm") or [None])[0]
        if power is not None:
            from dataclasses import replace

            out.append(f"three's SpotLight.power = {power:.4g} lm (π × {li.intensity:g} cd whatever the cone); the "
                       f"flux it emits (smoothstep profile) is {replace(li, profile='smoothstep').flux():.4g} lm, "
                       f"KHR's profile would emit {li.flux():.4g} lm: a spot given .power = Φ emits "
                       f"{replace(li, profile='smoothstep').flux() / power:.3f} Φ.")
    return out


def punctual_findings(m: Measurements) -> list[str]:
    out: list[str] = []
    for sr in m.scenes:
        out += point_findings(sr) if sr.kind is K.POINT else spot_findings(sr) if sr.kind is K.SPOT else []
    return out


def hemisphere_findings(m: Measurements) -> list[str]:
    """Each engine's bias against the exact environment, and the LightProbe built as HemisphereLightProbe did against
    HemisphereLight at the same arguments (three issue 26668): π · probe(L, 1) / light(L, π) over the judged pixels."""
    out = []
    for sr in (s for s in m.scenes if s.kind is K.HEMISPHERE):
        js = {name: er.judgements["mitsuba"] for name, er in sr.engines.items()}
        biases = "; ".join(f"{name} {_bias(j)} ({pct(j.fraction_accepted)} accepted)" for name, j in js.items())
        out.append(f"{sr.scene.name} vs Mitsuba's two-value environment, engine/Mitsuba bias: {biases}. "
                   "mix(ground, sky, ½ + ½ n·up) is the exact irradiance of a two-value sky on a Lambertian receiver "
                   "(sky view factor (1 + cos θ)/2), so for this receiver it is not an approximation.")
        if {"three", "three_probe"} <= set(sr.engines):
            r = np.pi * sr.engines["three_probe"].image[sr.mask] / sr.engines["three"].image[sr.mask]
            out.append(f"three issue 26668: HemisphereLightProbe(sky, ground, k) / HemisphereLight(sky, ground, k) = "
                       f"{r.mean():.7f} ± {r.std(ddof=1) / np.sqrt(r.size):.1e} over {r.shape[0]} px × 3 channels "
                       f"(π = {np.pi:.7f}): the probe reads its colours as radiance, the light as irradiance — a "
                       "units factor π, not a formula error.")
    return out


PROBE_NOTE = ("The probe (ict_uffizi_256x128.hdr from --probes, 2 × 2 box means → 128 × 64 lat-long, texel centres "
              "in the probes' convention) lights white spheres: metal over roughness, and a Lambertian sphere. "
              "Mitsuba's envmap gets a (2H + 1)-row node lattice on which its bilinear lookup equals the GPU's "
              "bilinear texture exactly; three.js takes the texels as a float equirect DataTexture → PMREMGenerator, "
              "Babylon as an RGBE .hdr → HDRCubeTexture (its nearest-texel panorama-to-cube, spherical polynomial "
              "and prefilter). Reference (i) only: glTF 2.0's single-scattering GGX metal (Mitsuba roughconductor); "
              "the engines' multiscatter compensation shows as the energy ratio above 1 at high roughness. The "
              "multiscatter microsurface reference (ii) and glTF's dielectric and intermediate metalness are in the "
              "section '(b) Probe on glTF materials' below.")


def probe_table(m: Measurements) -> Table | None:
    """(b) per engine × roughness: per-pixel judgement, energy ratio and contrast ratio (compute.contrast_ratio)."""
    from .compute import contrast_ratio

    rows: list[list[Any]] = []
    for sr in (s for s in m.scenes if s.kind in (K.PROBE, K.PROBE_LAMBERT)):
        ref, se = sr.references["mitsuba"], sr.stderrs["mitsuba"]
        mat = sr.scene.material
        for name, er in sr.engines.items():
            j = er.judgements["mitsuba"]
            cv, cu = contrast_ratio(er.image, ref, se, sr.mask, m.settings.seed)
            ratio = float(er.image[sr.mask].mean() / ref[sr.mask].mean())
            rows.append([name, "Lambert" if sr.kind is K.PROBE_LAMBERT else "metal", f"{mat.roughness:g}",
                         j.n_pixels, f"{100 * j.fraction_accepted:.2f}", fpm(j.mean_rel, j.mean_rel_unc, scale=100),
                         fpm(j.max_rel, j.max_rel_unc, scale=100), fpm(j.mean_signed_rel, j.mean_rel_unc, scale=100),
                         f"{ratio:.4f}", fpm(cv, cu)])
    if not rows:
        return None
    return Table(["engine", "material", "roughness (–)", "pixels (px)", "accepted (%)", "mean rel. err. (%)",
                  "max rel. err. (%)", "mean rel. bias (%)", "energy ratio engine/Mitsuba (×)",
                  "contrast ratio std(engine)/std(truth) (×)"], rows, caption="(b) probe: white spheres")


def probe_findings(m: Measurements) -> list[str]:
    """three issues 17911/26796 (roughness 0.2–0.3 too shiny) and PR 32311 (middle roughness too crisp)."""
    from .compute import contrast_ratio

    out = [f"(b) probe: {m.probe_note} (H, W)."] if m.probe_note else []
    for sr in (s for s in m.scenes if s.kind is K.PROBE):
        r = sr.scene.material.roughness
        for name, er in sr.engines.items():
            cv, cu = contrast_ratio(er.image, sr.references["mitsuba"], sr.stderrs["mitsuba"], sr.mask,
                                    m.settings.seed)
            j = er.judgements["mitsuba"]
            issue = (" (three 17911/26796: 'too shiny' would be c > 1)" if 0.2 <= r <= 0.3 else
                     " (PR 32311: 'too crisp' would be c > 1)" if r == 0.5 else "")
            out.append(f"{sr.scene.name}, {name}: contrast ratio c = {fpm(cv, cu)}{issue}; bias "
                       f"{fpm(j.mean_signed_rel, j.mean_rel_unc, '%')}, mean |rel| "
                       f"{fpm(j.mean_rel, j.mean_rel_unc, '%')}, {pct(j.fraction_accepted)} of {j.n_pixels} px "
                       "accepted.")
    return out


# the substitution Babylon's rectangular light is rendered with (its engine's notes["rect"])
RECT_LTC_LABEL = registry.find("babylon").notes.get("rect", "") if registry.find("babylon") else ""
RECT_NOTE = ("A square 0.6 × 0.6 m area light of 10 nits beside the view (no camera ray meets it), tilted onto the "
             "Lambertian plane and facing the Lambertian sphere, against Mitsuba's rectangle with an area emitter of "
             "that radiance (next-event estimation; per-pixel standard error from 8 passes). three.js's "
             "RectAreaLight with RectAreaLightUniformsLib.init()'s LTC tables; Babylon's row is " + RECT_LTC_LABEL +
             ": its RectAreaLight loads areaLightsLTC.bin from assets.babylonjs.com, so Heitz et al. 2016's GGX "
             "tables (three's LTC_MAT_1 / LTC_MAT_2) are put where Babylon 9.35 looks for them (scene._ltcTextures; "
             "it has no public LTC provider) in the layout its shader reads. The Lambertian pixels do not depend on "
             "the table (diffuse = the LTC with the identity matrix, specular 0; measured bit-identical with a "
             "constant table). Pixels are judged apart where the whole rectangle is above the surface's horizon "
             "(Lambert's polygon formula exact, no clipping) and where it is clipped.")


def rect_table(m: Measurements) -> Table | None:
    """(d) per scene and engine, the judgement on all pixels, on those wholly above the horizon and the rest."""
    from ...scenes.render_scenes import rect_above_horizon

    rows: list[list[Any]] = []
    for sr in (s for s in m.scenes if s.kind is K.RECT):
        ref, se = sr.references["mitsuba"], sr.stderrs["mitsuba"]
        b, text = budget(sr.kind, ref)
        above = rect_above_horizon(sr.scene)
        for name, er in sr.engines.items():
            power = (er.info.get("light_power_lm") or [None])[0]
            for part, mk in (("all", sr.mask), ("above horizon", sr.mask & above), ("clipped", sr.mask & ~above)):
                if not mk.any():
                    continue
                j = judge(er.image, ref, se, sr.dof, mk, b, text)
                rows.append([sr.scene.name, f"{name} ({er.info['note']})" if er.info.get("note") else name, part,
                             j.n_pixels, f"{100 * j.fraction_accepted:.2f}",
                             fpm(j.mean_rel, j.mean_rel_unc, scale=100), fpm(j.max_rel, j.max_rel_unc, scale=100),
                             fpm(j.mean_signed_rel, j.mean_rel_unc, scale=100),
                             "" if power is None else f"{power:.4g}"])
        for name, why in sr.skipped.items():
            rows.append([sr.scene.name, name, "skipped", why, "", "", "", "", ""])
    if not rows:
        return None
    return Table(["scene", "engine", "pixel set", "pixels (px)", "accepted (%)", "mean rel. err. (%)",
                  "max rel. err. (%)", "mean rel. bias (%)", "light.power (lm)"], rows,
                 caption="(d) rectangular area light")


def rect_findings(m: Measurements) -> list[str]:
    """three issue 19214: RectAreaLight.intensity is luminance (nits); its .power is π·A·intensity lm. Babylon:
    the same unit (photometric scale 1 for area lights), shown by its units claim; its row's table substitution."""
    out = []
    for sr in (s for s in m.scenes if s.kind is K.RECT):
        for name, er in sr.engines.items():
            if er.info.get("note"):
                j = er.judgements["mitsuba"]
                out.append(f"{sr.scene.name}, {name} — {er.info['note']}: {pct(j.fraction_accepted)} of "
                           f"{j.n_pixels} px accepted, mean |rel| {fpm(j.mean_rel, j.mean_rel_unc, '%')}, max "
                           f"{fpm(j.max_rel, j.max_rel_unc, '%')}, bias {100 * j.mean_signed_rel:+.3f} %; "
                           "RectAreaLight.intensity is radiance (nits): light.js _getPhotometricScale is 1 for "
                           "area lights in every intensity mode.")
    for sr in (s for s in m.scenes if s.kind is K.RECT and s.scene.geometry == "sphere"):
        li = sr.scene.lights[0]
        for er in sr.engines.values():
            power = (er.info.get("light_power_lm") or [None])[0]
            if power is not None:
                out.append(f"three issue 19214: RectAreaLight(intensity {li.intensity:g}, "
                           f"{li.width:g} × {li.height:g} m)"
                           f".power = {power:.4g} lm = π·A·intensity ({np.pi * li.area() * li.intensity:.4g}): "
                           "intensity is luminance per area (nits); a light given .power = Φ has L = Φ/(πA).")
    return out


SECTIONS = ((K.FURNACE, "(a) White furnace", [REFERENCE_NOTE]),
            (K.DIRECTIONAL, "(c) Directional light, Lambertian", []),
            (K.POINT, "(c) Point lights, KHR_lights_punctual units", [PUNCTUAL_NOTE]),
            (K.SPOT, "(c) Spot light, KHR_lights_punctual cone", []),
            (K.HEMISPHERE, "(f) Hemisphere light", [HEMISPHERE_NOTE]))


def sections(m: Measurements, ctx: Any) -> list[Section]:
    out = []
    for kind, title, notes in SECTIONS:
        scenes = [s for s in m.scenes if s.kind is kind]
        figs = [f for f in (scene_figure(s, ctx) for s in scenes) if f is not None]
        out.append(Section(title, list(notes), figures=figs, tables=[scene_table(s) for s in scenes]))
    if any(s.kind is K.PROBE for s in m.scenes):
        scenes = [s for s in m.scenes if s.kind in (K.PROBE, K.PROBE_LAMBERT)]
        figs = [f for f in (scene_figure(s, ctx) for s in scenes) if f is not None]
        t = probe_table(m)
        out.append(Section("(b) Probe on spheres (roughness, prefilter and split-sum)", [PROBE_NOTE], figures=figs,
                           tables=[t] if t is not None else []))
    elif m.probe_note:
        out.append(Section("(b) Probe on spheres (roughness, prefilter and split-sum)", [m.probe_note]))
    rect = [s for s in m.scenes if s.kind is K.RECT]
    if rect:
        t = rect_table(m)
        out.append(Section("(d) Rectangular area light", [RECT_NOTE],
                           figures=[f for f in (scene_figure(s, ctx) for s in rect) if f is not None],
                           tables=[t] if t is not None else []))
    out += material_sections(m, ctx)
    for name in m.settings.engines:  # an engine's own paragraph on what it renders (its facts["report"])
        e = registry.find(name)
        if e is not None and e.facts.get("report"):
            out.append(Section(f"{e.product}: what it renders", [e.facts["report"]]))
    return out


def data(m: Measurements) -> dict:
    """results.json data: per scene and engine, frame times, energy and the per-pixel judgements."""
    return {"scenes": {s.scene.name: {"kind": s.kind.name, "skipped": s.skipped, "engines": {
        e: {"frame_ms": r.frame_ms, "wall_s": r.wall_s, "version": r.version, "energy": r.energy, "info": r.info,
            "judgements": {k: j.to_json() for k, j in r.judgements.items()}} for e, r in s.engines.items()},
        "reference_energy": s.reference_energy} for s in m.scenes}, "startup": m.startup,
        "bsdf_checks": m.bsdf_checks}


def not_run(m: Measurements) -> list[NotRun]:
    """The engines (of the main scenes, the shadows and the CDF part) that the missing runtime kept from running."""
    if m.missing is None:
        return []
    s = m.settings
    names = [*s.engines, *s.shadow_engines, *(("babylon",) if s.cdf_sizes else ())]
    what = ", ".join(dict.fromkeys(registry.product(n) for n in names))
    return [NotRun(what, f"{m.missing.piece}: {m.missing.why}", m.missing.fix)]


def summary(m: Measurements) -> str:
    """One line: what was rendered, or why every engine was skipped."""
    s = m.settings
    if m.missing is not None:
        return f"No engine judged: {m.missing.piece} missing ({m.missing.fix})."
    skipped = sorted({why for sc in m.scenes for why in sc.skipped.values()})
    if skipped and not any(sc.engines for sc in m.scenes):
        return "Skipped engines: " + "; ".join(skipped)
    return f"{len(m.scenes)} scenes × {len(s.engines)} engines at {s.resolution}² pixels."


def reported_settings(s: Settings, m: Measurements, ctx: Any) -> dict[str, Any]:
    """The settings the run used (the scene constants furnace_roughness, sun_lux, rect_resolution left out; the CDF
    part's only when it ran) and which probe (b) rendered."""
    unused = () if s.cdf_sizes else ("cdf_sizes", "cdf_resolution")
    return settings_json(s, omit=("furnace_roughness", "sun_lux", "rect_resolution", *unused), probe=m.probe_note)


# ---------------------------------------------------------------- (b) glTF materials: (i) and (ii) kept apart
MATERIAL_NOTE = ("White spheres (baseColor 1) over metalness × roughness under the probe, each engine's own "
                 "MeshPhysicalMaterial / PBRMaterial with glTF's core specular layer. Two references, kept apart: "
                 "'vs (i) glTF as specified' — glTF 2.0 Appendix B exactly (GGX D with α = roughness², Smith "
                 "height-correlated V, Schlick F, fresnel_mix with F₀ 0.04 over Lambert, conductor_fresnel, "
                 "material = mix(dielectric, metal, metallic)), the suite's Mitsuba plug-in gltf_metallic_roughness "
                 "(χ²-tested; claims renders.gltf_bsdf.*): the distance to it is the engine's real-time approximation "
                 "(prefilter, split-sum) plus its multiscatter compensation; 'vs (ii) multiscatter microsurface' — "
                 "the random-walk GGX conductor (Heitz et al. 2016, the suite's microsurface_walk, traced by BSDF "
                 "sampling) for the metal lobe, at metalness m the mix (1 − m)·(i)(0) + m·(ii)(1): the distance "
                 "from (i) to (ii) is glTF's own single-scattering energy loss. Energy ratios are the mean over the "
                 "judged pixels, ± the references' Monte Carlo standard error.")


def _ratio(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float]:
    """a/b ± the propagated standard errors (independent)."""
    r = a[0] / b[0]
    return r, abs(r) * float(np.hypot(a[1] / a[0], b[1] / b[0]))


def material_rows(m: Measurements) -> list[list[Any]]:
    from .compute import MATERIAL_REFERENCES

    rows: list[list[Any]] = []
    for sr in (s for s in m.scenes if s.kind is K.PROBE_MATERIAL):
        mat = sr.scene.material
        for name, er in sr.engines.items():
            for kind, j in er.judgements.items():
                r, u = _ratio((er.energy, 0.0), sr.reference_energy[kind])
                rows.append([f"{mat.metallic:g}", f"{mat.roughness:g}", name, MATERIAL_REFERENCES[kind], j.n_pixels,
                             f"{100 * j.fraction_accepted:.2f}", fpm(j.mean_rel, j.mean_rel_unc, scale=100),
                             fpm(j.mean_signed_rel, j.mean_rel_unc, scale=100), fpm(r, u),
                             flip_cell(sr, er.image, sr.references[kind])])
        for name, why in sr.skipped.items():
            rows.append([f"{mat.metallic:g}", f"{mat.roughness:g}", name, "skipped", why, "", "", "", "", ""])
    return rows


def material_reference_rows(m: Measurements) -> list[list[Any]]:
    """(i) against (ii): the model's own energy loss, per metalness × roughness."""
    rows = []
    for sr in (s for s in m.scenes if s.kind is K.PROBE_MATERIAL):
        e = sr.reference_energy
        ii = e.get("multiscatter")
        ratio = fpm(*_ratio(e["gltf"], ii)) if ii else "–"
        rows.append([f"{sr.scene.material.metallic:g}", f"{sr.scene.material.roughness:g}", fpm(*e["gltf"]),
                     fpm(*ii) if ii else "not rendered (no metal lobe)", ratio])
    return rows


def material_figure(sr: SceneResult, ctx: Any) -> Figure | None:
    """truth (i) | truth (ii) | per engine: image | |rel| vs (i) × 10."""
    from ...figures import plots

    if not sr.engines:
        return None
    images, titles = [np.nan_to_num(sr.references["gltf"])], ["truth (i) glTF"]
    if "multiscatter" in sr.references:
        images.append(np.nan_to_num(sr.references["multiscatter"]))
        titles.append("truth (ii) multiscatter")
    for name, er in sr.engines.items():
        images.append(er.image)
        titles.append(name)
        for kind, label in (("gltf", "(i)"), ("multiscatter", "(ii)")):
            if kind in er.judgements:
                rel = np.nan_to_num(np.abs(er.judgements[kind].rel_image))
                images.append(np.repeat(rel[..., None] * 10.0, 3, axis=-1))
                titles.append(f"{name} |rel| vs {label} × 10")
    path, rel_path = ctx.figure_path("renders", f"{sr.scene.name}_r{sr.scene.resolution}.png")
    plots.save_image_grid(path, images, titles, exposure=1.0)
    return Figure(rel_path, f"{sr.scene.name}: truth (i) | truth (ii) | per engine: image | relative error vs (i) × 10 "
                            "| vs (ii) × 10 (white = 10 %)")


def bsdf_check_table(m: Measurements) -> Table | None:
    b = m.bsdf_checks
    if not b:
        return None
    rows: list[list[Any]] = []
    for c in b["chi2"]:
        rows.append(["χ² sample vs pdf", f"metallic {c['metallic']:g}, roughness {c['roughness']:g}, μ_i "
                     f"{c['mu_i']:g}", f"p = {c['p_value']:.3g}", "accepted" if c["accepts"] else "rejected"])
    c = b["chi2_power"]
    rows.append(["χ² power: sampler α × 1.1", f"metallic {c['metallic']:g}, roughness {c['roughness']:g}",
                 f"p = {c['p_value']:.3g}", "accepted" if c["accepts"] else "rejected"])
    for a in b["albedo"]:
        rows.append(["albedo sample() vs quadrature", f"metallic {a['metallic']:g}, roughness {a['roughness']:g}, "
                     f"μ_i {a['mu_i']:g}", " / ".join(fpm(x, u) for x, u in zip(a["sampled"], a["unc"], strict=True))
                     + " vs " + " / ".join(f"{q:.5f}" for q in a["quadrature"]),
                     "z " + " / ".join(f"{z:+.2f}" for z in a["z"]) + "; F₀ 0.05: z "
                     + " / ".join(f"{z:+.1f}" for z in a["z_power"])])
    for x in b["metal_vs_roughconductor"]:
        rows.append(["metallic 1 vs roughconductor × G₂/(G₁G₁)", f"roughness {x['roughness']:g}, {x['pairs']} pairs",
                     f"max rel. {x['max_rel_diff']:.2e}", f"separable (as is): {x['separable_max_rel_diff']:.3g}"])
    return Table(["check", "case", "value (–)", "verdict / power (–)"], rows,
                 caption="glTF BSDF checks (reference (i)); albedo per channel R / G / B of baseColor (0, 0.5, 1)")


def material_sections(m: Measurements, ctx: Any) -> list[Section]:
    scenes = [s for s in m.scenes if s.kind is K.PROBE_MATERIAL]
    if not scenes:
        return []
    tables = [Table(["metalness (–)", "roughness (–)", "engine", "reference", "pixels (px)", "accepted (%)",
                     "mean rel. err. (%)", "mean rel. bias (%)", "energy ratio engine/reference (×)",
                     "mean HDR-FLIP (–)"], material_rows(m), caption="(b) materials per engine: " + FLIP_NOTE),
              Table(["metalness (–)", "roughness (–)", "(i) glTF mean (W/(m²·sr))",
                     "(ii) multiscatter mean (W/(m²·sr))", "(i)/(ii) (×)"], material_reference_rows(m),
                    caption="(b) materials: reference (i) against (ii), glTF's own energy loss")]
    t = bsdf_check_table(m)
    furnace = [s for s in m.scenes if s.kind is K.FURNACE_MATERIAL]
    tables += [scene_table(s) for s in furnace]
    figs = [f for f in (scene_figure(s, ctx) for s in furnace) if f is not None]
    figs += [f for f in (material_figure(s, ctx) for s in scenes) if f is not None]
    return [Section("(b) Probe on glTF materials: metalness × roughness, references (i) and (ii)", [MATERIAL_NOTE],
                    figures=figs, tables=tables + ([t] if t is not None else []))]


def material_findings(m: Measurements) -> list[str]:
    """three PR 32190 (multiscatter energy at intermediate metalness): engine/(ii) and (i)/(ii); the mix residual;
    the older reference (i) (roughconductor, separable masking) against glTF's height-correlated one."""
    from ...metrics.pixel_z import judge as _judge
    from .compute import PROBE_BUDGET_REL, linear_mix

    scenes = [s for s in m.scenes if s.kind is K.PROBE_MATERIAL]
    out = []
    for sr in scenes:
        mat, e = sr.scene.material, sr.reference_energy
        parts = []
        for name, er in sr.engines.items():
            ri = _ratio((er.energy, 0.0), e["gltf"])
            txt = f"{name}/(i) {fpm(*ri)}"
            if "multiscatter" in e:
                txt += f", {name}/(ii) {fpm(*_ratio((er.energy, 0.0), e['multiscatter']))}"
            mix = linear_mix(scenes, sr, name) if 0.0 < mat.metallic < 1.0 else None
            if mix is not None:
                j = _judge(er.image, mix, np.zeros_like(mix), sr.dof, sr.mask, 2 * PROBE_BUDGET_REL * mix, "mix")
                txt += (f", image/mix of its own m = 0 and 1 images: bias {j.mean_signed_rel:+.3%}, max |rel| "
                        f"{j.max_rel:.2%}, {pct(j.fraction_accepted)} within 2 × the probe budget")
            parts.append(txt)
        ii = f"; (i)/(ii) {fpm(*_ratio(e['gltf'], e['multiscatter']))}" if "multiscatter" in e else ""
        issue = " (three PR 32190: multiscatter energy at intermediate metalness)" if 0.0 < mat.metallic < 1.0 else ""
        out.append(f"(b) metalness {mat.metallic:g}, roughness {mat.roughness:g}{issue}: energy ratios "
                   + "; ".join(parts) + ii + ".")
    for sr in (s for s in m.scenes if s.kind is K.FURNACE_MATERIAL):
        mat, e = sr.scene.material, sr.reference_energy["gltf"]
        eng = "; ".join(f"{n} {er.energy:.5f}" for n, er in sr.engines.items())
        out.append(f"(a) white furnace, metalness {mat.metallic:g}, roughness {mat.roughness:g} (three PR 32190: "
                   f"multiscatter energy lost at intermediate metalness): mean radiance (truth 1) {eng}; glTF's single "
                   f"scattering (i) {fpm(*e)}.")
    older = {s.scene.material.roughness: s for s in m.scenes if s.kind is K.PROBE}
    for sr in (s for s in scenes if s.scene.material.metallic == 1.0 and s.scene.material.roughness in older):
        o = older[sr.scene.material.roughness]
        if o.scene.resolution == sr.scene.resolution:
            r = _ratio(o.reference_energy["mitsuba"], sr.reference_energy["gltf"])
            out.append(f"(b) white metal, roughness {sr.scene.material.roughness:g}: the older reference (i), Mitsuba "
                       f"roughconductor (separable masking G₁G₁), over glTF's height-correlated V: mean energy ratio "
                       f"{fpm(*r)} (the same pixels of each scene's mask).")
    return out
