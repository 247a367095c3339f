"""The Khronos glTF Sample Viewer (:mod:`validate.local_models.render.khronos_viewer`), a part of ``renders``: the
exported scene files (``validate scenes export``) rendered by the viewer through its own loaders and IBL sampler,
judged per pixel against the same Mitsuba references as three.js, Babylon.js and Filament. Measured by the parent's
``compute`` and kept at ``Measurements.khronos``.
"""

from __future__ import annotations

from .claims import khronos_claims as claims
from .compute import compute_khronos as compute
from .report import data
from .report import khronos_findings as findings
from .report import khronos_sections as sections

KEY = "khronos"

__all__ = ["KEY", "compute", "claims", "findings", "sections", "data"]
