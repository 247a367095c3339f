"""The report as a person sees it: every page loaded in headless Chromium (Debian's ``chromium``
package; nothing downloads a browser), every image decoded, every internal link resolved."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from validate.experiments.base import Claim, ExperimentResult, Figure, Section, Table
from validate.figures import plots
from validate.report.html import write_report, write_results_json

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="Debian's chromium is not installed (scripts/setup.sh "
                                                          "installs it)")

# A harness page beside the report: loads every page in an iframe (file:// access allowed by flag), makes
# lazy images eager, waits for them, then checks every <img> decoded and every <a href> resolves (an
# anchor to an element id on its page, a page of the report, or an image that decodes).
HARNESS = """<!DOCTYPE html><html><body><pre id="out">pending</pre><script>
const pages = %s;
const loadFrame = src => new Promise(res => { const f = document.createElement('iframe');
  f.style.width = '1400px'; f.style.height = '900px'; f.onload = () => res(f); f.src = src;
  document.body.appendChild(f); });
const loadImage = src => new Promise(res => { const im = new Image();
  im.onload = () => res(im.naturalWidth > 0); im.onerror = () => res(false); im.src = src; });
async function main() {
  const docs = {}, out = {images: [], links: []};
  for (const p of pages) { docs[p] = (await loadFrame(p)).contentDocument; }
  for (const p of pages) {
    const d = docs[p];
    for (const im of Array.from(d.images)) {
      out.images.push([p, im.getAttribute('src'), await loadImage(im.src)]);
    }
    for (const a of Array.from(d.querySelectorAll('a[href]'))) {
      const href = a.getAttribute('href');
      const [file, frag] = href.split('#');
      const target = file ? decodeURIComponent(file) : p;
      let ok;
      if (target in docs) ok = !frag || d.defaultView && !!docs[target].getElementById(frag);
      else if (/\\.(png|jpe?g|svg)$/i.test(target)) ok = await loadImage(new URL(href, d.baseURI).href);
      else ok = false;
      out.links.push([p, href, ok]);
    }
  }
  document.getElementById('out').textContent = JSON.stringify(out);
}
main().catch(e => { document.getElementById('out').textContent = 'error: ' + e; });
</script></body></html>"""


def _run_harness(folder: Path, html: str, window: str = "1400,900") -> dict:
    """Load ``html`` (written beside the report) in headless Chromium; return the JSON it leaves in
    ``<pre id="out">``."""
    harness = folder / "_harness.html"
    harness.write_text(html, encoding="utf-8")
    cmd = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--allow-file-access-from-files",
           "--hide-scrollbars", f"--window-size={window}", "--virtual-time-budget=20000", "--dump-dom",
           harness.as_uri()]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    text = proc.stdout
    start, end = text.find('<pre id="out">') + len('<pre id="out">'), text.find("</pre>")
    payload = text[start:end].replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", '"')
    assert payload.startswith("{"), f"harness did not finish: {payload[:300]!r} / {proc.stderr[-500:]}"
    return json.loads(payload)


def _results(out: Path) -> dict:
    fig = out / "figures" / "demo"
    plots.save_line_plot(fig / "sweep.png", np.arange(1.0, 4.0), {"a": np.array([3.0, 2.0, 1.0])}, "x", "y", "t")
    plots.save_image(fig / "env map.png", np.ones((8, 16, 3)))
    claim = Claim("demo.claim", "a claim", "metric", 0.01, 0.002, 0.001, source="a paper, eq. 1")
    claim.with_power("error × 5", 0.01)
    demo = ExperimentResult("demo", "Demo experiment", "summary", claims=[claim], findings=["a finding"],
                            sections=[Section("One", ["text"], figures=[Figure("figures/demo/sweep.png", "plot")],
                                              tables=[Table(["a"], [[1.0]])],
                                              gallery=[[Figure("figures/demo/env map.png", "env")]]),
                                      Section("Two", ["more"])])
    other = ExperimentResult("other", "Other experiment", "summary", claims=[
        Claim("other.claim", "fails", "m", 0.01, 0.5, 0.0).with_power("none", 0.6)])
    return {"meta": {"backend": "llvm_ad_rgb"},
            "experiments": {"demo": demo.to_json(), "other": other.to_json()}}


def test_every_image_loads_and_every_internal_link_resolves(tmp_path):
    results = _results(tmp_path)
    write_results_json(tmp_path, results)
    write_report(tmp_path, results)
    pages = sorted(p.name for p in tmp_path.glob("*.html"))
    assert pages == ["exp-demo.html", "exp-other.html", "index.html"]
    out = _run_harness(tmp_path, HARNESS % json.dumps(pages))
    assert len(out["images"]) >= 2 and all(ok for _, _, ok in out["images"]), out["images"]
    broken = [link for link in out["links"] if not link[2]]
    assert not broken, broken
    hrefs = {h for _, h, _ in out["links"]}
    assert {"exp-demo.html", "exp-other.html", "index.html"} <= hrefs  # navigation in both directions
    assert any(h.startswith("#") for h in hrefs)  # tables of contents


# The start of both harnesses below: the pages (a %s the caller fills), a 1280 × 800 iframe loader, an image waiter.
FRAME_HARNESS = """<!DOCTYPE html><html><body style="margin:0"><pre id="out">pending</pre><script>
const pages = %s;
const loadFrame = src => new Promise(res => { const f = document.createElement('iframe');
  f.style.width = '1280px'; f.style.height = '800px'; f.style.border = '0'; f.onload = () => res(f); f.src = src;
  document.body.insertBefore(f, document.body.firstChild); });
const settle = im => im.complete ? Promise.resolve() : new Promise(r => { im.onload = im.onerror = r; });
"""


# A harness that loads each page in a 1280 × 800 iframe (the window), opens every <details>,
# waits for the images, then measures: the summary figure's box, every table wrapper's scroll and
# client widths (and whether it scrolls by design), the page's own scroll width, and — on pages with a
# comparison widget — which image is visible at a point of the widget before and after each control.
LAYOUT_HARNESS = FRAME_HARNESS + """async function measure(p) {
  const f = await loadFrame(p), d = f.contentDocument, w = f.contentWindow;
  for (const im of Array.from(d.images)) { im.loading = 'eager'; await settle(im); }
  const res = {page: p};
  const fig = d.querySelector('.at-a-glance img');
  if (fig) { const r = fig.getBoundingClientRect(); res.summary = [r.top, r.bottom, fig.naturalWidth]; }
  for (const det of Array.from(d.querySelectorAll('details'))) det.open = true;
  res.tables = Array.from(d.querySelectorAll('.table-wrap')).map(wr => [wr.querySelector('table').className,
    wr.scrollWidth, wr.clientWidth, w.getComputedStyle(wr).overflowX]);
  res.width = [d.documentElement.scrollWidth, d.documentElement.clientWidth];
  const set = d.querySelector('[data-compare]');
  if (set) {
    set.scrollIntoView();
    const v = set.querySelector('.cmp-view').getBoundingClientRect();
    const at = fx => { const e = d.elementFromPoint(v.left + v.width * fx, v.top + v.height / 2);
      return e ? e.className : null; };
    const cmp = {start: [at(0.25), at(0.75)]};
    set.querySelector('button[data-show=technique]').click(); cmp.technique = [at(0.25), at(0.75)];
    set.querySelector('button[data-show=truth]').click(); cmp.truth = [at(0.25), at(0.75)];
    const range = set.querySelector('input.cmp-range'); range.value = '80';
    range.dispatchEvent(new Event('input')); cmp.wipe80 = [at(0.5), at(0.9)];
    cmp.state = set.getAttribute('data-state');
    res.compare = cmp;
  }
  f.remove();
  return res;
}
async function main() { const out = []; for (const p of pages) out.push(await measure(p));
  document.getElementById('out').textContent = JSON.stringify({pages: out}); }
main().catch(e => { document.getElementById('out').textContent = 'error: ' + e; });
</script></body></html>"""

LONG = ("a claim description long enough to need several lines in its cell, with a source that names the "
        "paper, the equation and the table it comes from ")


def _layout_results(out: Path) -> dict:
    """A page with everything that can overflow: long claims, a 16-column table, long unbroken ids, a
    truth / technique / error set, technique metrics (the generic summary figure) and a changes entry."""
    d = out / "figures" / "cmp"
    truth, tech = np.full((16, 16, 3), 0.2), np.full((16, 16, 3), 0.2)
    tech[..., 0] = 0.9
    plots.save_image(d / "sphere_reference.png", truth, exposure=1.0)
    plots.save_image(d / "sphere_technique.png", tech, exposure=1.0)
    plots.save_heatmap(d / "error map.png", np.abs(tech - truth)[..., 0], "error", "|ΔL|/L", percent=True)
    claims = [Claim(f"cmp.technique.some_long_technique_name_{i}.relative_error_over_every_environment",
                    LONG * 2, "max relative error over every environment and every normal", 0.05, 0.0123,
                    0.0004, unit="%", source=LONG).with_power(LONG, 0.2) for i in range(3)]
    table = Table([f"column {i} (%)" for i in range(16)], [[0.123456 * i for i in range(16)]] * 3 + [[LONG * 3] * 16])
    gallery = [[Figure("figures/cmp/sphere_reference.png", "reference sphere (Mitsuba)"),
                Figure("figures/cmp/sphere_technique.png", "technique sphere"),
                Figure("figures/cmp/error map.png", "error heat map, % of L")]]
    e = ExperimentResult("cmp", "Comparison", "summary", claims=claims, findings=[f"technique t{i}: finding {i}"
                                                                                 for i in range(6)],
                         sections=[Section("Images", ["text"], tables=[table], gallery=gallery)],
                         techniques={f"t{i}": {"family": "f", "metrics": {"err.env_a": {"value": 0.01 * (i + 1),
                                                                                        "uncertainty": 0.001}}}
                                     for i in range(3)})
    changes = {"baseline": "old/results.json", "regressions": 1, "rows": [
        {"kind": "claim", "key": claims[0].id, "old": 0.0100, "new": 0.0123, "old_uncertainty": 0.0004,
         "new_uncertainty": 0.0004, "change": 0.0023, "exceeds_uncertainty": True, "status": "regressed"},
        {"kind": "metric", "key": "cmp.t0.err.env_a", "old": 0.01, "new": 0.01, "old_uncertainty": 0.001,
         "new_uncertainty": 0.001, "change": 0.0, "exceeds_uncertainty": False, "status": "unchanged"}]}
    return {"meta": {"backend": "llvm_ad_rgb"}, "experiments": {"cmp": e.to_json()}, "changes": changes}


def test_layout_at_1280_and_the_comparison_widget(tmp_path):
    results = _layout_results(tmp_path)
    write_report(tmp_path, results)
    index = (tmp_path / "index.html").read_text(encoding="utf-8")
    assert "Changes since old/results.json" in index and "regressed" in index and "cmp.t0.err.env_a" not in index
    out = _run_harness(tmp_path, LAYOUT_HARNESS % json.dumps(["index.html", "exp-cmp.html"]), "1280,800")
    by_page = {p["page"]: p for p in out["pages"]}
    for p in by_page.values():
        assert p["width"][0] <= p["width"][1], f"{p['page']} scrolls sideways: {p['width']}"
        for cls, scroll, client, overflow in p["tables"]:
            # a table fits its box, or its box scrolls by design; the claims table (power column) must fit
            assert scroll <= client or (overflow in ("auto", "scroll") and "claims" not in cls), (p["page"], cls,
                                                                                                   scroll, client)
        assert any("claims" in t[0] for t in p["tables"])
    exp = by_page["exp-cmp.html"]
    top, bottom, natural = exp["summary"]
    assert natural > 0 and 0 <= top and bottom <= 800, exp["summary"]  # the summary figure, above the fold
    cmp = exp["compare"]
    assert cmp["start"] == ["cmp-truth", "cmp-technique"]  # wipe at 50 %: truth left, technique right
    assert cmp["technique"] == ["cmp-technique", "cmp-technique"]
    assert cmp["truth"] == ["cmp-truth", "cmp-truth"]
    assert cmp["wipe80"] == ["cmp-truth", "cmp-technique"] and cmp["state"] == "wipe"


# Every experiment page at 1280 × 800: the summary (a figure, or the renders page's acceptance grid) inside the
# first screen; a figure's smallest text (its data-font-px, the size summary_plots draws every text at, times the
# rendered / natural width) at least the body's font size; every grid cell a link to an element holding an image
# that decoded.
SUMMARY_HARNESS = FRAME_HARNESS + """async function measure(p) {
  const f = await loadFrame(p), d = f.contentDocument, w = f.contentWindow;
  for (const im of Array.from(d.images)) { im.loading = 'eager'; await settle(im); }
  const res = {page: p, body: parseFloat(w.getComputedStyle(d.body).fontSize), height: w.innerHeight};
  const el = d.querySelector('.at-a-glance .summary-grid, .at-a-glance .summary img');
  if (el) {
    const r = el.getBoundingClientRect();
    res.summary = {tag: el.tagName, top: r.top, bottom: r.bottom, width: r.width, natural: el.naturalWidth || 0,
                   font: parseFloat(el.dataset.fontPx || '0')};
  }
  res.cells = Array.from(d.querySelectorAll('.summary-grid a.accept-cell')).map(a => {
    const t = d.getElementById(a.getAttribute('href').slice(1)), im = t && t.querySelector('img');
    return [a.getAttribute('href'), !!im && im.complete && im.naturalWidth > 0, im ? im.getAttribute('src') : null];
  });
  f.remove();
  return res;
}
async function main() { const out = []; for (const p of pages) out.push(await measure(p));
  document.getElementById('out').textContent = JSON.stringify({pages: out}); }
main().catch(e => { document.getElementById('out').textContent = 'error: ' + e; });
</script></body></html>"""


def _summary_results(out: Path) -> dict:
    """The four pages with summaries of their own (sh9, worstcase, listings, renders, as test_report_summary
    builds them) and a plug-in page (the generic matrix), with the renders strips as PNGs."""
    import sys

    sys.path.insert(0, str(Path(__file__).parent))
    from test_report_summary import PAGE_ENTRIES

    entries = {name: make() for name, make in PAGE_ENTRIES.items()}
    for f in entries["renders"]["report"]["sections"][0]["figures"]:
        plots.save_image(out / f["path"], np.full((16, 48, 3), 0.5))
    entries["plugin"] = {"techniques": {f"t{i}": {"metrics": {"err.a": {"value": 0.01 * (i + 1), "uncertainty": 0.0},
                                                              "err.b": {"value": 0.02, "uncertainty": 0.0}}}
                                        for i in range(4)}}
    for name, e in entries.items():
        e.update(title=f"The {name} experiment", claims=[Claim(f"{name}.c", "a claim", "m", 0.01, 0.002, 0.0)
                                                         .with_power("× 10", 0.02).to_json()])
    return {"meta": {"backend": "llvm_ad_rgb"}, "experiments": entries}


def test_summary_figures_are_above_the_fold_and_readable(tmp_path):
    results = _summary_results(tmp_path)
    write_report(tmp_path, results)
    pages = [f"exp-{n}.html" for n in results["experiments"]]
    out = _run_harness(tmp_path, SUMMARY_HARNESS % json.dumps(pages), "1280,800")
    by_page = {p["page"]: p for p in out["pages"]}
    assert set(by_page) == set(pages)
    for p in by_page.values():
        s = p.get("summary")
        assert s is not None, f"{p['page']}: no summary figure"
        assert 0 <= s["top"] and s["bottom"] <= p["height"] == 800, (p["page"], s)  # inside the first screen
        if s["tag"] == "IMG":
            assert s["natural"] > 0 and s["font"] > 0, (p["page"], s)
            shown = s["font"] * s["width"] / s["natural"]  # the figure's smallest text, as drawn on the screen
            assert shown >= p["body"] - 0.01, (p["page"], shown, p["body"])
    cells = by_page["exp-renders.html"]["cells"]
    assert by_page["exp-renders.html"]["summary"]["tag"] == "DIV"
    assert len(cells) == 4, cells  # every cell of the 2 scenes × 2 engines (a skipped one too) opens the strip
    for href, decoded, src in cells:
        assert decoded and (tmp_path / src).is_file(), (href, src)
