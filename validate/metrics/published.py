"""Comparison of computed SH9 coefficients with a published table, up to one exposure factor.

The circulating probe files are brighter than the exposure R&H used for their table (e.g.
grace_probe.hdr ≈ 3.19×, rnl_probe.hdr ≈ 9.97×), so we fit one scale s per probe by least squares,

    s = argmin_s Σ (c_k − s t_k)² = Σ c_k t_k / Σ t_k²      (c: ours, t: table; all 27 numbers)

and report the largest deviation of the scaled coefficients from the table, max_k |c_k / s − t_k|.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

PUBLISHED_TOLERANCE = 0.01  # the threshold: every scaled coefficient within ±0.01 of the table


@dataclass
class PublishedFit:
    probe: str
    scale: float
    max_deviation: float

    def to_json(self) -> dict:
        return {"probe": self.probe, "scale": self.scale, "max_deviation": self.max_deviation}


def fit_exposure(ours: np.ndarray, table: np.ndarray, probe: str = "") -> PublishedFit:
    """Least-squares exposure factor s (ours ≈ s · table) and max |ours/s − table|."""
    c = np.asarray(ours, dtype=np.float64).ravel()
    t = np.asarray(table, dtype=np.float64).ravel()
    s = float(c @ t / (t @ t))
    return PublishedFit(probe, s, float(np.max(np.abs(c / s - t))))
