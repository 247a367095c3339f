"""HDR-FLIP, the one wrapper of NVIDIA's ``flip_evaluator`` in the suite: value, map and the parameters used.

    FLIP(R, T) = mean over the compared pixels of the per-pixel HDR-FLIP error ∈ [0, 1]   [1, 2]

``flip_evaluator.evaluate(reference, test, "HDR")`` [3] with the package's defaults (ACES tone mapper, exposure
range from the reference, 67 pixels per degree), returned as :attr:`FlipResult.parameters` so every figure
carries its provenance. HDR-FLIP needs linear, non-negative (H, W, 3) float32 images:

* without a mask every pixel is compared; a pixel non-finite in either image is black in both (no error),
  and the mean is FLIP's own mean over the image (the shadow metrics);
* with a mask (H, W), pixels outside it or with a non-finite reference are black in both, a NaN test pixel is
  0, and the mean is taken over the masked pixels; the map is NaN outside them (the IBL image metrics);
* ``negatives="raise"`` refuses negative values (one line, :class:`ValidateError`); ``"clamp"`` clamps them to 0
  (a model may legitimately go below zero, e.g. truncated SH; FLIP sees what a display would).

FLIP is perceptual (0 = identical, 1 = maximal) and carries no Monte Carlo uncertainty of its own; callers
quote a noise floor where they need one (:func:`validate.metrics.shadow_error.flip_noise_floor`).

References
  [1] P. Andersson, J. Nilsson, T. Akenine-Möller, M. Oskarsson, K. Åström, M. D. Fairchild,
      "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM CGIT 3(2), 2020.
  [2] P. Andersson, J. Nilsson, P. Shirley, T. Akenine-Möller, "Visualizing Errors in Rendered High Dynamic
      Range Images", Eurographics 2021 (HDR-FLIP).
  [3] NVlabs/flip, ``flip_evaluator/flip_python_api.py`` (``evaluate``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import flip_evaluator
import numpy as np

from ..errors import ValidateError


@dataclass
class FlipResult:
    """HDR-FLIP of a test image against a reference (module docstring)."""

    error: np.ndarray  # (H, W) FLIP map (NaN outside the mask when one is given)
    mean: float  # mean over the compared pixels
    parameters: dict[str, Any]  # what flip_evaluator used (tone mapper, exposures, pixels per degree)


def _images(reference: np.ndarray, test: np.ndarray, mask: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    ref = np.asarray(reference, dtype=np.float64)
    tst = np.asarray(test, dtype=np.float64)
    if ref.ndim != 3 or ref.shape[2] != 3 or ref.shape != tst.shape:
        raise ValidateError(f"FLIP: images must both be (H, W, 3); got {ref.shape} and {tst.shape}")
    if mask is not None and np.shape(mask) != ref.shape[:2]:
        raise ValidateError(f"FLIP: mask {np.shape(mask)} does not match image {ref.shape[:2]}")
    return ref, tst


def _plain(value: Any) -> Any:
    return float(value) if isinstance(value, (int, float, np.floating)) else value


def flip_hdr(reference: np.ndarray, test: np.ndarray, mask: np.ndarray | None = None, *,
             negatives: Literal["raise", "clamp"] = "raise") -> FlipResult:
    """HDR-FLIP [1, 2] of ``test`` against ``reference``, linear (H, W, 3); see the module docstring for the
    mask and ``negatives`` rules. Returns the map, the mean and flip_evaluator's parameters [3]."""
    ref, tst = _images(reference, test, mask)
    if mask is None:
        keep = np.isfinite(ref).all(axis=2) & np.isfinite(tst).all(axis=2)
        ref, tst = np.where(keep[..., None], ref, 0.0), np.where(keep[..., None], tst, 0.0)
    else:
        keep = np.asarray(mask, dtype=bool) & np.all(np.isfinite(ref), axis=-1)
        ref = np.where(keep[..., None], ref, 0.0)
        tst = np.where(keep[..., None], np.nan_to_num(tst, nan=0.0), ref)
    if negatives == "clamp":
        ref, tst = np.maximum(ref, 0.0), np.maximum(tst, 0.0)
    elif (ref < 0).any() or (tst < 0).any():
        raise ValidateError("FLIP: HDR images must be nonnegative")
    fmap, mean, params = flip_evaluator.evaluate(np.ascontiguousarray(ref, dtype=np.float32),
                                                 np.ascontiguousarray(tst, dtype=np.float32), "HDR", applyMagma=False)
    parameters = {k: _plain(v) for k, v in params.items()}
    if mask is None:
        return FlipResult(np.asarray(fmap).reshape(ref.shape[:2]), float(mean), parameters)
    fmap = np.asarray(fmap, dtype=np.float64).reshape(keep.shape)
    out = np.full(keep.shape, np.nan)
    out[keep] = fmap[keep]
    return FlipResult(out, float(fmap[keep].mean()) if keep.any() else float("nan"), parameters)


__all__ = ["FlipResult", "flip_hdr"]
