"""The report: tone mapping, PNG figures, number formatting, results.json round trip and the HTML page."""

from __future__ import annotations

import json
import re
from pathlib import Path
from urllib.parse import unquote

import matplotlib.image as mpimg
import numpy as np
import pytest

from validate.errors import ValidateError
from validate.experiments.base import Claim, ExperimentResult, Figure, Section, Table
from validate.figures import plots
from validate.report import html
from validate.report.html import (
    fmt_measured,
    fmt_num,
    fmt_pct,
    fmt_threshold,
    load_results,
    write_report,
    write_results_json,
)

# 8-bit value of a pixel whose luminance is the auto-exposure percentile: displayed at 0.9 of white by
# construction, 255 · 0.9 = 229.5, which the float round trip through sRGB⁻¹ and f⁻¹ puts on 229 or 230.
AUTO_TARGET_U8 = (229, 230)
MASK_RGB = np.array([0xD9, 0xD9, 0xD9]) / 255.0  # plots.MASK_COLOUR
PNG_ATOL = 1.0 / 255.0  # imread returns 8-bit PNG values as float32 k/255


# ---------------------------------------------------------------------------------------------------
# Tone mapping
# ---------------------------------------------------------------------------------------------------

def test_tonemap_auto_exposure_puts_p99_at_target():
    rgb = np.full((8, 8, 3), 3.7, dtype=np.float32)
    out = plots.tonemap(rgb)
    assert out.dtype == np.uint8 and out.shape == (8, 8, 3)
    assert int(out[0, 0, 0]) in AUTO_TARGET_U8 and (out == out[0, 0, 0]).all()
    # Auto exposure is scale invariant: 1000× the radiance gives the same picture.
    np.testing.assert_array_equal(plots.tonemap(rgb * 1000.0), out)


def test_tonemap_auto_exposure_uses_99th_percentile():
    # A grey ramp of 1000 luminances 1..1000: Y₉₉ = 990.01 (numpy's linear interpolation).
    ramp = np.repeat(np.arange(1.0, 1001.0).reshape(20, 50, 1), 3, axis=-1)
    k = plots.auto_exposure(ramp)
    assert k == pytest.approx(plots.aces_filmic_inverse(float(plots.srgb_decode(0.9))) / 990.01, rel=1e-12)
    out = plots.tonemap(ramp)[..., 0].ravel()
    assert out[989] in AUTO_TARGET_U8 and (np.diff(out.astype(int)) >= 0).all()  # monotone curve
    # Half of Y₉₉ displays at 0.79 of white (module docstring): 255 · 0.79 ≈ 202.
    assert abs(int(out[494]) - 202) <= 1
    assert (np.diff(out.astype(int)) >= 0).all()  # monotone curve


def test_tonemap_nan_grey_negative_black_and_explicit_exposure():
    rgb = np.ones((4, 4, 3))
    rgb[0, 0] = np.nan
    rgb[0, 1, 1] = np.inf
    rgb[1, 1] = -5.0
    out = plots.tonemap(rgb, exposure=1.0)
    assert (out[0, 0] == plots.NAN_GREY).all() and (out[0, 1] == plots.NAN_GREY).all()
    assert (out[1, 1] == 0).all()
    expected = round(255 * float(plots.srgb_encode(plots.aces_filmic(np.array(1.0)))))
    assert (out[3, 3] == expected).all()
    assert (plots.tonemap(rgb, exposure=0.0)[2:] == 0).all()


def test_tonemap_grey_input_and_bad_shapes():
    assert plots.tonemap(np.ones((3, 5))).shape == (3, 5, 3)
    with pytest.raises(ValidateError, match="expected"):
        plots.tonemap(np.ones((3, 5, 4)))
    with pytest.raises(ValidateError, match="exposure"):
        plots.tonemap(np.ones((3, 5, 3)), exposure=-1.0)


def test_aces_and_srgb_inverses_round_trip():
    for t in (0.001, 0.05, 0.5, 0.9, 0.99):
        assert float(plots.aces_filmic(np.array(plots.aces_filmic_inverse(t)))) == pytest.approx(t, rel=1e-12)
        assert float(plots.srgb_encode(plots.srgb_decode(t))) == pytest.approx(t, rel=1e-12)


# ---------------------------------------------------------------------------------------------------
# PNG figures
# ---------------------------------------------------------------------------------------------------

def _png(path: Path) -> np.ndarray:
    assert path.is_file() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    return mpimg.imread(path)


def test_save_image_size_and_upscale(tmp_path):
    rgb = np.random.default_rng(0).random((16, 32, 3)).astype(np.float32) * 5.0
    plots.save_image(tmp_path / "a.png", rgb)
    plots.save_image(tmp_path / "b.png", rgb, exposure=0.5, upscale=3)
    a, b = _png(tmp_path / "a.png"), _png(tmp_path / "b.png")
    assert a.shape[:2] == (16, 32) and b.shape[:2] == (48, 96)
    np.testing.assert_allclose(a[..., :3], plots.tonemap(rgb) / 255.0, atol=PNG_ATOL)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "b.png"]  # no temp files left


@pytest.mark.parametrize("shape", [(32, 64), (40, 40)])
def test_save_heatmap_nan_mask_and_percent(tmp_path, shape):
    values = np.random.default_rng(1).random(shape) * 0.03
    values[: shape[0] // 4] = np.nan  # top quarter masked
    path = tmp_path / "heat.png"
    plots.save_heatmap(path, values, "relative error", "|ΔE|/E", percent=True)
    img = _png(path)
    w, h = plots.heatmap_size(*shape)
    assert img.shape[:2] == (round(h * plots.FIG_DPI), round(w * plots.FIG_DPI))
    mask_pixels = np.all(np.abs(img[..., :3] - MASK_RGB) <= PNG_ATOL, axis=-1).sum()
    # The masked quarter covers ≈ 1/4 of the map, which fills well over a third of the figure.
    assert mask_pixels > 0.25 * 0.3 * img.shape[0] * img.shape[1]

    fig = plots.heatmap_figure(values, "relative error", "|ΔE|/E", percent=True)
    fig.canvas.draw()
    cax = fig.axes[0].child_axes[0]
    labels = [t.get_text() for t in cax.get_yticklabels() if t.get_text()]
    assert labels and all(t.endswith("%") for t in labels)
    assert cax.get_ylabel() == "|ΔE|/E"
    assert fig.axes[0].get_xticks().size == 0 and fig.axes[0].get_yticks().size == 0


def test_save_heatmap_signed_and_all_nan(tmp_path):
    plots.save_heatmap(tmp_path / "s.png", np.linspace(-1, 2, 64).reshape(8, 8), "signed", "ΔE")
    plots.save_heatmap(tmp_path / "n.png", np.full((8, 16), np.nan), "empty", "ΔE")
    assert _png(tmp_path / "s.png").ndim == 3 and _png(tmp_path / "n.png").ndim == 3
    with pytest.raises(ValidateError, match="'bad'"):
        plots.save_heatmap(tmp_path / "x.png", np.ones(5), "bad", "ΔE")


def test_save_line_plot_size_percent_and_hlines(tmp_path):
    x = np.array([1.0, 2.0, 4.0, 8.0, 16.0])
    series = {"SH9": 0.05 / x, "hemisphere": np.array([0.2, 0.2, np.nan, 0.2, 0.2])}
    path = tmp_path / "line.png"
    plots.save_line_plot(path, x, series, "half-angle (deg)", "error", "sweep", logx=True,
                         hlines={"1 % budget": 0.01}, percent=True)
    img = _png(path)
    w, h = plots.FIG_SIZE
    assert img.shape[:2] == (round(h * plots.FIG_DPI), round(w * plots.FIG_DPI))

    fig = plots.line_plot_figure(x, series, "half-angle (deg)", "error", "sweep", logx=True,
                                 hlines={"1 % budget": 0.01}, percent=True)
    fig.canvas.draw()
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["SH9", "hemisphere", "1 % budget"]
    assert ax.get_lines()[-1].get_linestyle() == "--"
    ylabels = [t.get_text() for t in ax.get_yticklabels() if t.get_text()]
    assert ylabels and all(t.endswith("%") for t in ylabels)
    assert [t.get_text() for t in ax.get_xticklabels()] == ["1", "2", "4", "8", "16"]
    # Per-cent labels on a log axis spanning decades stay distinct (no run of "0%").
    fig = plots.line_plot_figure(x, {"e": 10.0 ** -x}, "x", "e", "t", logy=True, percent=True)
    fig.canvas.draw()
    ylabels = [t.get_text() for t in fig.axes[0].get_yticklabels() if t.get_text()]
    assert len(ylabels) >= 5 and len(set(ylabels)) == len(ylabels) and "1%" in ylabels
    with pytest.raises(ValidateError, match="'SH9'"):
        plots.save_line_plot(path, x, {"SH9": x[:3]}, "x", "y", "t")


def test_save_image_grid(tmp_path):
    rgb = np.ones((8, 16, 3))
    plots.save_image_grid(tmp_path / "g.png", [rgb, 0.5 * rgb, 0.5 * rgb], ["ref", "approx", "diff"])
    img = _png(tmp_path / "g.png")
    assert img.shape[1] > img.shape[0]
    with pytest.raises(ValidateError):
        plots.save_image_grid(tmp_path / "h.png", [rgb], ["a", "b"])


# ---------------------------------------------------------------------------------------------------
# Number formatting
# ---------------------------------------------------------------------------------------------------

def test_number_formats():
    assert fmt_pct(0.0086) == "0.86 %"
    assert fmt_pct(0.01) == "1 %"
    assert fmt_pct(0.123456) == "12.3 %"
    assert fmt_num(0.123456) == "0.123"
    assert fmt_num(1.234e-5) == "1.23e-5"
    assert fmt_num(2.5e7) == "2.5e7"
    assert fmt_num(1234.4) == "1234"
    assert fmt_num(42) == "42"
    assert fmt_num(0.0) == "0"
    assert fmt_num(float("nan")) == "NaN"
    assert fmt_num(None) == "—"
    pct_claim = {"measured": 0.0086, "uncertainty": 0.0001, "threshold": 0.01, "comparison": "<", "unit": "%"}
    # σ = 0.010 % keeps two digits (PDG rule, validate.format) and the value is rounded to σ's decimal
    assert fmt_measured(pct_claim) == "0.860 ± 0.010 %"
    assert fmt_threshold(pct_claim) == "< 1 %"
    plain = {"measured": 0.5, "uncertainty": 0.0, "threshold": 0.0, "comparison": ">", "unit": ""}
    assert fmt_measured(plain) == "0.5"
    assert fmt_threshold(plain) == "> 0"


# ---------------------------------------------------------------------------------------------------
# results.json and the page
# ---------------------------------------------------------------------------------------------------

def _results(out: Path) -> dict:
    fig_dir = out / "figures" / "sh9"
    x = np.array([1.0, 2.0, 4.0])
    plots.save_line_plot(fig_dir / "sweep.png", x, {"SH9": 0.02 / x}, "x", "error", "sweep", percent=True)
    err = np.full((8, 16), 0.004)
    err[:2] = np.nan
    plots.save_heatmap(fig_dir / "error map.png", err, "error", "|ΔE|/E", percent=True)
    plots.save_image(fig_dir / "env.png", np.ones((8, 16, 3)))
    sh9 = ExperimentResult(
        name="sh9", title="SH9 irradiance", summary="Order-2 SH against the quadrature reference <b>.",
        claims=[Claim("sh9-smooth", "SH9 error on smooth skies", "mean relative error", 0.01, 0.0086, 0.0001,
                      "<", "%", "R&H 2001"),
                Claim("sh9-sun", "SH9 error with a small sun", "max relative error", 0.03, 0.112, 0.002,
                      "<", "%", "budget")],
        findings=["Smooth skies hold within 1 %.", "A 0.5° sun rings."],
        sections=[Section("Maps", ["Paragraph with <script>alert(1)</script> in it."],
                          figures=[Figure("figures/sh9/sweep.png", "error vs size"),
                                   Figure("figures/sh9/error map.png", "error map", width=400)],
                          tables=[Table(["env", "mean"], [["sunsky", 0.0086], ["constant", 1.2e-7]],
                                        "per env")],
                          gallery=[[Figure("figures/sh9/env.png", "env A"),
                                    Figure("figures/sh9/env.png", "env B")]])],
        data={"per_env": {"sunsky": [0.0086, 0.1]}}, wall_time_s=1.5, settings={"normals": 256})
    energy = ExperimentResult(
        name="energy", title="Energy", summary="Flux conservation.",
        claims=[Claim("energy-flux", "flux ratio − 1", "relative flux error", 1e-4, 2.3e-6, 1.1e-6, "<", "",
                      "fp32")],
        wall_time_s=0.25)
    # "zeta" before "alpha": experiments keep insertion order, meta keys get sorted.
    return {"meta": {"wall_time_s": 1.75, "versions": {"numpy": "2", "drjit": "1.5"},
                     "backend": "llvm_ad_rgb", "generated": "2025-01-01T00:00:00",
                     "command": "validate run --quick", "quick": True,
                     "skipped_inputs": [["probes/bad.exr", "NaN texels"]]},
            "experiments": {"zeta_sh9": sh9.to_json(), "alpha_energy": energy.to_json()}}


def test_results_json_round_trip_and_order(tmp_path):
    results = _results(tmp_path)
    path = write_results_json(tmp_path, results)
    assert path == tmp_path / "results.json"
    assert load_results(tmp_path) == results
    text = path.read_text(encoding="utf-8")
    assert text.index('"zeta_sh9"') < text.index('"alpha_energy"')
    meta_keys = list(json.loads(text)["meta"])
    assert meta_keys == sorted(meta_keys)
    assert load_results(tmp_path / "nowhere") == {}


def test_results_json_numpy_values(tmp_path):
    write_results_json(tmp_path, {"experiments": {"x": {"v": np.float32(0.5), "a": np.arange(3)}}})
    assert load_results(tmp_path) == {"experiments": {"x": {"v": 0.5, "a": [0, 1, 2]}}}


@pytest.mark.parametrize("text", ['{"meta": {', "[1, 2]", ""])
def test_corrupt_results_json(tmp_path, text):
    (tmp_path / "results.json").write_text(text, encoding="utf-8")
    with pytest.raises(ValidateError) as err:
        load_results(tmp_path)
    msg = str(err.value)
    assert str(tmp_path / "results.json") in msg and "\n" not in msg


def _claim_rows(page: str) -> dict[str, list[tuple[str, str]]]:
    rows = re.findall(r"<tr class=\"(ok|bad)\" id=\"claim-[^\"]*\">(.*?)</tr>", page, flags=re.S)
    by_id: dict[str, list[tuple[str, str]]] = {}
    for cls, body in rows:
        cid = re.search(r"<code>([^<]+)</code>", body).group(1)
        by_id.setdefault(cid, []).append((cls, body))
    return by_id


def test_write_report(tmp_path):
    results = _results(tmp_path)
    results["experiments"]["zeta_sh9"]["claims"][0]["power"] = {
        "perturbation": "SH band 1 sign flipped", "measured": 0.04, "uncertainty": 0.0, "fails": True}
    write_results_json(tmp_path, results)
    index = write_report(tmp_path, results)
    assert index == tmp_path / "index.html"
    page = index.read_text(encoding="utf-8")
    sh9_page = (tmp_path / "exp-zeta_sh9.html").read_text(encoding="utf-8")
    energy_page = (tmp_path / "exp-alpha_energy.html").read_text(encoding="utf-8")

    assert "validate — real-time lighting vs physics" in page
    for claim_id in ("sh9-smooth", "sh9-sun", "energy-flux"):
        assert claim_id in page
    # the claims table keeps a unit on its number's line (no-break space before "%")
    assert "0.860 ± 0.010\u00a0%" in page and "&lt; 1 %" in page and "(2.3 ± 1.1)e-6" in page
    # overview: every claim once; each experiment page: its own claims
    by_id = _claim_rows(page)
    assert {k: len(v) for k, v in by_id.items()} == {"sh9-smooth": 1, "sh9-sun": 1, "energy-flux": 1}
    assert by_id["sh9-sun"][0][0] == "bad" and ">FAIL<" in by_id["sh9-sun"][0][1]
    assert by_id["sh9-smooth"][0][0] == "ok" and "SH band 1 sign flipped" in by_id["sh9-smooth"][0][1]
    assert "fails ✓" in by_id["sh9-smooth"][0][1]
    assert set(_claim_rows(sh9_page)) == {"sh9-smooth", "sh9-sun"}
    assert set(_claim_rows(energy_page)) == {"energy-flux"}
    # overview table links every page; pages link back and to each other
    assert 'href="exp-zeta_sh9.html"' in page and 'href="exp-alpha_energy.html"' in page
    assert 'href="index.html"' in sh9_page and 'href="exp-alpha_energy.html"' in sh9_page
    assert page.index('exp-zeta_sh9.html') < page.index('exp-alpha_energy.html')

    # text is escaped; meta, findings, skipped inputs and footer are there.
    for text in (page, sh9_page):
        assert "<script" not in text and "<link" not in text and "http://" not in text and "https://" not in text
    assert "&lt;script&gt;" in sh9_page and "&lt;b&gt;" in sh9_page
    assert "llvm_ad_rgb" in page and "validate run --quick" in page and "quick mode" in page
    assert "A 0.5° sun rings." in sh9_page and "probes/bad.exr" in page and "generated from" in page

    srcs = re.findall(r'<img src="([^"]+)"', sh9_page)
    assert len(srcs) == 4
    for src in srcs:
        assert not src.startswith(("/", "file:", "http")) and ".." not in src
        assert (tmp_path / unquote(src)).is_file()
    assert 'width="400"' in sh9_page

    leftovers = sorted(p.name for p in tmp_path.iterdir())
    assert leftovers == ["exp-alpha_energy.html", "exp-zeta_sh9.html", "figures", "index.html", "results.json"]
    assert not any(p.name.startswith(".") for p in tmp_path.rglob("*"))  # no temp files

    # a page of an experiment that is gone is removed on the next render
    del results["experiments"]["alpha_energy"]
    write_report(tmp_path, results)
    assert not (tmp_path / "exp-alpha_energy.html").exists()


def test_bench_json_is_shown(tmp_path):
    (tmp_path / "bench.json").write_text(json.dumps({"generated": "today", "tables": [
        {"headers": ["map", "time (s)"], "rows": [["1k", 0.5], ["8k", 9.0]], "caption": "SH9 by map size"}]}))
    page = write_report(tmp_path, _results(tmp_path)).read_text(encoding="utf-8")
    assert 'id="bench"' in page and "SH9 by map size" in page and "8k" in page


def test_report_from_loaded_results_matches(tmp_path):
    results = _results(tmp_path)
    write_results_json(tmp_path, results)
    assert html.render_report(tmp_path, load_results(tmp_path)) == html.render_report(tmp_path, results)


def test_missing_figure_and_empty_results(tmp_path):
    results = {"experiments": {"e": {"title": "E", "report": {"sections": [
        {"title": "S", "figures": [{"path": "figures/e/gone.png", "caption": "gone"},
                                   {"path": "/etc/passwd", "caption": "outside"}]}]}}}}
    write_report(tmp_path, results)
    page = (tmp_path / "exp-e.html").read_text(encoding="utf-8")
    assert "missing figure" in page and "figures/e/gone.png" in page and "outside the report folder" in page
    assert "<img" not in page
    empty = write_report(tmp_path, {}).read_text(encoding="utf-8")
    assert "No claims were recorded." in empty
    with pytest.raises(ValidateError, match="results.json"):
        write_report(tmp_path, {"experiments": ["not", "a", "mapping"]})


def _texts_inside(fig) -> list[str]:
    """Texts (titles, drawn tick labels, axis labels) of a drawn figure that stick out of it (clipped in
    the PNG), by the figure's tight bounding box (which counts only what is drawn) and each text."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    tight = fig.get_tightbbox(renderer)  # inches
    w, h = fig.get_size_inches()
    if tight.x0 >= -0.005 and tight.y0 >= -0.005 and tight.x1 <= w + 0.005 and tight.y1 <= h + 0.005:
        return []
    return [f"tight bbox {tight.bounds} exceeds the figure's {w:.2f} × {h:.2f} in"]


@pytest.mark.parametrize("n, columns", [(16, 7), (3, None), (1, 7)])
def test_image_grid_fixed_layout(tmp_path, n, columns):
    """Every panel shows its own image (distinct flat colours, each covering ≥ 80 % of its panel's nominal
    area), titles stay inside the figure, and the PNG is the figure's size at FIG_DPI."""
    levels = np.linspace(0.05, 1.0, n)
    images = [np.full((48, 48, 3), lv) * np.array([1.0, 0.6, 0.3]) for lv in levels]
    titles = [f"technique_{i}_name" for i in range(n)]
    fig = plots.image_grid_figure(images, titles, exposure=1.0, columns=columns)
    assert _texts_inside(fig) == []
    plots.save_image_grid(tmp_path / "g.png", images, titles, exposure=1.0, columns=columns)
    img = (_png(tmp_path / "g.png")[..., :3] * 255.0).round().astype(int)
    w_in, h_in = fig.get_size_inches()
    assert img.shape[:2] == (round(h_in * plots.FIG_DPI), round(w_in * plots.FIG_DPI))
    cols = n if columns is None else min(n, columns)
    panel_px = (min(2.6, 12.0 / cols) - 0.1) ** 2 * plots.FIG_DPI ** 2
    for im in images:
        colour = plots.tonemap(im[:1, :1], 1.0)[0, 0].astype(int)
        count = np.all(np.abs(img - colour) <= 1, axis=-1).sum()
        assert count >= 0.8 * panel_px, (colour, count, panel_px)


def test_heatmap_grid_fixed_layout(tmp_path):
    """One colour scale: the panel holding vmax shows the colour map's top colour, the zero panel its bottom;
    NaN pixels masked; the colour bar has per-cent tick labels and its label; no text outside the figure."""
    import matplotlib

    maps = [np.full((48, 48), 0.02 * k) for k in range(15)]
    maps[3][:24] = np.nan
    titles = [f"technique_{k}" for k in range(15)]
    label = "|Y(E′) − Y(E)| / Φ_Y"
    fig = plots.heatmap_grid_figure(maps, titles, label, percent=True)
    assert _texts_inside(fig) == []
    cax = fig.axes[-1]
    ticks = [t.get_text() for t in cax.get_yticklabels() if t.get_text()]
    assert ticks and all(t.endswith("%") for t in ticks) and cax.get_ylabel() == label
    plots.save_heatmap_grid(tmp_path / "h.png", maps, titles, label, percent=True)
    img = (_png(tmp_path / "h.png")[..., :3] * 255.0).round().astype(int)
    panel_px = (1.9 - 0.1) ** 2 * plots.FIG_DPI ** 2
    cmap = matplotlib.colormaps["magma"]
    for value, share in [(1.0, 1.0), (0.0, 1.0)]:
        colour = (np.array(cmap(value)[:3]) * 255.0).round().astype(int)
        count = np.all(np.abs(img - colour) <= 2, axis=-1).sum()
        assert count >= 0.8 * share * panel_px, (value, count)
    mask = np.all(np.abs(img - (MASK_RGB * 255.0).round()) <= 2, axis=-1).sum()
    assert mask >= 0.8 * 0.5 * panel_px


@pytest.mark.parametrize("shape, scale", [((32, 64), 0.03), ((40, 40), 4.0), ((96, 24), -0.5)])
def test_heatmap_fixed_layout_keeps_texts_inside(shape, scale):
    """The fixed layout leaves room for the title, the colour bar's tick labels and its label, for wide,
    square and tall maps, per-cent and signed labels."""
    values = np.random.default_rng(2).random(shape) * scale
    fig = plots.heatmap_figure(values, "sunsky_30deg: |E_SH9 − E| / Φ (all normals, lat-long)",
                               "error / total flux", percent=scale < 1.0)
    assert _texts_inside(fig) == []
