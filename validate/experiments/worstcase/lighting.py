"""The searched lighting family and the truth for it: lobes + a soft lat-long map, rasterised in drjit.

Family (one parameter vector θ, :class:`Family` says how it is laid out):

* K spherical Gaussians G_k(ω) = exp(λ_k (μ_k·ω − 1)) [1], μ_k = v_k/|v_k| (v_k ∈ ℝ³ free),
  λ_k = λ_min (λ_max/λ_min)^σ(s_k) (σ the logistic function), each with its own RGB flux
  f_kc = softplus(a_kc): on the H×W texels the lobe is rasterised as
  L_k,jc = f_kc G_k(ω_j) / Σ_j G_k(ω_j) ΔΩ_j, so its discrete flux is f_kc exactly and a lobe narrower than a
  texel collapses onto the nearest texel (a sun) instead of vanishing between texel centres;
* a low-resolution map softplus(m) of h×2h×3 texels, bilinearly upsampled to H×W (a sky);
* the sum, rescaled to the luminance flux Φ_Y = Φ₀ 10^(D σ(g)) (Φ₀ = 4π: mean radiance 1; ``decades`` D):
  the flux-normalised metrics are scale-free for a linear technique, but a clamp (Babylon's 4096) is not.

Every texel is non-negative by construction, the lighting is a plain (H, W, 3) map in Mitsuba's
lat-long convention (:mod:`validate.scenes.latlong`) and the truth is the suite's quadrature of it,

    E_c(n) = Σ_j L_jc max(0, n·ω_j) ΔΩ_j   (exact cell solid angles ΔΩ_j, Σ ΔΩ_j = 4π),

evaluated (and differentiated) in drjit, in the variant's float (float32 for ``llvm_ad_rgb``).
The same θ rasterised at 2H is the "2× resolution" check of the search's figure.

References
  [1] J. Wang, P. Ren, M. Gong, J. Snyder, B. Guo, "All-frequency rendering of dynamic, spatially-varying
      reflectance", SIGGRAPH Asia 2009 (spherical Gaussians exp(λ(μ·ω − 1))).
"""

from __future__ import annotations

import functools
import hashlib
import math
from collections import OrderedDict
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...scenes import latlong

FLUX_REFERENCE = 4.0 * math.pi  # Φ₀: a map of mean radiance 1
LUMINANCE = (0.2126, 0.7152, 0.0722)


@dataclass(frozen=True)
class Family:
    """Layout of θ: K lobes × (v 3, s 1, a 3), then h×2h×3 map logits, then one flux logit g."""

    lobes: int = 3
    map_height: int = 4
    sharpness_min: float = 1.0
    sharpness_max: float = 1e5
    decades: float = 3.0  # Φ_Y ∈ Φ₀ [1, 10^D]

    @property
    def size(self) -> int:
        return 7 * self.lobes + 6 * self.map_height ** 2 + 1

    def random(self, rng: np.random.Generator) -> np.ndarray:
        """A random start: lobe directions uniform on the sphere (normalised Gaussian v), sharpness logits
        U(−3, 0) (λ ∈ [1.8, 316] for the default range: broad to sun-sized lobes, none yet a single texel),
        lobe flux logits N(0, 1), map logits N(−1, 1), flux logit N(0, 1)."""
        th = np.empty(self.size)
        k = self.lobes
        v = rng.normal(size=(k, 3))
        lob = np.concatenate([v, rng.uniform(-3.0, 0.0, size=(k, 1)), rng.normal(size=(k, 3))], axis=1)
        th[:7 * k] = lob.reshape(-1)
        th[7 * k:-1] = rng.normal(size=6 * self.map_height ** 2) - 1.0
        th[-1] = rng.normal()
        return th


@functools.lru_cache(maxsize=8)
def texel_geometry(height: int) -> tuple[np.ndarray, np.ndarray]:
    """(directions (H·W, 3), solid angles (H·W,)) of an H×2H map, row-major, float64 (cached, read-only)."""
    w = 2 * height
    d, dw = latlong.texel_directions(height, w).reshape(-1, 3), latlong.texel_solid_angles(height, w).reshape(-1)
    d.flags.writeable = dw.flags.writeable = False
    return d, dw


def upsample_plan(coarse: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """Bilinear lookup of a coarse h×2h map (Mitsuba's convention: rows align corners, φ wraps) at every
    texel of an H×2H map: (indices (4, H·W) into the coarse map, weights (4, H·W))."""
    d = latlong.texel_directions(height, 2 * height).reshape(-1, 3)
    theta, phi = latlong.direction_to_spherical(d)
    taps = latlong.bilinear_taps(theta, phi, coarse, 2 * coarse)
    return np.stack([i for i, _ in taps]), np.stack([wt for _, wt in taps])


def softplus(dr: Any, x: Any) -> Any:
    """log(1 + eˣ), stable for large |x| (any drjit float)."""
    return dr.maximum(x, 0.0) + dr.log(1.0 + dr.exp(-dr.abs(x)))


def sigmoid(dr: Any, x: Any) -> Any:
    return 1.0 / (1.0 + dr.exp(-x))


class Raster:
    """Rasterises θ of a :class:`Family` onto an H×2H map in drjit (differentiable in θ)."""

    def __init__(self, fam: Family, height: int) -> None:
        import mitsuba as mi

        self.fam, self.height = fam, height
        d, dw = texel_geometry(height)
        self.dirs = [mi.Float(d[:, i].astype(np.float32)) for i in range(3)]
        self.dw = mi.Float(dw.astype(np.float32))
        idx, wts = upsample_plan(fam.map_height, height)
        self.up_idx = [mi.UInt32(i.astype(np.uint32)) for i in idx]
        self.up_w = [mi.Float(w.astype(np.float32)) for w in wts]

    def radiance(self, theta: Any) -> list[Any]:
        """θ (a drjit Float of size ``fam.size``) → [L_R, L_G, L_B], each a Float of H·W texels."""
        import drjit as dr
        import mitsuba as mi

        fam = self.fam
        g = [dr.gather(mi.Float, theta, i) for i in range(fam.size)]
        out = [self.dirs[0] * 0.0 for _ in range(3)]
        for k in range(fam.lobes):
            v = g[7 * k:7 * k + 3]
            norm = dr.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + 1e-20)
            cos = (v[0] * self.dirs[0] + v[1] * self.dirs[1] + v[2] * self.dirs[2]) / norm
            span = math.log(fam.sharpness_max / fam.sharpness_min)
            lam = fam.sharpness_min * dr.exp(span * sigmoid(dr, g[7 * k + 3]))
            lobe = dr.exp(lam * (cos - dr.max(dr.detach(cos))))  # the shift cancels in the normalisation
            lobe = lobe / dr.sum(lobe * self.dw)
            for c in range(3):
                out[c] = out[c] + softplus(dr, g[7 * k + 4 + c]) * lobe
        m0 = 7 * fam.lobes
        nm = 2 * fam.map_height ** 2
        for c in range(3):
            coarse = softplus(dr, dr.gather(mi.Float, theta, mi.UInt32(np.arange(m0 + c * nm, m0 + (c + 1) * nm,
                                                                                  dtype=np.uint32))))
            for i, w in zip(self.up_idx, self.up_w, strict=True):
                out[c] = out[c] + w * dr.gather(mi.Float, coarse, i)
        flux_y = dr.sum((LUMINANCE[0] * out[0] + LUMINANCE[1] * out[1] + LUMINANCE[2] * out[2]) * self.dw)
        target = FLUX_REFERENCE * dr.exp(math.log(10.0) * fam.decades * sigmoid(dr, g[-1]))
        return [L * (target / flux_y) for L in out]

    def numpy(self, theta: np.ndarray) -> np.ndarray:
        """The rasterised map as a float32 numpy array (H, 2H, 3) (no gradients)."""
        import drjit as dr
        import mitsuba as mi

        ch = self.radiance(mi.Float(np.asarray(theta, dtype=np.float32)))
        dr.eval(ch)  # the three channels in one go (converting each alone would rasterise the map three times)
        return np.stack([np.array(c) for c in ch], axis=-1).reshape(self.height, 2 * self.height, 3).astype(np.float32)


def truth_numpy(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """E_c(n) = Σ_j L_jc max(0, n·ω_j) ΔΩ_j (float64) for an (H, 2H, 3) map at normals (N, 3) → (N, 3).
    The sum runs over the lit texels only (a zero texel adds nothing): a certificate's delta maps cost their
    one to three texels, not H·2H."""
    h = radiance.shape[0]
    d, dw = texel_geometry(h)
    lw = radiance.reshape(-1, 3).astype(np.float64) * dw[:, None]
    normals = np.asarray(normals, dtype=np.float64)
    lit = np.flatnonzero(np.any(lw != 0.0, axis=1))
    if len(lit) < len(lw) // 2:
        return np.maximum(normals @ d[lit].T, 0.0) @ lw[lit]
    if len(normals) < 64 or len(normals) * len(dw) > KERNEL_CACHE_ENTRIES:  # not kept
        return np.maximum(normals @ d.T, 0.0) @ lw
    return cosine_kernel(normals, h) @ radiance.reshape(-1, 3).astype(np.float64)


_KERNELS: OrderedDict[tuple[bytes, int], np.ndarray] = OrderedDict()
KERNEL_CACHE = 2  # kernels kept (LRU): a search's normal set and worst_normal's dense one
KERNEL_CACHE_ENTRIES = 1 << 23  # at most 4096 normals × a 32×64 map each (64 MiB of float64)


def cosine_kernel(normals: np.ndarray, height: int) -> np.ndarray:
    """K[n, j] = max(0, n·ω_j) ΔΩ_j (N, H·2H) float64, kept for the last :data:`KERNEL_CACHE` normal sets and
    map heights (a search evaluates the same normals on hundreds of maps); none above
    :data:`KERNEL_CACHE_ENTRIES` entries."""
    d, dw = texel_geometry(height)
    key = (hashlib.blake2b(np.ascontiguousarray(normals).tobytes(), digest_size=16).digest(), height)
    if key in _KERNELS:
        _KERNELS.move_to_end(key)
        return _KERNELS[key]
    k = np.maximum(normals @ d.T, 0.0) * dw[None, :]
    if k.size <= KERNEL_CACHE_ENTRIES:
        k.flags.writeable = False
        _KERNELS[key] = k
        while len(_KERNELS) > KERNEL_CACHE:
            _KERNELS.popitem(last=False)
    return k


def flux_numpy(radiance: np.ndarray) -> np.ndarray:
    """Φ_c = Σ_j L_jc ΔΩ_j (3,)."""
    _, dw = texel_geometry(radiance.shape[0])
    return dw @ radiance.reshape(-1, 3).astype(np.float64)


def write_probe(path: Any, radiance: np.ndarray) -> None:
    """Write the map as a float32 RGB OpenEXR lat-long probe (atomically), loadable with ``--probe``."""
    import mitsuba as mi

    from ...atomic import atomic_path
    from ...backend import bitmap_io_threads

    with atomic_path(path, ".exr") as tmp, bitmap_io_threads():
        mi.Bitmap(np.ascontiguousarray(radiance, dtype=np.float32)).write(str(tmp))


def _softplus_np(x: np.ndarray) -> np.ndarray:
    return np.maximum(x, 0.0) + np.log1p(np.exp(-np.abs(x)))


def describe(fam: Family, theta: np.ndarray, height: int) -> str:
    """The lighting θ in words: each lobe's direction (θ, φ in degrees), sharpness λ and share of the luminance
    flux, the soft map's share, and Φ_Y (before the rescaling every share is a flux in the same units)."""
    y = np.array(LUMINANCE)
    parts, shares = [], []
    for k in range(fam.lobes):
        v = theta[7 * k:7 * k + 3]
        th, ph = latlong.direction_to_spherical(v / np.linalg.norm(v))
        lam = fam.sharpness_min * (fam.sharpness_max / fam.sharpness_min) ** (1 / (1 + np.exp(-theta[7 * k + 3])))
        shares.append(float(_softplus_np(theta[7 * k + 4:7 * k + 7]) @ y))
        parts.append(f"lobe θ={np.degrees(th):.1f}° φ={np.degrees(ph):.1f}° λ={lam:.3g}")
    idx, wts = upsample_plan(fam.map_height, height)
    _, dw = texel_geometry(height)
    coarse = _softplus_np(theta[7 * fam.lobes:-1]).reshape(3, -1)
    shares.append(float(sum(y[c] * ((wts * coarse[c][idx]).sum(axis=0) @ dw) for c in range(3))))
    total = sum(shares)
    flux = FLUX_REFERENCE * 10 ** (fam.decades / (1 + np.exp(-theta[-1])))
    words = [f"{p} ({100 * s / total:.1f} % of Φ)" for p, s in zip(parts, shares[:-1], strict=True)]
    return "; ".join(words + [f"soft map {100 * shares[-1] / total:.1f} % of Φ", f"Φ_Y = {flux:.4g}"])
