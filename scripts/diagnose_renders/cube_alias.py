"""Diagnosis B, stage 1 in numpy: Babylon 9.35's PanoramaToCubeMapTools.CreateCubemapTexture (corner-aligned
lattice of samples per face, nearest texel by Math.round) replicated on the served panorama, its luminous energy
∫lum dω against the panorama's; sweep the panorama's roll (whole columns) to move the sun against the lattice.
Usage: python -m scripts.diagnose_renders.cube_alias [sizes]   (~85 s wall, numpy only)
"""
import sys

import numpy as np

from scripts.diagnose_renders.cdf import probe
from scripts.diagnose_renders.cdf_textures import LUM, cube_solid_angles
from validate.scenes import render_cdf_scenes as rcs
from validate.scenes.render_scenes import engine_texels

FACES = {  # PanoramaToCubeMapTools.FACE_* corners
    "left": [(-1, -1, -1), (1, -1, -1), (-1, 1, -1), (1, 1, -1)], "right": [(1, -1, 1), (-1, -1, 1), (1, 1, 1), (-1, 1, 1)],
    "front": [(1, -1, -1), (1, -1, 1), (1, 1, -1), (1, 1, 1)], "back": [(-1, -1, 1), (-1, -1, -1), (-1, 1, 1), (-1, 1, -1)],
    "down": [(1, 1, -1), (1, 1, 1), (-1, 1, -1), (-1, 1, 1)], "up": [(-1, -1, -1), (-1, -1, 1), (1, -1, -1), (1, -1, 1)]}

def cube_energy(pan_lum, size, samples, centred=False):
    h, w = pan_lum.shape
    o = 0.5 if centred else 0.0
    f = (np.arange(size * samples) + o) / (size * samples)  # sub-sample positions along x and y
    fx, fy = np.meshgrid(f, f)
    omega = np.repeat(np.repeat(cube_solid_angles(size), samples, 0), samples, 1) / samples**2
    tot = 0.0
    for c in FACES.values():
        c0, c1, c2, c3 = (np.asarray(v, float) for v in c)
        v1 = c0 + (c1 - c0) * fx[..., None]
        v2 = c2 + (c3 - c2) * fx[..., None]
        v = v1 + (v2 - v1) * fy[..., None]
        v /= np.linalg.norm(v, axis=-1, keepdims=True)
        theta = np.arctan2(v[..., 2], v[..., 0])
        phi = np.arccos(np.clip(v[..., 1], -1, 1))
        px = np.clip(np.round((theta / np.pi * 0.5 + 0.5) * w), 0, w - 1).astype(int)  # JS Math.round: half up
        py = np.clip(np.round(phi / np.pi * h), 0, h - 1).astype(int)
        tot += float((pan_lum[h - py - 1, px] * omega).sum())
    return tot

if __name__ == "__main__":
    t = probe()
    tex = rcs.rolled_probe(t)
    served = np.roll(engine_texels(tex), tex.shape[1] // 4, axis=1)  # the RGBE file Babylon loads
    lum = served @ LUM
    h, w = lum.shape
    om = (2 * np.pi / w) * (np.pi / h) * np.sin((np.arange(h) + 0.5) / h * np.pi)[:, None]
    e_pan = float((lum * om).sum())
    sizes = [int(a) for a in sys.argv[1:]] or [64, 128, 256]
    for n in sizes:
        s = max(1, round(w / 4 / n))
        print(f"size {n} samples {s}²: cube/panorama energy {cube_energy(lum, n, s) / e_pan:.4f}", flush=True)
    print("roll sweep (shipped lattice, size 64 × 4²; size 256 × 1):")
    for k in range(-3, 5):
        l2 = np.roll(lum, k, axis=1)
        print(f"  roll {k:+d} col ({k * 360 / w:+.2f}°): 64: {cube_energy(l2, 64, 4) / e_pan:.4f}  256: "
              f"{cube_energy(l2, 256, 1) / e_pan:.4f}  64 dense (32²): {cube_energy(l2, 64, 32) / e_pan:.4f}", flush=True)
