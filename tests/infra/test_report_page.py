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
from validate.report import plots
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
    harness = tmp_path / "_harness.html"
    harness.write_text(HARNESS % json.dumps(pages), encoding="utf-8")
    cmd = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--allow-file-access-from-files",
           "--virtual-time-budget=20000", "--dump-dom", harness.as_uri()]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    text = proc.stdout
    start, end = text.find('<pre id="out">') + len('<pre id="out">'), text.find("</pre>")
    payload = text[start:end].replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", '"')
    assert payload.startswith("{"), f"harness did not finish: {payload[:300]!r} / {proc.stderr[-500:]}"
    out = json.loads(payload)
    assert len(out["images"]) >= 2 and all(ok for _, _, ok in out["images"]), out["images"]
    broken = [link for link in out["links"] if not link[2]]
    assert not broken, broken
    hrefs = {h for _, h, _ in out["links"]}
    assert {"exp-demo.html", "exp-other.html", "index.html"} <= hrefs  # navigation in both directions
    assert any(h.startswith("#") for h in hrefs)  # tables of contents
