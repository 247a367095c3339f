"""Diagnosis B: Babylon's own textures for the CDF scene's probe, read back in the page, against numpy on the panorama.

Per cube size: the luminous energy ∫lum dω (lum = Rec. 709 luminance, Babylon's LuminanceEncodeApprox) of the cube
HDRCubeTexture built (6 faces read back, texel solid angles exact for a cube face), of the CDF's equirect grid (its
scaled-luminance texture sin θ·lum, 4N × 2N, read back; its 1×1 mip, the pdf's normalisation, read back too), both
over the panorama's. Usage: python -m scripts.diagnose_renders.cdf_textures '{"sizes": [64, 256], "lattice": 2048}'
("lattice": as cdf_patch.py).
"""

import numpy as np

from scripts.diagnose_renders.cdf import config_scene
from validate.gl import browser_page
from validate.scenes.render_scenes import engine_environment

JS = r"""
async ({url, size, ss, cap}) => {
  const B = await import('/node_modules/@babylonjs/core/index.js');
  const G = await import('/node_modules/@babylonjs/core/Rendering/iblCdfGenerator.js');
  const {f32ToB64} = await import('/validate/local_models/render/common.mjs');
  const canvas = document.createElement('canvas'); canvas.width = 8; canvas.height = 8;
  const eng = new B.Engine(canvas, false, {preserveDrawingBuffer: true});
  const scene = new B.Scene(eng);
  const tex = new B.HDRCubeTexture(url + '?diag=' + size + ss, scene, size, false, false, false, false, null, null, false, true, true);
  if (!ss) tex._supersample = false;
  await new Promise((res) => { const c = () => (tex.isReady() && tex.irradianceTexture) ? res() : setTimeout(c, 20); c(); });
  const out = {cube: [], irr: [], irrSize: tex.irradianceTexture.getSize().width};
  for (let f = 0; f < 6; f++) out.cube.push(f32ToB64(await tex.readPixels(f, 0)));
  for (let f = 0; f < 6; f++) { const p = await tex.irradianceTexture.readPixels(f, 0); out.irrType = p.constructor.name;
    out.irr.push(f32ToB64(p instanceof Float32Array ? p : new Float32Array(p))); }
  const g = new G.IblCdfGenerator(scene);
  g.iblSource = tex;
  await g.renderWhenReady();
  const sl = g._scaledLuminancePT, icdf = g._icdfPT;
  const s = sl.getSize(); out.W = s.width; out.H = s.height;
  out.sl = f32ToB64(await sl.readPixels(0, 0));
  const top = Math.floor(Math.log2(s.width));
  out.slTop = Array.from(await sl.readPixels(0, top));
  const ic = await icdf.readPixels(0, 0); out.icdfType = ic.constructor.name;
  out.icdf = f32ToB64(ic instanceof Float32Array ? ic : new Float32Array(ic));
  out.cdfx = f32ToB64(await g._cdfxPT.readPixels(0, 0));
  return out;
}
"""

LUM = np.array([0.2126, 0.7152, 0.0722])

def cube_solid_angles(n):
    a = (np.arange(n) + 0.5) / n * 2 - 1
    x, y = np.meshgrid(a, a)
    return (2.0 / n) ** 2 / (1 + x * x + y * y) ** 1.5

if __name__ == "__main__":
    cfg, scene = config_scene()
    env = engine_environment(scene.environment)
    tex = scene.environment.texels
    h, w = tex.shape[:2]
    th = (np.arange(h) + 0.5) / h * np.pi
    om = (2 * np.pi / w) * (np.pi / h) * np.sin(th)[:, None]  # texel solid angle (midpoint)
    lum_pan = tex @ LUM
    E_pan = float((lum_pan * om).sum())
    print("panorama ∫lum dω =", E_pan, " max lum", lum_pan.max())
    page = browser_page.open_page("babylon.html")
    if cfg.get("lattice"):
        from scripts.diagnose_renders.cdf_patch import PATCH
        page.evaluate(PATCH, {"quality": 0, "lattice": cfg["lattice"], "centred": cfg.get("centred", False)})
    for size in cfg.get("sizes", [64, 128, 256]):
        for ss in cfg.get("ss", [True]):
            r = page.evaluate(JS, {"url": env["url"], "size": size, "ss": ss})
            cube = np.stack([browser_page.decode_f32(c, (size, size, 4)) for c in r["cube"]])
            E_cube = float(((cube[..., :3] @ LUM) * cube_solid_angles(size)[None]).sum())
            W, H = r["W"], r["H"]
            sl = browser_page.decode_f32(r["sl"], (H, W, 4))[..., 0].astype(np.float64)
            icdf = browser_page.decode_f32(r["icdf"], (H, W, 4)).astype(np.float64)
            mean_np = sl.mean()
            E_cdf = mean_np * 2 * np.pi**2
            v = (np.arange(H) + 0.5) / H
            deform = np.sin(np.pi * v)[:, None]
            lum = sl / deform
            pdf = icdf[..., 2]
            big = lum > 0.5 * lum.max()
            norm_from_pdf = np.median(lum[big] / (2 * np.pi * pdf[big]))
            irr = np.stack([browser_page.decode_f32(c, (r["irrSize"], r["irrSize"], 4)) for c in r["irr"]])
            print(f"size {size} ss={ss}: cube ∫lum dω = {E_cube:.5g} ({E_cube/E_pan:.4f} of panorama); CDF grid {W}x{H}: "
                  f"∫lum dω from scaledLuminance = {E_cdf:.5g} ({E_cdf/E_pan:.4f}); top mip {r['slTop'][0]:.6g} vs numpy mean "
                  f"{mean_np:.6g}; norm from pdf {norm_from_pdf:.6g}; max lum cube {float((cube[...,:3]@LUM).max()):.4g}; "
                  f"irr max {float((irr[...,:3]@LUM).max()):.5g} ({r['irrType']}, icdf {r['icdfType']})", flush=True)
            np.savez(f"/tmp/cdf_{size}_{int(ss)}.npz", cube=cube, sl=sl, icdf=icdf, irr=irr)
