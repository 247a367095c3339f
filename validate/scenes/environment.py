"""The :class:`Environment`: a distant radiance field, stored as a lat-long map in Mitsuba's
``envmap`` convention (see :mod:`validate.scenes.latlong`), plus where it came from.

The lat-long array *is* the environment: the Mitsuba reference and every local model see the same
bilinear radiance function, so a measured error is the approximation's, not a convention mismatch.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from . import latlong


@dataclass(frozen=True, eq=False)
class Environment:
    """A distant environment. ``radiance`` has shape (H, W, 3), float32, linear RGB, y-up."""

    name: str
    radiance: np.ndarray
    kind: str = "procedural"  # "procedural" | "probe"
    description: str = ""
    source: Path | None = None
    layout: str = "latlong"  # how the source file was laid out: latlong | angular | cross | procedural
    angular: np.ndarray | None = None  # the original angular map (for the R&H rh2001 convention)
    notes: tuple[str, ...] = ()
    # (texels clamped to 0, the lowest value before) when the loader clamped negative texels, else None
    clamped_negative: tuple[int, float] | None = None
    tags: tuple[str, ...] = field(default_factory=tuple)

    @property
    def height(self) -> int:
        return int(self.radiance.shape[0])

    @property
    def width(self) -> int:
        return int(self.radiance.shape[1])

    @cached_property
    def digest(self) -> str:
        """Content hash of the radiance (and of the angular source, if any): the cache key. Hashed
        from the array's own buffer (no copy) and computed once per environment."""
        h = hashlib.sha256()
        h.update(memoryview(np.ascontiguousarray(self.radiance, dtype=np.float32)).cast("B"))
        h.update(str(self.radiance.shape).encode())
        if self.angular is not None:
            h.update(memoryview(np.ascontiguousarray(self.angular, dtype=np.float32)).cast("B"))
        return h.hexdigest()[:32]

    def total_flux(self) -> np.ndarray:
        """Φ = ∫ L dω per channel (RGB), by exact texel solid angles. The solid angle depends on the
        row only, so Φ = Σ_i Ω_i Σ_j L_ij: row sums (float64) in blocks, no full-size temporaries."""
        per_row = latlong.row_solid_angles(self.height, self.width)
        rows = latlong.row_sums(self.radiance)
        return per_row @ rows

    def mitsuba_emitter(self) -> dict:
        """Mitsuba scene-dict entry for this environment (``envmap`` from an in-memory bitmap)."""
        import mitsuba as mi

        return {"type": "envmap", "bitmap": mi.Bitmap(np.ascontiguousarray(self.radiance, np.float32))}
