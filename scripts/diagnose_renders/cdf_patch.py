"""Diagnosis B: the sphere's energy ratio with Babylon patched in the page (diagnosis only, never in a run):
quality = importance samples of HDRIrradianceFiltering; lattice = panorama-to-cube samples per cube-face edge
(PanoramaToCubeMapTools.CreateCubemapTexture with samples = lattice/size per texel axis; "centred" puts the
sub-samples at sub-texel centres instead of Babylon's corners). Usage:

    python -m scripts.diagnose_renders.cdf_patch '{"sizes": [64, 256], "quality": 16384}'   # 4× Babylon's samples
    python -m scripts.diagnose_renders.cdf_patch '{"lattice": 2048}'   # 8 samples per panorama texel width
"""
import json

import numpy as np

from scripts.diagnose_renders.cdf import config_scene, render
from validate.experiments.renders.cdf.compute import energy_ratio
from validate.gl import browser_page
from validate.metrics.pixel_z import interior_mask
from validate.reference.render_reference import render_reference

PATCH = r"""
async ({quality, lattice, centred}) => {
  if (quality) {
    const F = await import('/node_modules/@babylonjs/core/Materials/Textures/Filtering/hdrIrradianceFiltering.js');
    const proto = F.HDRIrradianceFiltering.prototype, orig = proto._createEffect;
    proto._createEffect = function (t, c) { this.quality = quality; return orig.call(this, t, c); };
  }
  if (lattice) {
    const P = await import('/node_modules/@babylonjs/core/Misc/HighDynamicRange/panoramaToCubemap.js');
    const T = P.PanoramaToCubeMapTools;
    T.CreateCubemapTexture = function (texSize, faceData, data, W, H, supersample, invertY, stride) {
      const a = new Float32Array(texSize * texSize * 3), s = Math.max(1, Math.round(lattice / texSize)), w = 1 / (s * s);
      const o = centred ? 0.5 : 0.0;
      const [c0, c1, c2, c3] = faceData;
      for (let y = 0; y < texSize; y++) for (let sy = 0; sy < s; sy++) {
        const fy = (y + (sy + o) / s) / texSize;
        for (let x = 0; x < texSize; x++) for (let sx = 0; sx < s; sx++) {
          const fx = (x + (sx + o) / s) / texSize;
          const v1 = c1.subtract(c0).scale(fx).add(c0), v2 = c3.subtract(c2).scale(fx).add(c2);
          const v = v2.subtract(v1).scale(fy).add(v1); v.normalize();
          const c = T.CalcProjectionSpherical(v, data, W, H, stride, invertY);
          const i = 3 * (y * texSize + x); a[i] += c.r * w; a[i + 1] += c.g * w; a[i + 2] += c.b * w;
        }
      }
      return a;
    };
  }
  return true;
}
"""

if __name__ == "__main__":
    cfg, scene = config_scene()
    ref = render_reference(scene, 1024, 8, 0)
    page = browser_page.open_page("babylon.html")
    page.evaluate(PATCH, {"quality": cfg.get("quality", 0), "lattice": cfg.get("lattice", 0),
                          "centred": cfg.get("centred", False)})
    for n in cfg.get("sizes", [64, 128, 256]):
        img, info = render(scene, n, cfg.get("variant", "shipped"))
        mask = interior_mask(ref.hit, img[..., 3])
        r, u = energy_ratio(img[..., :3].astype(np.float64), ref.mean, ref.stderr, mask)
        print(json.dumps(cfg), n, f"ratio={r:.4f}±{u:.4f}", flush=True)
