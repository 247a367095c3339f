"""The report's at-a-glance parts: summary specs read from results.json, the verdict, the generic
fallback for plug-in experiments, finding groups and truth / technique / error sets."""

from __future__ import annotations

import math

import numpy as np
import pytest

from validate.figures import plots
from validate.report import summary
from validate.report.findings import group_findings, input_names
from validate.report.imagesets import find_set, png_size


def _stat(mx: float, sigma: float) -> dict:
    return {"mean": mx / 3, "max": mx, "mean_uncertainty": sigma, "max_uncertainty": sigma}


def _sh9_entry() -> dict:
    # techniques.<t>.metrics.<env>.flux_luminance as the sh9 experiment writes it
    errors = {"sh9": {"sky": 0.012, "probe": 0.032}, "sh1": {"sky": 0.05, "probe": 0.25}}
    return {"techniques": {t: {"metrics": {env: {"flux_luminance": _stat(v, 0.0004)} for env, v in envs.items()}}
                           for t, envs in errors.items()},
            "claims": []}


def test_sh9_matrix_and_verdict():
    s = summary.summary_for("sh9", _sh9_entry()).matrix  # the full matrix below the spread
    assert isinstance(s, summary.Matrix)
    assert s.rows == ["sh9", "sh1"] and s.cols == ["sky", "probe"]
    assert s.values == [[0.012, 0.032], [0.05, 0.25]]
    claims = [{"passed": True, "power": {"fails": True}}, {"passed": False, "power": {"fails": False}},
              {"passed": True, "power": None}]
    best, worst, tally = summary.verdict(s, claims)
    # worst over the environments ranks them: sh9 3.2 % < sh1 25 %; σ = 0.04 % → two decimals
    assert best.startswith("Best: sh9 — 3.20 ± 0.04 %") and "worst over environments" in best
    assert worst.startswith("Worst: sh1 — 25.00 ± 0.04 %")
    assert tally == ("Claims: 2/3 pass; power checks: 1/3 fail under their perturbation, as they must; "
                     "1 still pass under their perturbation; 1 without a power check.")


def test_generic_summary_for_a_plug_in_experiment():
    e = {"techniques": {"mine": {"metrics": {"rel.env_a": {"value": 0.1, "uncertainty": 0.01},
                                             "rel.env_b": {"value": 0.3, "uncertainty": 0.01},
                                             "other": {"value": 9.0, "uncertainty": 0.0}}},
                        "theirs": {"metrics": {"rel.env_a": {"value": 0.2, "uncertainty": 0.02}}}}}
    s = summary.summary_for("not_a_built_in", e)
    assert isinstance(s, summary.Matrix) and s.metric == "rel"
    assert s.rows == ["mine", "theirs"] and s.cols == ["env_a", "env_b"]
    assert math.isnan(s.values[1][1])  # not measured
    assert [r[0] for r in s.ranking()] == ["theirs", "mine"]  # worst over inputs: 0.2 < 0.3


@pytest.mark.parametrize("bad", [{"techniques": "junk"}, {"techniques": {"t": {"metrics": {"e": 3}}}},
                                 {"alpha_sweep": {"alpha_deg": "x", "errors": 5}}, {}])
def test_malformed_entries_give_no_summary_and_never_raise(bad):
    for name in [*summary.SUMMARIES, "plug_in"]:
        assert summary.summary_for(name, bad) is None
    assert summary.verdict(None, []) == ["Claims: none recorded."]


def test_shadows_curves_carry_their_uncertainty_bands():
    sweep = {str(n): {"0.02": {"hard": {"total": {"mean": 1.0 / n, "uncertainty": 0.1 / n}}}} for n in (1024, 256)}
    s = summary.summary_for("shadows", {"resolution_sweep": sweep})
    assert isinstance(s, summary.Curves)
    assert s.x == [256.0, 1024.0] and s.series["hard"] == [1 / 256, 1 / 1024]  # sorted by map size
    assert s.bands["hard"] == [0.1 / 256, 0.1 / 1024]


def test_summary_figures_are_drawn(tmp_path):
    from validate.report import summary_plots

    for name, spec in (("m", summary.summary_for("sh9", _sh9_entry()).matrix),
                       ("c", summary.Curves("t", "err, %", "x", [1.0, 2.0], {"a": [0.1, 0.0]}, {"a": [0.01, 0.01]}))):
        path = tmp_path / f"{name}.png"
        summary_plots.draw(spec, path)
        w, h = png_size(path)
        assert 300 < w <= summary_plots.MAX_WIDTH_IN * plots.FIG_DPI and h > 100


def test_findings_are_grouped():
    findings = ["technique a: 1 %", "b (the sky): 2 %", "sky: 3 %", "White-furnace albedo of a: 1",
                "White-furnace albedo of b: 2", "Something else entirely."]
    groups = group_findings(findings, techniques=["a", "b"], inputs=["sky"])
    assert [(g["title"], g["findings"]) for g in groups] == [
        ("By technique", findings[:2]), ("By input", [findings[2]]), ("White-furnace albedo", findings[3:5]),
        ("Other findings", [findings[5]])]
    many = group_findings([f"technique a: {i}" for i in range(5)], techniques=["a"])
    assert len(many[0]["visible"]) == 3 and len(many[0]["folded"]) == 2
    assert input_names({"environments": {"sky": {}}, "materials": ["m"]}) == {"sky", "m"}


def test_truth_technique_error_sets(tmp_path):
    plots.save_image(tmp_path / "a_reference.png", np.ones((6, 8, 3)))
    plots.save_image(tmp_path / "a_sh9.png", np.ones((6, 8, 3)))
    plots.save_image(tmp_path / "a_small.png", np.ones((3, 4, 3)))
    plots.save_heatmap(tmp_path / "a_error.png", np.ones((6, 8)), "e", "e")

    def fig(name: str, caption: str = "") -> dict:
        return {"src": name, "caption": caption, "exists": (tmp_path / name).is_file()}

    row = [fig("env.png", "environment"), fig("a_reference.png", "reference"), fig("a_small.png", "tiny"),
           fig("a_sh9.png", "SH9 sphere"), fig("a_error.png", "error heat map")]
    s = find_set(row, tmp_path)
    assert s is not None and (s["truth"]["src"], s["technique"]["src"], s["error"]["src"]) == (
        "a_reference.png", "a_sh9.png", "a_error.png")
    assert (s["width"], s["height"]) == (8, 6) and not s["linked"]  # the heat map has axes: no crosshair
    assert [f["src"] for f in s["rest"]] == ["env.png", "a_small.png"]
    assert find_set([row[1], row[2], row[4]], tmp_path) is None  # no technique image of the truth's size
    assert find_set([row[1], row[3]], tmp_path) is None  # no error map


def test_changes_rows_regressions_first_in_their_units():
    from validate.report.html import _changes

    exps = [{"claims": [{"id": "c.pct", "unit": "%"}, {"id": "bare", "unit": "%", "experiment": "x"}]}]
    rows = [{"kind": "metric", "key": "m.better", "old": 0.2, "new": 0.1, "old_uncertainty": 0.01,
             "new_uncertainty": 0.01, "change": -0.1, "exceeds_uncertainty": True, "status": "improved"},
            {"kind": "metric", "key": "m.same", "old": 0.2, "new": 0.2, "change": 0.0, "status": "unchanged"},
            {"kind": "claim", "key": "c.new", "old": None, "new": 0.5, "change": None, "status": "new"},
            {"kind": "claim", "key": "c.pct", "old": 0.0100, "new": 0.0123, "old_uncertainty": 0.0004,
             "new_uncertainty": 0.0004, "change": 0.0023, "exceeds_uncertainty": True, "status": "newly_failing"},
            {"kind": "metric", "key": "m.worse", "old": 1.0, "new": 2.0, "change": 1.0, "status": "regressed"},
            {"kind": "claim", "key": "x/bare", "old": 0.5, "new": 0.25, "change": -0.25, "status": "improved"}]
    out = _changes({"baseline": "b.json", "regressions": 2, "rows": rows}, exps)
    assert [r["key"] for r in out["rows"]] == ["m.worse", "c.pct", "c.new", "m.better", "x/bare"]
    # each row's unit: the claim's (an id without its experiment's prefix is keyed <experiment>/<id>; "—" for one
    # this run lacks), "–" for a technique metric (a relative error as stored)
    assert [r["unit_shown"] for r in out["rows"]] == ["–", "%", "—", "–", "%"]
    assert out["rows"][4]["new_text"] == "25 %"
    pct = out["rows"][1]
    assert (pct["old_text"], pct["new_text"], pct["change_text"]) == ("1.00 ± 0.04 %", "1.23 ± 0.04 %", "0.23 %")
    assert out["rows"][2]["old_text"] == "—" and out["baseline"] == "b.json"
    assert _changes(None, exps) is None


def test_ibl_bars_rank_each_technique_by_its_worst_material():
    comps = [{"group": "Lambertian", "parameter": "ρ = 0.8", "approximation": "sh9", "mean": 0.04,
              "mean_uncertainty": 0.02},
             {"group": "Phong", "parameter": "s = 10", "approximation": "pre", "mean": 0.7, "mean_uncertainty": 0.02},
             {"group": "Phong", "parameter": "s = 100", "approximation": "pre", "mean": 0.9, "mean_uncertainty": 0.01}]
    s = summary.summary_for("ibl", {"comparisons": comps})
    assert isinstance(s, summary.Bars) and s.groups == ["Lambertian ρ = 0.8", "Phong s = 10", "Phong s = 100"]
    assert s.ranking() == [("sh9", 0.04, 0.02), ("pre", 0.9, 0.01)]


def test_overview_names_the_environments_whose_noise_negatives_were_clamped(tmp_path):
    """Issue 23 item 4: an environment clamped by default is noted on the overview page (from
    meta.environments.<name>.clamped_negative); one that was not clamped is not listed."""
    from validate.report import html

    results = {"meta": {"environments": {
        "blender_world_interior": {"source": "x.exr", "clamped_negative": {"texels": 1, "min": -2.3e-6}},
        "grace_probe": {"source": "g.hdr"}}}, "experiments": {}}
    page = html.render_pages(tmp_path, results)["index.html"]
    assert "Negative texels clamped" in page and "blender_world_interior" in page and "-2.3e-06" in page
    assert "grace_probe" not in page.split('id="clamped"')[1].split("</section>")[0]


# ---------------------------------------------------------------------------------------------------
# The pages' own summaries: sh9 spread, worst case, listings, renders acceptance
# ---------------------------------------------------------------------------------------------------

def _sh9_spread_entry() -> dict:
    errors = {"sh9": {"sky": 0.012, "grace_probe": 0.032, "sun": 0.2}, "sh1": {"sky": 0.05, "grace_probe": 0.25},
              "sh4": {"sky": 0.001, "grace_probe": 0.01, "sun": 0.09}}
    e = _sh9_entry()
    e["techniques"] = {t: {"metrics": {env: {"flux_luminance": _stat(v, 0.0004)} for env, v in envs.items()}}
                       for t, envs in errors.items()}
    e["environments"] = {"sky": {"kind": "procedural"}, "grace_probe": {"kind": "probe", "published": {}},
                         "sun": {"kind": "procedural"}}
    return e


def _worstcase_entry() -> dict:
    cert = {"value": 0.09375, "uncertainty": 1e-6, "direction": [0.0, 1.0, 0.0]}
    lum = [[0.0] * 8 for _ in range(4)]
    lum[1][2] = 1.0
    return {"certificates": {"sh9": {"flux_luminance.max": cert}, "sh9_lanczos": {"flux_luminance.max": {
        "value": 0.2, "uncertainty": 1e-5, "direction": [1.0, 0.0, 0.0]}}},
        "searches": {"sh9": {"flux_luminance.max": {"value": 0.0936, "uncertainty": 1e-5}},
                     "zh3": {"flux_luminance.max": {"value": 0.25, "uncertainty": 0.002}}},
        "worst_lighting": {"sh9": {"height": 4, "width": 8, "luminance": lum}}}


def _listings_entry() -> dict:
    def m(v, s=0.0):
        return {"value": v, "uncertainty": s, "unit": ""}
    return {"gl": {"available": True}, "index": [
        {"name": "redbook_7_4", "seed": "redbook", "listing": "Example 7.4", "status": "with an edit", "runs": True,
         "transcription": m(3e-7), "mitsuba": m(4e-7, 1e-6)},
        {"name": "orange_12_6_12_7", "seed": "orange", "listing": "Listings 12.6", "status": "as printed",
         "runs": True, "transcription": m(8e-7), "mitsuba": m(12.0, 0.01)},
        {"name": "ganovelli_6_12", "seed": "ganovelli", "listing": "Listing 6.12", "status": "not runnable",
         "runs": True, "transcription": None, "mitsuba": None}]}


def _judgement(f: float) -> dict:
    return {"n_pixels": 100, "fraction_accepted": {"value": f, "uncertainty": 0.0, "unit": "%", "better": "higher"}}


def _renders_entry() -> dict:
    return {"scenes": {
        "point_plane": {"kind": "point", "skipped": {}, "engines": {
            "three": {"judgements": {"mitsuba": _judgement(1.0)}},
            "filament": {"judgements": {"mitsuba": _judgement(0.5)}}}},
        "furnace_metal_r1": {"kind": "furnace", "skipped": {"filament": "no IBL"}, "engines": {
            "three": {"judgements": {"energy": _judgement(1.0), "model": _judgement(0.011)}}}}},
        "report": {"sections": [{"figures": [{"path": "figures/renders/point_plane_r64.png", "caption": "strip"},
                                             {"path": "figures/renders/furnace_metal_r1_r64.png", "caption": "s"}]}]}}


PAGE_ENTRIES = {"sh9": _sh9_spread_entry, "worstcase": _worstcase_entry, "listings": _listings_entry,
                "renders": _renders_entry}


def test_sh9_spread_sorts_by_median_and_marks_the_papers_probes():
    s = summary.summary_for("sh9", _sh9_spread_entry())
    assert isinstance(s, summary.Spread)
    assert s.rows == ["sh4", "sh9", "sh1"]  # median of the max over the environments: 1 %, 3.2 %, 15 %
    assert s.marked == ["grace_probe"] and list(s.panels) == ["mean over the normals", "max over the normals"]
    assert s.hlines["max over the normals"] == {"R&H: max < 5 %": 0.05}
    assert s.matrix is not None and s.matrix.rows == ["sh9", "sh1", "sh4"]  # the full matrix, as measured
    assert summary.verdict(s, [])[0].startswith("Best: sh4 — 9")  # worst over the environments: 9 %


def test_worstcase_certificate_beside_search_with_the_lighting():
    s = summary.summary_for("worstcase", _worstcase_entry())
    assert isinstance(s, summary.Worst)
    assert s.rows == ["sh9", "sh9_lanczos", "zh3"]
    assert s.certificate[0] == (0.09375, 1e-6) and math.isnan(s.certificate[2][0])
    assert s.search[2] == (0.25, 0.002) and math.isnan(s.search[1][0])
    assert s.maps[0][1][2] == 1.0 and s.maps[1] is None
    assert s.stars[0][1] == pytest.approx(0.0)  # +y: θ = 0, the top row of the map
    assert s.stars[1] == (pytest.approx(0.25), pytest.approx(0.5))  # +x: φ = 90°, the horizon
    assert [r[0] for r in s.ranking()] == ["sh9", "sh9_lanczos", "zh3"]


def test_listings_rows_status_and_errors():
    s = summary.summary_for("listings", _listings_entry())
    assert isinstance(s, summary.Listings)
    assert s.rows == ["Red Book 7.4", "Orange Book 12.6 12.7", "Ganovelli 6.12"]
    assert s.status == ["with an edit", "as printed", "not runnable"]
    assert s.transcription[0] == (3e-7, 0.0) and s.mitsuba[1] == (12.0, 0.01) and s.why[2] == "not run"
    assert "Listings: 1 with an edit, 1 as printed, 1 not runnable (3 catalogued)." in summary.verdict(s, [])


def test_renders_acceptance_names_the_reference_and_the_strip():
    s = summary.summary_for("renders", _renders_entry())
    assert isinstance(s, summary.Acceptance)
    assert s.rows == ["three", "filament"] and s.cols == ["point_plane", "furnace_metal_r1"]
    assert s.values[0] == [1.0, 0.011] and s.refs[0] == ["mitsuba", "model"]  # model before energy
    assert s.others[0][1] == "energy 100.0 %"
    assert math.isnan(s.values[1][1]) and s.skipped[1][1] == "no IBL"
    assert s.strips == ["figures/renders/point_plane_r64.png", "figures/renders/furnace_metal_r1_r64.png"]
    assert [r[0] for r in s.ranking()] == ["filament", "three"]  # lowest fraction accepted: 50 % > 1.1 %


@pytest.mark.parametrize("name", [*PAGE_ENTRIES, "engines", "shadows", "ibl"])
def test_summary_figures_are_readable(name, tmp_path):
    """Every text at the body's size or larger, none past the edge, none overlapping another; the figure fits
    the page column and the fold; it leaves as PNG and SVG."""
    from validate.report import summary_plots

    entry = PAGE_ENTRIES[name]() if name in PAGE_ENTRIES else None
    if name == "engines":
        entry = _sh9_entry()
    elif name == "shadows":
        entry = {"resolution_sweep": {str(n): {"0.02": {t: {"total": {"mean": k / n, "uncertainty": 0.1 / n}}
                                                        for k, t in enumerate(["hard", "pcf", "vsm"], 1)}}
                                      for n in (256, 512, 1024, 2048)}}
    elif name == "ibl":
        entry = {"comparisons": [{"approximation": f"technique_{i}", "group": "Lambertian", "mean": 0.01 * (i + 1),
                                  "mean_uncertainty": 0.001} for i in range(12)]}
    spec = summary.summary_for(name, entry)
    assert spec is not None
    fig = summary_plots.figure(spec)
    assert summary_plots.text_problems(fig) == []
    w, h = fig.get_size_inches()
    assert w <= summary_plots.MAX_WIDTH_IN + 1e-9 and h <= summary_plots.MAX_HEIGHT_IN + 1e-9
    for ext in ("png", "svg"):
        summary_plots.draw(spec, tmp_path / f"{name}.{ext}")
    assert png_size(tmp_path / f"{name}.png")[0] == round(w * plots.FIG_DPI)


def test_text_problems_sees_small_overlapping_and_clipped_text():
    from validate.report import summary_plots

    fig = plots._new_figure((3.0, 2.0), layout=None)
    fig.text(0.1, 0.5, "small", fontsize=6)
    fig.text(0.1, 0.5, "overlapping", fontsize=summary.FONT_PT)
    fig.text(0.9, 0.1, "past the right edge", fontsize=summary.FONT_PT)
    problems = summary_plots.text_problems(fig)
    assert any("'small' at 6 pt" in p for p in problems)
    assert any("overlaps" in p for p in problems)
    assert any("past the edge" in p for p in problems)
