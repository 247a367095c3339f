"""The world-lit sphere's Cycles offset, taken apart (docs/experiments/blender.md, "Cycles' offset under a probe").

Slow (Blender renders, 1–3 min each): ``pytest -m slow tests/experiments/test_blender_world_offset.py``.

* The suite's hand-over to Blender (the camera, the frame, the UV sphere, the equirectangular texture's mapping):
  under a world linear in the direction, L = 1 + a·ω, a Lambertian sphere reads exactly 1 + (2/3) a·n, so Cycles'
  image gives back each pixel's normal; it must be the suite's to 10⁻³ (a 0.5° turn of the camera fails).
* Small bright caps in the texture: a cap wholly above a pixel's horizon gives it exactly n̄·V/π (V = ∫ L ω dω of the
  texture's bilinear radiance), so its direction and its energy are read back from the lit pixels.
* grace_probe: Cycles and Mitsuba each over the footprint-averaged quadrature of Mitsuba's radiance.
"""

from __future__ import annotations

import importlib
import math
from pathlib import Path

import numpy as np
import pytest

from validate.local_models.render import blender as bl

VERSION, WHY = bl.available()
pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(VERSION is None, reason=f"Blender not installed ({WHY}): {bl.FIX}")]
wd = importlib.import_module("validate.experiments.blender.world")
R, VIEW = 64, (15.0, 0.0)


def _env(name: str = "flat"):
    from validate.scenes.environment import Environment

    return Environment(name, np.ones((16, 32, 3), np.float32))


def _cycles(tmp: Path, tex: np.ndarray, frames: int, spp: int, env=None) -> np.ndarray:
    """(F, R, R, 3) Cycles frames of the experiment's world-lit Lambertian sphere under the texture ``tex``."""
    from validate.local_models.render.blender_cycles import ENGINE

    exr = tmp / "world.exr"
    wd.write_exr(exr, tex.astype(np.float32))
    job = wd.job(wd.WorldScene(env or _env(), VIEW), exr, ENGINE, R, spp, tuple(range(frames)), tmp / "f")
    return bl.render_batch([job], tmp).results[0].frames[..., :3].astype(np.float64)


def _footprint_normals() -> tuple[np.ndarray, np.ndarray]:
    """(N, k², 3) Blender-frame normals at the footprint nodes of the masked pixels, and the (N, 3) footprint means."""
    from validate.backend import init
    from validate.reference import pathtrace

    init()
    mask = pathtrace.footprint_mask(R)
    z = np.zeros((R, R, 3))
    n, w = wd.footprint_normals(pathtrace.SphereRender(z, z, None, mask, 1, 4, 0, {}, VIEW))
    nb = wd.to_blender(n.reshape(-1, 3)).reshape(n.shape)
    return nb, (nb * w[None, :, None]).sum(axis=1)


def _mask() -> np.ndarray:
    from validate.reference import pathtrace

    return pathtrace.footprint_mask(R)


def test_a_linear_world_gives_back_the_suites_normals(tmp_path) -> None:
    a = 0.9
    tex = 1.0 + a * wd.blender_texel_directions(512, 1024)  # R, G, B: Blender x, y, z
    frames = _cycles(tmp_path, tex, 8, 64)
    _, nbar = _footprint_normals()
    img = frames.mean(axis=0)[_mask()]
    ncyc = (img - 1.0) / (2.0 / 3.0 * a)

    def fit(n: np.ndarray) -> np.ndarray:
        m, *_ = np.linalg.lstsq(np.c_[n, np.ones(len(n))], ncyc, rcond=None)
        return m

    expect = np.r_[np.eye(3), np.zeros((1, 3))]
    assert np.abs(fit(nbar) - expect).max() < 2e-3, fit(nbar)  # measured ≤ 6.7·10⁻⁴ (noise)
    assert np.abs(img.mean(axis=0) / (1.0 + 2.0 / 3.0 * a * nbar).mean(axis=0) - 1).max() < 1e-3
    t = math.radians(0.5)  # power: the camera turned 0.5° about Blender's z
    turned = nbar @ np.array([[math.cos(t), -math.sin(t), 0], [math.sin(t), math.cos(t), 0], [0, 0, 1]]).T
    assert np.abs(fit(turned) - expect).max() > 2e-3


CAPS = ((-0.7155, -0.0429, 0.6973), (-0.9659, 0.0, 0.2588), (0.3008, -0.2005, 0.9324))  # window, camera, high
CAP_RADIUS = math.radians(4.0)


def cap_vectors(tex: np.ndarray, sub: int = 8) -> np.ndarray:
    """(3, 3) V_c = ∫ L_c ω dω of the texture's bilinear radiance (Cycles' 'Linear', texel centres (i + ½)/W),
    by a midpoint rule ``sub`` × finer than the texels (exact for the bilinear pieces up to the sin θ weight)."""
    h, w = tex.shape[:2]
    fh, fw = sub * h, sub * w
    v = (np.arange(fh) + 0.5) / fh
    u = (np.arange(fw) + 0.5) / fw
    y, x = v * h - 0.5, u * w - 0.5
    y0 = np.floor(y).astype(int)
    x0 = np.floor(x).astype(int)
    fy, fx = (y - y0)[:, None, None], (x - x0)[None, :, None]
    ya, yb = np.clip(y0, 0, h - 1), np.clip(y0 + 1, 0, h - 1)
    xa, xb = x0 % w, (x0 + 1) % w
    out = np.zeros((3, 3))
    d = wd.blender_texel_directions(fh, fw)
    dw = (math.pi / fh) * (2 * math.pi / fw) * np.sin(v * math.pi)
    for r0 in range(0, fh, 256):
        s = slice(r0, r0 + 256)
        t = tex[ya[s]], tex[yb[s]]
        lin = ((1 - fy[s]) * ((1 - fx) * t[0][:, xa] + fx * t[0][:, xb])
               + fy[s] * ((1 - fx) * t[1][:, xa] + fx * t[1][:, xb]))
        out += np.einsum("ijc,ijk,i->ck", lin, d[s], dw[s])
    return out


def test_small_caps_keep_their_direction_and_energy(tmp_path) -> None:
    h, w = 1024, 2048
    d = wd.blender_texel_directions(h, w)
    s = np.array(CAPS) / np.linalg.norm(CAPS, axis=1, keepdims=True)
    tex = np.stack([np.where(d @ s[c] > math.cos(CAP_RADIUS), 100.0, 0.0) for c in range(3)], axis=-1)
    v = cap_vectors(tex)
    assert np.allclose(np.linalg.norm(v, axis=1), 100 * math.pi * math.sin(CAP_RADIUS) ** 2, rtol=0.01)
    frames = _cycles(tmp_path, tex, 16, 64)
    nb, nbar = _footprint_normals()
    mask = _mask()
    for c in range(3):
        lit = (nb @ s[c]).min(axis=1) > math.sin(CAP_RADIUS) + 0.01
        fit, *_ = np.linalg.lstsq(nbar[lit], math.pi * frames.mean(axis=0)[mask][lit, c], rcond=None)
        angle = math.degrees(math.acos(fit @ v[c] / np.linalg.norm(fit) / np.linalg.norm(v[c])))
        gain = np.array([f[mask][lit, c].mean() for f in frames]) / (nbar[lit] @ v[c] / math.pi).mean()
        assert angle < 0.05, (c, angle)  # measured ≤ 0.021°; half a texel is 0.088°
        # measured 0.99914 ± 0.00012, 0.99931 ± 0.00014, 1.00071 ± 0.00018 (Blender 5.0.1): Cycles' finding
        assert abs(gain.mean() - 1) < 3e-3, (c, gain.mean())


def test_grace_each_renderer_over_the_quadrature(tmp_path) -> None:
    import mitsuba as mi

    from validate.reference import pathtrace
    from validate.scenes.probes import load_probes

    envs, _ = load_probes(Path(__file__).resolve().parents[3] / "shared" / "probes", [], "auto", False,
                          only_stems={"grace_probe"})
    if not envs:
        pytest.skip("shared probe grace_probe not found")
    env = envs[0]
    mask = _mask()
    render = pathtrace.SphereRender(np.zeros((R, R, 3)), np.zeros((R, R, 3)), None, mask, 1, 4, 0, {}, VIEW)
    q, _ = pathtrace.quadrature_sphere(env, render)
    qm = q[mask].mean()
    tex, _ = wd.texture(env)
    cyc = np.array([f[mask].mean() for f in _cycles(tmp_path, tex, 16, 64, env)]) / qm
    scene = pathtrace.sphere_scene(env, R, 1024, VIEW)
    mit = np.array([np.asarray(mi.render(scene, seed=7000 + i, spp=1024), np.float64)[mask].mean()
                    for i in range(8)]) / qm
    um = mit.std(ddof=1) / math.sqrt(len(mit))
    assert abs(mit.mean() - 1) < 4 * um + 1e-4, (mit.mean(), um)  # measured 1.00014 ± 0.00009 (64 × 1024 spp)
    assert abs(cyc.mean() - 1) < 3e-3, cyc.mean()  # measured 0.99943 ± 0.00021 (64 × 64 spp): Cycles' finding
