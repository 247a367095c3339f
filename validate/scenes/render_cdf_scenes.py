"""(b) Babylon.js's CDF irradiance scene: the Lambertian sphere under a sunny 1k probe (Babylon PR 16247).

Babylon.js can build its diffuse irradiance by importance sampling CDF maps of the environment cube
(``HDRCubeTexture(..., prefilterIrradianceOnLoad = true, prefilterUsingCdf = true)``, Babylon PRs 15878, 16010).
PR 16247 ("Make prefiltering using CDF default to supersample", 2025-03-04) reports that with a cube size below 256
"the resulting irradiance brightness varies considerably (and usually gets darker) with different resolutions": the
panorama-to-cube conversion samples one panorama point per cube texel and loses bright spots; the PR forces the
conversion's supersampling (round(W/4/size)² points per texel, W the panorama width) when CDF filtering is on. For a
W = 1024 panorama the supersampling factor is 4² at size 64, 2² at 128 and 1 from 256 up — the "below 256" of the PR.

The scene: the Lambertian sphere (:data:`~validate.scenes.render_scenes.LAMBERT`) lit only by ``CDF_PROBE_FILE`` of
the probes folder at its full 1024 × 512 (no resampling: the engine's own conversion is what is measured), rolled in
azimuth (whole columns, exact) so that its sun — the brightest texel — sits at azimuth ``SUN_AZIMUTH_DEG`` (φ in
the probes' convention, d = (sin φ sin θ, cos θ, −cos φ sin θ); 180° faces the camera at +z) and lights the visible
hemisphere. Mitsuba gets the same texels (``envmap`` on :func:`~validate.scenes.render_scenes.mitsuba_envmap_nodes`);
Babylon gets them as the RGBE file of :func:`~validate.scenes.render_scenes.engine_environment` — exact, since the
probe is itself an RGBE file (every texel is m·2^(E−136) with integer mantissas, which re-encode unchanged).

What the scene measures under this sun (diagnosed; docs/experiments/renders.md, "Babylon PR 16247"): the sun is 6
texels (2 rows × 3 columns, 0.70° × 1.05°) holding 63 % of the probe's luminous energy ∫lum dω, and Babylon's
panorama-to-cube conversion point-samples it on a fixed lattice (W/4 = 256 points per face edge at every size as
shipped), so the cube keeps 0.840 / 0.837 / 0.836 of that energy at 64 / 128 / 256 at this azimuth — an alias, not a
bias: the sun moved by whole panorama columns (0.35° each, −3 … +4) gives a cube 0.83–1.32 of it, and by −2 / +1
columns a sphere 1.10–1.38 × Mitsuba.
``SUN_AZIMUTH_DEG`` therefore fixes the sign of the engine's error as well as its size.
"""

from __future__ import annotations

import numpy as np

from .render_scenes import LAMBERT, Environment, RenderScene

CDF_PROBE_FILE = "rooitou_park_1k.hdr"  # Poly Haven, 1024 × 512; the sun ≈ 5.9e4 at 10° elevation, mean 0.50
SUN_AZIMUTH_DEG = 140.0  # 40° to the camera's right of +z: the terminator crosses the image
# Babylon's cube sizes around PR 16247's threshold (256); each × ("shipped", "pre16247") — babylon_cdf.mjs
CDF_SIZES = (64, 128, 256)
CDF_VARIANTS = ("shipped", "pre16247")
CDF_THRESHOLD_SIZE = 256  # PR 16247: "when the cube texture size is below 256"


def sun_column(texels: np.ndarray) -> int:
    """Column of the brightest texel (channel mean)."""
    lum = np.asarray(texels).mean(axis=-1)
    return int(np.unravel_index(int(np.argmax(lum)), lum.shape)[1])


def rolled_probe(texels: np.ndarray, azimuth_deg: float = SUN_AZIMUTH_DEG) -> np.ndarray:
    """The texels rolled by whole columns so the sun's column is the one at φ = ``azimuth_deg`` (φ = 2π(j + ½)/W)."""
    t = np.asarray(texels, np.float64)
    w = t.shape[1]
    target = int(round(azimuth_deg / 360.0 * w - 0.5))
    return np.roll(t, target - sun_column(t), axis=1)


def cdf_lambert_scene(texels: np.ndarray, resolution: int) -> RenderScene:
    """The Lambertian sphere under the rolled probe (module docstring)."""
    env = Environment("cdf_" + CDF_PROBE_FILE.split(".")[0], texels=rolled_probe(texels))
    return RenderScene("cdf_lambert", LAMBERT, environment=env, resolution=resolution)


def engine_name(size: int, variant: str) -> str:
    """The registered engine (a variant of ``babylon``: :mod:`validate.local_models.render.babylon`) for Babylon's CDF
    irradiance at ``size``."""
    return f"babylon_cdf{size}_{variant}"


__all__ = ["CDF_PROBE_FILE", "SUN_AZIMUTH_DEG", "CDF_SIZES", "CDF_VARIANTS", "CDF_THRESHOLD_SIZE", "sun_column",
           "rolled_probe", "cdf_lambert_scene", "engine_name"]
