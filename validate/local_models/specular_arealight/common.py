"""The specular area-light family's shared pieces: reading a technique's GGX parameters (α, F0) from the
family's brdf mapping, with the one-line error every technique raises. Registers nothing."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...errors import ValidateError


def brdf_params(brdf: Mapping[str, Any], who: str) -> tuple[float, np.ndarray]:
    alpha = np.asarray(brdf.get("alpha", 0.3), dtype=np.float64)
    f0 = np.asarray(brdf.get("f0", 1.0), dtype=np.float64)
    if alpha.ndim != 0 or not 0.0 < float(alpha) <= 1.0:
        raise ValidateError(f"technique '{who}' (specular_arealight): alpha={alpha.tolist()!r} must be in (0, 1]")
    if f0.ndim > 1 or (f0.ndim == 1 and f0.shape[0] != 3) or np.any((f0 < 0) | (f0 > 1)):
        raise ValidateError(f"technique '{who}' (specular_arealight): f0={f0.tolist()!r} must be in [0, 1], scalar "
                            "or RGB")
    return float(alpha), np.broadcast_to(f0, (3,))
