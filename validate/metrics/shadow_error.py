"""Shadow error metrics: image error by region, false shadow / false light, FLIP, and a per-pixel test.

Inputs are per-pixel arrays over the *valid* pixels (the pixel-centre ray hit geometry): reference
radiance r (N, 3) with its Monte Carlo standard error σ (N, 3), the approximation a (N, 3), the
approximation's visibility V′ (N,) and the reference visible fraction of the disc V (N,).

* Normalisation: L_norm = mean Y(r) over the reference-lit pixels (Y = Rec. 709 luminance), so an
  error of 0.05 is 5 % of the typical lit radiance.
* Per-pixel error e = |Y(a) − Y(r)| / L_norm.
* Regions from V (``region_masks``): ``lit`` V = 1 (every visibility ray reached the disc), ``umbra``
  V = 0, ``penumbra`` 0 < V < 1; pixels whose whole disc is below the horizon (V = NaN) belong to no
  region but count in ``total``. Per region: ``mean`` = mean e over the region, and ``share`` =
  Σ_region e / N_valid, the region's contribution to the total mean (so shares add up to the total
  less the below-horizon pixels). ``share`` grows with the region's area; ``mean`` does not.
* Uncertainty of a mean error: the reference noise moves each |a − r| by at most |r − r_true|, whose
  expectation is ≈ 0.8 σ; we quote mean(Y(σ))/L_norm over the region (conservative; the convention
  of :mod:`validate.metrics.irradiance_error`).
* ``false_shadow`` (shadow acne and over-darkening): fraction of the reference-lit pixels where
  V′ < ½. ``false_light`` (peter-panning and light leaks): fraction of the umbra pixels where V′ > ½.
  Each ± its binomial standard error √(max(p(1 − p), 1/n)/n) over the n pixels of the region (the
  pixels are a sample of the surface; 1/n keeps the error of an empty count from being zero).
* ``leak``: mean V′ over the umbra pixels (the fraction of the unoccluded light that leaks where the
  reference is black; the filtered maps' "light bleeding" [2] [3]), ± the standard error of that mean.
* ``flip_noise``: HDR-FLIP between the reference and the reference plus one draw of its own noise
  (r + σ ξ, ξ ~ N(0, 1), fixed seed, clamped at 0) — the FLIP a perfect model would score against this
  reference, quoted as FLIP's uncertainty.
* FLIP [1]: HDR-FLIP of the two images, :func:`validate.metrics.flip.flip_hdr` (no mask: invalid pixels black
  in both; negative values refused)
  (defaults: 67 pixels per degree, ACES tone mapper, exposure range from the reference).
* ``outside_band_test``: per-pixel two-sided Student-t test of a − r against σ with P − 1 degrees
  of freedom (P passes) at level α; the statistic is the fraction of pixels that exceed, with its
  binomial standard error. With a correct model it is α in expectation.

References
[1] P. Andersson, J. Nilsson, P. Shirley, T. Akenine-Möller, "Visualizing Errors in Rendered High
    Dynamic Range Images", Eurographics 2021 (HDR-FLIP).
[2] W. Donnelly, A. Lauritzen, "Variance Shadow Maps", I3D 2006, §3.2 (light bleeding).
[3] T. Annen, T. Mertens, H.-P. Seidel, E. Flerackers, J. Kautz, "Exponential Shadow Maps", GI 2008.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..errors import ValidateError
from ..scenes.latlong import luminance
from ..stats import two_sided_t_critical
from .flip import flip_hdr

REGIONS = ("lit", "penumbra", "umbra")
FLOAT_TOLERANCE = 1e-6  # relative to L_norm: below this a difference is float rounding, not error


@dataclass
class RegionError:
    mean: float  # mean e over the region (NaN if empty)
    share: float  # Σ_region e / N_valid
    uncertainty: float  # mean Y(σ)/L_norm over the region
    pixels: int

    def to_json(self) -> dict[str, Any]:
        return {k: _finite_or_none(v) for k, v in asdict(self).items()}


def _finite_or_none(v: Any) -> Any:
    """NaN (an empty region, FLIP not computed) becomes None, so results.json stays strict JSON."""
    return None if isinstance(v, float) and not np.isfinite(v) else v


@dataclass
class ShadowErrors:
    total: RegionError
    regions: dict[str, RegionError]
    false_shadow: float  # fraction of reference-lit pixels with V′ < ½
    false_light: float  # fraction of umbra pixels with V′ > ½
    flip: float  # mean HDR-FLIP (NaN if not computed)
    normaliser: float  # L_norm
    false_shadow_uncertainty: float = 0.0  # binomial standard error
    false_light_uncertainty: float = 0.0
    leak: float = float("nan")  # mean V′ over the umbra
    leak_uncertainty: float = 0.0

    def to_json(self) -> dict[str, Any]:
        return {"total": self.total.to_json(), "regions": {k: v.to_json() for k, v in self.regions.items()},
                "false_shadow": _finite_or_none(self.false_shadow), "false_light": _finite_or_none(self.false_light),
                "false_shadow_uncertainty": self.false_shadow_uncertainty,
                "false_light_uncertainty": self.false_light_uncertainty,
                "leak": _finite_or_none(self.leak), "leak_uncertainty": self.leak_uncertainty,
                "flip": _finite_or_none(self.flip), "normaliser": self.normaliser}


def region_masks(visibility: np.ndarray) -> dict[str, np.ndarray]:
    """Lit (V = 1), penumbra (0 < V < 1) and umbra (V = 0) masks; NaN is in none."""
    v = np.asarray(visibility, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        return {"lit": v >= 1.0, "penumbra": (v > 0.0) & (v < 1.0), "umbra": v <= 0.0}


def _check(name: str, a: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    a = np.asarray(a, dtype=np.float64)
    if a.shape != shape:
        raise ValidateError(f"shadow metrics: {name} has shape {a.shape}, expected {shape}")
    return a


def lit_normaliser(reference: np.ndarray, visibility: np.ndarray) -> float:
    """L_norm = mean luminance of the reference over its lit pixels."""
    lit = region_masks(visibility)["lit"]
    if not lit.any():
        raise ValidateError("shadow metrics: the reference has no lit pixel to normalise by")
    norm = float(luminance(np.asarray(reference)[lit]).mean())
    if not norm > 0:
        raise ValidateError("shadow metrics: the reference's lit pixels are black")
    return norm


def pixel_error(reference: np.ndarray, approx: np.ndarray, normaliser: float) -> np.ndarray:
    """e = |Y(a) − Y(r)| / L_norm per pixel."""
    return np.abs(luminance(np.asarray(approx)) - luminance(np.asarray(reference))) / normaliser


def shadow_errors(reference: np.ndarray, uncertainty: np.ndarray, approx: np.ndarray,
                  approx_visibility: np.ndarray, visibility: np.ndarray, images: tuple[np.ndarray, np.ndarray]
                  | None = None, normaliser: float | None = None) -> ShadowErrors:
    """All shadow metrics over N valid pixels (see module doc). ``images`` = (reference, approx) (H, W, 3)
    for FLIP; None skips FLIP."""
    reference = np.asarray(reference, dtype=np.float64)
    if reference.ndim != 2 or reference.shape[1] != 3:
        raise ValidateError(f"shadow metrics: reference has shape {reference.shape}, expected (N, 3)")
    n = reference.shape[0]
    uncertainty = _check("uncertainty", uncertainty, reference.shape)
    approx = _check("approximation", approx, reference.shape)
    v_approx = _check("approximation visibility", approx_visibility, (n,))
    v_ref = _check("reference visibility", visibility, (n,))
    norm = lit_normaliser(reference, v_ref) if normaliser is None else float(normaliser)
    e = pixel_error(reference, approx, norm)
    d = luminance(uncertainty) / norm
    masks = region_masks(v_ref)

    def region(m: np.ndarray) -> RegionError:
        k = int(m.sum())
        if k == 0:
            return RegionError(float("nan"), 0.0, 0.0, 0)
        return RegionError(float(e[m].mean()), float(e[m].sum() / n), float(d[m].mean()), k)

    regions = {name: region(masks[name]) for name in REGIONS}
    lit, umbra = masks["lit"], masks["umbra"]
    fs, fs_u = binomial_fraction(v_approx[lit] < 0.5)
    fl, fl_u = binomial_fraction(v_approx[umbra] > 0.5)
    k = int(umbra.sum())
    leak = float(v_approx[umbra].mean()) if k else float("nan")
    leak_u = float(v_approx[umbra].std(ddof=1) / np.sqrt(k)) if k > 1 else 0.0
    flip = flip_hdr(*images).mean if images is not None else float("nan")
    return ShadowErrors(region(np.ones(n, dtype=bool)), regions, fs, fl, flip, norm, fs_u, fl_u, leak, leak_u)


def binomial_fraction(hits: np.ndarray) -> tuple[float, float]:
    """(fraction p of True, binomial standard error √(max(p(1 − p), 1/n)/n)); (NaN, 0) when empty."""
    n = int(np.size(hits))
    if n == 0:
        return float("nan"), 0.0
    p = float(np.mean(hits))
    return p, float(np.sqrt(max(p * (1 - p), 1.0 / n) / n))


def flip_noise_floor(reference: np.ndarray, uncertainty: np.ndarray, seed: int = 0) -> float:
    """Mean HDR-FLIP of the reference (H, W, 3) against itself plus one draw of its noise σ (module doc)."""
    ref = np.nan_to_num(np.asarray(reference, dtype=np.float64))
    sig = np.nan_to_num(np.asarray(uncertainty, dtype=np.float64))
    noisy = np.maximum(ref + sig * np.random.default_rng(seed).standard_normal(ref.shape[:2])[..., None], 0.0)
    return flip_hdr(ref, noisy).mean


@dataclass
class PixelTest:
    fraction: float  # fraction of tested pixels whose |a − r| exceeds the t bound
    stderr: float  # binomial standard error of that fraction
    exceeded: int
    tested: int
    alpha: float
    t_bound: float

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


def outside_band_test(reference: np.ndarray, uncertainty: np.ndarray, approx: np.ndarray, passes: int,
                      include: np.ndarray, normaliser: float, alpha: float = 1e-3) -> PixelTest:
    """Fraction of ``include``d pixels where |Y(a) − Y(r)| > t_{1−α/2, P−1} · Y(σ) (and above float rounding)."""
    if passes < 2:
        raise ValidateError(f"outside_band_test: passes={passes}; need ≥ 2 for a standard error")
    if not (0 < alpha < 1):
        raise ValidateError(f"outside_band_test: alpha={alpha} must be in (0, 1)")
    t_bound = two_sided_t_critical(alpha, passes - 1)
    dy = np.abs(luminance(np.asarray(approx)) - luminance(np.asarray(reference)))
    sy = luminance(np.asarray(uncertainty))
    exceed = (dy > t_bound * sy) & (dy > FLOAT_TOLERANCE * normaliser)
    include = np.asarray(include, dtype=bool)
    k = int(include.sum())
    if k == 0:
        raise ValidateError("outside_band_test: no pixel to test")
    f = float(exceed[include].mean())
    return PixelTest(f, float(np.sqrt(max(f * (1 - f), 1.0 / k) / k)), int(exceed[include].sum()), k, alpha,
                     t_bound)
