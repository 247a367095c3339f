"""Diagnosis B: the sphere's energy ratio (shipped) with the sun moved by whole panorama columns (0.35° each) from
the scene's azimuth: the cube-lattice alias moves with it (numpy: cube_alias.py). Mitsuba references at 1024 spp × 8
passes (new scenes: ~25 s each on 2 cores). Usage: python -m scripts.diagnose_renders.cdf_roll '[-2, 1]'
"""
import json
import sys

import numpy as np

from scripts.diagnose_renders.cdf import probe, render
from validate.experiments.renders.cdf.compute import energy_ratio
from validate.metrics.pixel_z import interior_mask
from validate.reference.render_reference import render_reference
from validate.scenes import render_cdf_scenes as rcs
from validate.scenes.render_scenes import LAMBERT, Environment, RenderScene

if __name__ == "__main__":
    rolls = json.loads(sys.argv[1])
    t = rcs.rolled_probe(probe())
    for k in rolls:
        env = Environment(f"cdf_{rcs.CDF_PROBE_FILE.split('.')[0]}_roll{k}", texels=np.roll(t, k, axis=1))
        scene = RenderScene("cdf_lambert", LAMBERT, environment=env, resolution=32)
        ref = render_reference(scene, 1024, 8, 0)
        for n in (64, 128, 256):
            img, _ = render(scene, n)
            r, u = energy_ratio(img[..., :3].astype(np.float64), ref.mean, ref.stderr, interior_mask(ref.hit, img[..., 3]))
            print(f"roll {k:+d}", n, f"ratio={r:.4f}±{u:.4f}", flush=True)
