"""Findings and report sections of the ``listings`` experiment (numbers only from :class:`Measurements`)."""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

from ...local_models.listings.catalog import LISTINGS, SEED_FILES
from ...stats import Measured
from ..base import Context, NotRun, Section, Table
from .compute import Measurements

STATUS_WORDS = {"printed": "as printed", "edited": "with an edit", "unrunnable": "not runnable"}


def index_counts() -> dict[str, dict[str, int]]:
    """Per seed: how many listings run as printed, with an edit, or not at all."""
    out: dict[str, dict[str, int]] = {k: {w: 0 for w in STATUS_WORDS.values()} for k in SEED_FILES}
    for x in LISTINGS:
        out[x.seed][STATUS_WORDS[x.status]] += 1
    return out


def _gl_findings(m: Measurements) -> list[str]:
    if not m.gl["available"]:
        return [f"No OpenGL compatibility runtime here ({m.gl['reason']}): the GLSL rows are skipped, the Python "
                f"transcriptions stand in for the listings, and {len(m.gl['skipped'])} GLSL listing techniques are "
                f"not registered ({', '.join(m.gl['skipped'])})."]
    t = m.transcription
    worst = max(t, key=lambda k: t[k]["rel"])
    return [f"All {len(t)} runnable listings ran on {m.gl['renderer']}; each equals its float64 Python "
            f"transcription within {t[worst]['rel']:.1e} of its largest value (worst: {worst}; bound 1·10⁻⁵)."]


def _ct_findings(m: Measurements) -> list[str]:
    ct = m.cook_torrance

    def span(key: str) -> str:
        v = [ct[a][key]["energy_ratio"] for a in ct]
        return f"{min(v):.2f}–{max(v):.2f}×"
    return [f"Ganovelli's Cook–Torrance (eq. 6.60–6.66) against Mitsuba's Beckmann conductor, α ∈ "
            f"{{{', '.join(ct)}}}, reflected energy: as extracted (a fraction with no n·l, G2 without the 2) "
            f"{span('literal')}; with the 2 of eq. 6.62 restored in G2 {span('literal_g2x2')}; with the incident "
            f"n·l {span('with_nl')}; both {span('with_nl_g2x2')} (= the suite's cook_torrance_printed, "
            f"{span('cook_torrance_printed (suite)')}); the corrected form "
            f"{span('cook_torrance (corrected)')}. The printed text is wrong in four places: no π and no 4 in the "
            "denominator, no n·l, G2 lacks the 2 of eq. 6.62, and Schlick's F takes n·l instead of v·h."]


def _falloff_findings(m: Measurements) -> list[str]:
    f = m.falloff
    p, li = f["printed"], f["listing"]
    return [f"Fore June eq. 20.47 as printed (near branch M exp(s (d₀/d)^β)) meets the far branch at d₀ with slope "
            f"{p['slope_inner']:+.3f} against {p['slope_outer']:+.3f} (α = 2, d₀ = 2r, units of πL/r) and falls to "
            f"{p['at_d_small']:.2g} M at d = 10⁻³ r: against a Lambertian disc's exact E(d) it errs by up to "
            f"{p['max_rel_near']:.0%} inside d₀. The listing's pow(z/d0, beta) is C¹ (slopes {li['slope_inner']:+.4f} "
            f"/ {li['slope_outer']:+.4f}), tends to M ({li['at_d_small']:.4f} M at 10⁻³ r) and errs by at most "
            f"{li['max_rel']:.3f}. With the book's values (M, K, d₀, α) = (2, 1, 1, 1) the printed slopes at d₀ are "
            f"{p['book_slopes'][0]:+.3f} / {p['book_slopes'][1]:+.3f}, the listing's "
            f"{li['book_slopes'][0]:+.3f} / {li['book_slopes'][1]:+.3f}."]


def _point_findings(m: Measurements) -> list[str]:
    p = m.point
    lamp = next(v for k, v in p.items() if k.startswith("ganovelli_6_9 (") and isinstance(v, dict))
    usc = p["point_usc420_a1b1c0 (printed)"]
    red = next(v for k, v in p.items() if k.startswith("redbook_7_4 (") and isinstance(v, dict))
    return [f"Ganovelli Listing 6.9 (street lamps) delivers {lamp['ratio_min']:.3f}× Mitsuba's point-light irradiance "
            "on every receiver: its r = 0.03·3.14·3.14·|p − x| divides the inverse square by (0.03·3.14²)² = 0.0875 "
            "(Listing 6.12's area lights likewise by 0.01·3.14² = 0.0986, ×10.1).",
            f"USC lecture 11's a = b = 1, c = 0 ('a reasonable starting point') gives E/E_Mitsuba from "
            f"{usc['ratio_min']:.2f} to {usc['ratio_max']:.2f} over the plane (rel. L1 error {usc['rel_l1']:.2f}); "
            f"the Red Book's Example 7.4 with (0, 0, 1) matches Mitsuba to {red['max_rel']:.1e}."]


def _uberlight_findings(m: Measurements) -> list[str]:
    b, o = m.uberlight_book, m.orange
    pr = next(v for k, v in b["models"].items() if k.startswith("as printed"))
    lt = next(v for k, v in b["models"].items() if k.startswith("light term"))
    return [f"Fore June's überlight listing with Figure 20-17's values (a, b, A, B, d = 0.2, 0.3, 0.3, 0.4, 0.8; "
            f"zNear/zFar 1/2, edges 0.4/0.8; maxIntensity 2, d0 1, alpha 1 on the depth |z|) on the projector "
            f"scene's sphere ({b['pixels']} pixels, beam depths {b['depth_range'][0]:.2f}–{b['depth_range'][1]:.2f} "
            f"radii, inside the cuton/cutoff window) against Mitsuba's projector with the same beam shape: as printed "
            f"(with its ambient (0.5, 0.2, 0.2) and (n·h)⁴ term) max error {pr['max_rel']:.2f} of the peak, "
            f"{pr['scaled_max_rel']:.3f} after the best scale; its light term alone {lt['max_rel']:.3f}, "
            f"{lt['scaled_max_rel']:.3f} scaled (the 1/z falloff instead of 1/d²).",
            _barndoor_finding(m),
            f"Orange Book Listings 12.6/12.7 (no distance falloff; the book prints no parameter values) against the "
            f"projector ({o['pixels']} receivers, {o['runs']}): max error "
            f"{o['models']['as printed (no falloff)']['max_rel']:.2f} of the peak, "
            f"{o['models']['as printed (no falloff)']['scaled_max_rel']:.3f} after the best scale; × 1/d² "
            f"{o['models']['× 1/d² (corrected)']['scaled_max_rel']:.1e}."]


def _barndoor_finding(m: Measurements) -> str:
    b = m.barndoor_book
    pr = next(v for k, v in b["models"].items() if k.startswith("as printed"))
    lt = next(v for k, v in b["models"].items() if k.startswith("light term"))
    sh = next(v for k, v in b["models"].items() if k.startswith("the listing's shape"))
    ax, ay = (1e3 * a for a in b["aperture"])
    return (f"The same listing against a path-traced barn door of the book's beam (disc r = "
            f"{b['disc_radius'] * 1e3:.1f} mm behind a roundness-0.8 hole {ax:.0f} × {ay:.0f} mm at "
            f"{b['depth'] * 1e3:.0f} mm: edge centres (a + A)/2, (b + B)/2 and penumbra A − a at the sphere's nearest "
            f"depth; {b['pixels']} sphere pixels, ± {pr['uncertainty']:.3f} of the peak, {b['passes']} passes × "
            f"{b['spp']} spp): as printed max error {pr['max_rel']:.2f} ({pr['scaled_max_rel']:.2f} scaled), light "
            f"term {lt['max_rel']:.2f} ({lt['scaled_max_rel']:.2f} scaled); the listing's smoothstep edge alone with "
            f"the physical 1/d² {sh['max_rel']:.2f} — a physical penumbra is not the smoothstep between two "
            "superellipses.")


def _closed_form_findings(m: Measurements) -> list[str]:
    h, r = m.hemisphere, m.redbook_values
    return [f"The Red Book's 'actual analytic function' for hemisphere lighting, a = 1 − ½ sin θ (θ ≤ 90°), ½ sin θ "
            f"(θ > 90°), is not the irradiance fraction of a uniform sky over a Lambertian receiver, which is exactly "
            f"(1 + cos θ)/2 (Fore June eq. 20.6) — the formula the Red Book calls the 'roughly equivalent' shortcut. "
            f"They differ by up to {h['max_abs']:.3f} (at θ = {h['at_deg']:.0f}°); the equal areas the book notes "
            f"({h['area_printed']:.4f} = {h['area_exact']:.4f}) hide it.",
            f"The Red Book's suggested values (Shininess ≈ {r['shininess']:.0f}, Strength ≈ {r['strength']:.0f}, base "
            f"colour 1) reflect {r['albedo_normal']:.2f}× the incident light at normal incidence "
            f"({r['specular_albedo_normal']:.2f} from the highlight alone): energy conservation allows 1."]


def not_run(m: Measurements) -> list[NotRun]:
    """Without a GL runtime the listings' GLSL does not run (their Python transcriptions stand in)."""
    if m.gl["available"]:
        return []
    return [NotRun(f"the listings' GLSL ({len(m.gl['skipped'])} techniques)", f"no GL runtime: {m.gl['reason']}",
                   "python -m validate setup --system")]


def findings(m: Measurements) -> list[str]:
    counts = index_counts()
    idx = "; ".join(f"{k}: " + ", ".join(f"{n} {w}" for w, n in v.items()) for k, v in counts.items())
    return ([f"Listing index ({len(LISTINGS)} catalogued, docs/listings.md): {idx}."] + _gl_findings(m)
            + _ct_findings(m) + _falloff_findings(m) + _point_findings(m) + _uberlight_findings(m)
            + _closed_form_findings(m))


def _mitsuba_errors(m: Measurements) -> dict[str, str]:
    """Per listing, its error against Mitsuba where this experiment measures one (± its uncertainty)."""
    p, b, o = m.point, m.uberlight_book["models"], m.orange["models"]
    lamp = next(v for k, v in p.items() if k.startswith("ganovelli_6_9 (") and isinstance(v, dict))
    red = next(v for k, v in p.items() if k.startswith("redbook_7_4 (") and isinstance(v, dict))
    fj = next(v for k, v in b.items() if k.startswith("as printed"))
    oo = o["as printed (no falloff)"]
    return {"ganovelli_6_9": f"E/E_ref {lamp['ratio_min']:.3f}–{lamp['ratio_max']:.3f} ± 10⁻⁶ (point emitter)",
            "redbook_7_4": f"max |E/E_ref − 1| {red['max_rel']:.1e} ± 10⁻⁶ (point emitter)",
            "forejune_20_5": f"max {fj['max_rel']:.2f}, scaled {fj['scaled_max_rel']:.3f} of the peak ± "
                             f"{fj['uncertainty']:.0g} (projector, Figure 20-17's values)",
            "orange_12_6_12_7": f"max {oo['max_rel']:.2f}, scaled {oo['scaled_max_rel']:.3f} of the peak ± "
                                f"{oo['uncertainty']:.0g} (projector)"}


def _index_rows(m: Measurements) -> list[list[Any]]:
    rows = []
    vs = _mitsuba_errors(m)
    for x in LISTINGS:
        t = m.transcription.get(x.name)
        gl = "skipped (no GL)" if not m.gl["available"] and x.status != "unrunnable" and x.runs else (
            f"{t['rel']:.1e}" if t else "—")
        rows.append([x.seed, x.section, x.number, STATUS_WORDS[x.status] + ("" if x.runs else " (not run)"),
                     x.technique, gl, vs.get(x.name, "—")])
    return rows


def _model_rows(part: dict[str, Any]) -> list[list[Any]]:
    return [[k, f"{v['max_rel']:.3g}", f"{v['mean_rel']:.3g}", f"{v['scaled_max_rel']:.3g}", f"{v['scale']:.4g}",
             f"± {v['uncertainty']:.1g}"] for k, v in part["models"].items()]


def sections(m: Measurements, ctx: Context) -> list[Section]:
    del ctx
    ct_rows = [[a, k, f"{v['energy_ratio']:.3f} ± {v['uncertainty_energy']:.2g}",
                f"{v['rel_l1']:.3f} ± {v['uncertainty_rel_l1']:.2g}"] for a, d in m.cook_torrance.items()
               for k, v in d.items()]
    pt_rows = [[k, f"{v['ratio_min']:.4g}", f"{v['ratio_max']:.4g}", f"{v['rel_l1']:.3g}"]
               for k, v in m.point.items() if isinstance(v, dict)]
    head = ["model", "max |Δ|/peak (–)", "mean |Δ|/peak (–)", "scaled max (–)", "scale (×)", "± (–)"]
    return [
        Section("Listing index", [f"GL: {m.gl.get('renderer') or m.gl.get('reason')}"],
                tables=[Table(["seed", "section", "listing", "status", "technique", "GLSL vs Python, relative (–)",
                               "error vs Mitsuba (–)"],
                              _index_rows(m), "every lighting listing of the seeds; edits in docs/listings.md")]),
        Section("Cook–Torrance as printed (Ganovelli eq. 6.60–6.66)", tables=[
            Table(["α (–)", "reading", "energy vs Mitsuba (–)", "rel. L1 error (–)"], ct_rows,
                  "± = |grid n − grid n/2|; Mitsuba roughconductor (Beckmann)")]),
        Section("Point lights as printed", tables=[
            Table(["technique", "min E/E_ref (–)", "max E/E_ref (–)", "rel. L1 (–)"], pt_rows,
                  f"{m.point['receivers']} receivers on y = 0; reference: {m.point['reference']}")]),
        Section("Überlight listings against the projector", tables=[
            Table(head, _model_rows(m.uberlight_book), "Fore June's listing, Figure 20-17's values, sphere pixels"),
            Table(head, _model_rows(m.barndoor_book), "the same against a path-traced barn door of the book's beam "
                  "(± = largest per-pixel standard error / peak)"),
            Table(head, _model_rows(m.orange), "Orange Book Listings 12.6/12.7, the projector scene")]),
    ]


__all__ = ["findings", "index_counts", "not_run", "sections"]


def data(m: Measurements) -> dict[str, Any]:
    """The measurements as results.json data (the settings go under ``settings``), and ``index``: per catalogued
    listing its status and its errors (:func:`index_data`)."""
    return {**{k: v for k, v in asdict(m).items() if k != "settings"}, "index": index_data(m)}


def mitsuba_measured(m: Measurements) -> dict[str, Measured]:
    """Per listing measured against Mitsuba here, its largest relative error (dimensionless: |E/E_ref − 1| over the
    receivers for the point lights, |Δ|/peak over the pixels for the projectors) ± its uncertainty."""
    p, b, o = m.point, m.uberlight_book["models"], m.orange["models"]
    lamp = next(v for k, v in p.items() if k.startswith("ganovelli_6_9 (") and isinstance(v, dict))
    red = next(v for k, v in p.items() if k.startswith("redbook_7_4 (") and isinstance(v, dict))
    fj = next(v for k, v in b.items() if k.startswith("as printed"))
    oo = o["as printed (no falloff)"]
    point = {"reference": "point emitter", "over": "receivers"}
    return {"ganovelli_6_9": Measured(max(abs(lamp["ratio_min"] - 1.0), abs(lamp["ratio_max"] - 1.0)), 1e-6,
                                      stat="max", params=point),
            "redbook_7_4": Measured(red["max_rel"], 1e-6, stat="max", params=point),
            "forejune_20_5": Measured(fj["max_rel"], fj["uncertainty"], stat="max",
                                      params={"reference": "projector", "over": "pixels, of the peak"}),
            "orange_12_6_12_7": Measured(oo["max_rel"], oo["uncertainty"], stat="max",
                                         params={"reference": "projector", "over": "pixels, of the peak"})}


def index_data(m: Measurements) -> list[dict[str, Any]]:
    """One entry per catalogued listing: seed, listing, status (as printed / with an edit / not runnable), whether
    it runs, and its error against its float64 Python transcription (GLSL run; absent when it did not run) and
    against Mitsuba (absent where this experiment measures none), as measured values."""
    vs = mitsuba_measured(m)
    out = []
    for x in LISTINGS:
        t = m.transcription.get(x.name)
        out.append({"name": x.name, "seed": x.seed, "listing": x.number, "status": STATUS_WORDS[x.status],
                    "runs": bool(x.runs),
                    "transcription": Measured(t["rel"], stat="max").to_json() if t else None,
                    "mitsuba": vs[x.name].to_json() if x.name in vs else None})
    return out
