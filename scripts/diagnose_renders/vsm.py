"""Diagnosis A (docs/experiments/renders.md, "three.js VSM columns"): three.js's VSM shadow on the fully lit plane.

Renders the shadow scenes (validate.scenes.render_shadow_scenes) through three.html with variants of the scene's
shadow JSON and of three_shadows.mjs's diagnostic `sh.diag` overrides, and prints per scene the least shadow factor
s = radiance/(ρE/π) over the fully lit region, the pixels with s < 0.995 and their columns. Usage, from the root:

    python -m scripts.diagnose_renders.vsm 64 '[{}, {"floatMoments": 1}, {"excludeReceiver": 1}, {"bias": -2e-4},
        {"shadow": {"map_size": 1024}}, {"blurSamples": 1}, {"type": "pcf"}]'

A variant is {"type": shadow type (default vsm), "shadow": {scene JSON overrides}, **diag}; "dump": 1 saves the
shadow map's moments to /tmp/moments_<scene>_<variant index>.npy.
"""
import json
import sys

import numpy as np

from validate.gl import browser_page
from validate.scenes import render_shadow_scenes as rss

LAST = {}

def run(scene, v):
    v = dict(v)
    d = scene.with_shadow_type(v.pop("type", "vsm")).engine_json()
    d["shadow"].update(v.pop("shadow", {}))
    d["shadow"]["diag"] = v
    d["options"] = {}
    r = browser_page.call("three.html", "renderThree", d)
    n = scene.resolution
    img = browser_page.decode_f32(r["data"], (n, n, 4))[::-1, :, :3].astype(float)
    m = r["info"].get("moments")
    if m:
        k = d["shadow"]["map_size"]
        LAST["moments"] = browser_page.decode_f32(m, (k, k, 4))
    return img.mean(-1) / rss.unshadowed_radiance(scene)

def summary(s, lit):
    bad = lit & (s < 0.995)
    cols = sorted(set(np.nonzero(bad)[1].tolist()))
    return f"min_s_lit={s[lit].min():.4f} bad_px={int(bad.sum())}/{int(lit.sum())} cols={cols}"

if __name__ == "__main__":
    res = int(sys.argv[1])
    variants = json.loads(sys.argv[2])
    which = sys.argv[3] if len(sys.argv) > 3 else "both"
    for scene in rss.shadow_scenes(res):
        if which != "both" and which not in scene.name:
            continue
        lit = rss.regions(scene)["lit"]
        for v in variants:
            s = run(scene, v)
            print(scene.name, json.dumps(v), summary(s, lit), flush=True)
            if "moments" in LAST:
                M = LAST.pop("moments")
                np.save(f"/tmp/moments_{scene.name}_{variants.index(v)}.npy", M)
                mu, sd = M[..., 0], M[..., 1]
                print("  moments: mean<1 texels", int((mu < 1).sum()), "sd>0", int((sd > 0).sum()),
                      "min mean", float(mu.min()))
