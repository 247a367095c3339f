"""Diagnosis B (docs/experiments/renders.md, "Babylon PR 16247"): the energy ratio r = Σ Babylon/Σ Mitsuba of the CDF
scene (validate.scenes.render_cdf_scenes, 32², Mitsuba 1024 spp × 8 passes as FULL, cached) for probe variants:

    python -m scripts.diagnose_renders.cdf '{"sizes": [64, 128, 256], "scale": 0.0625}'   # the probe / 16
    python -m scripts.diagnose_renders.cdf '{"cap": 4000}'                                # every texel ≤ 4000

"scale" renders Babylon on k × the probe and divides by k (Mitsuba is linear in the probe: its reference is the
unscaled one); "variant" is shipped | pre16247.
"""
import json
import sys
import time

import numpy as np

from validate.experiments.renders.cdf.compute import energy_ratio
from validate.gl import browser_page
from validate.local_models import render as engines
from validate.metrics.pixel_z import interior_mask
from validate.reference.render_reference import render_reference
from validate.scenes import render_cdf_scenes as rcs
from validate.scenes.loaders import load_environment
from validate.scenes.probes import default_probes_dir

PROBES = default_probes_dir()  # ../shared/probes beside the checkout, or $VALIDATE_PROBES

def probe(name=rcs.CDF_PROBE_FILE):
    return np.asarray(load_environment(PROBES / name, "latlong", False).radiance, np.float64)

def config_scene():
    """(cfg, scene) from the JSON config in argv[1]: the probe ('probe'), optionally capped at 'cap', on the 32² sphere."""
    cfg = json.loads(sys.argv[1])
    t = probe(cfg.get("probe", rcs.CDF_PROBE_FILE))
    if "cap" in cfg:
        t = np.minimum(t, cfg["cap"])
    return cfg, rcs.cdf_lambert_scene(t, 32)

def render(scene, size, variant="shipped", extra=None):
    e = engines.registry.get(rcs.engine_name(size, variant))
    page, fn, options = e.page, e.entry, e.options
    if extra is not None:
        browser_page.open_page(page).evaluate("(x) => { window.__cdfDiag = x; }", extra)
    d = dict(scene.engine_json(), options=options)
    r = browser_page.call(page, fn, d)
    n = scene.resolution
    img = browser_page.decode_f32(r["data"], (n, n, 4))[::-1].copy()
    return img, r.get("info", {})

if __name__ == "__main__":
    cfg = json.loads(sys.argv[1])  # {"probe":..., "scale":k, "cap":c, "sizes":[...], "variant":..., "extra":{...}}
    t = probe(cfg.get("probe", rcs.CDF_PROBE_FILE))
    if "cap" in cfg:
        t = np.minimum(t, cfg["cap"])
    base = rcs.cdf_lambert_scene(t, 32)
    ref = render_reference(base, 1024, 8, 0)
    k = cfg.get("scale", 1.0)
    scene = base if k == 1.0 else rcs.cdf_lambert_scene(t * k, 32)
    for n in cfg.get("sizes", [64, 128, 256]):
        t0 = time.perf_counter()
        img, info = render(scene, n, cfg.get("variant", "shipped"), cfg.get("extra"))
        mask = interior_mask(ref.hit, img[..., 3])
        r, u = energy_ratio(img[..., :3].astype(np.float64) / k, ref.mean, ref.stderr, mask)
        print(json.dumps(cfg), n, f"ratio={r:.4f}±{u:.4f}", f"{time.perf_counter()-t0:.0f}s", flush=True)
