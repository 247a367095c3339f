"""Khronos's glTF-IBL-Sampler, a part of ``ibl``: its units and orientation (a constant and a marked
environment), its Lambertian cube against Mitsuba's irradiance quadrature on the paper's probes beside SH9 and
the suite's own irradiance map (Ramamoorthi & Hanrahan's 1 % / 5 % of Φ), its GGX chain beside
``split_sum_ggx`` over roughness (from the parent's rendered spheres), and a sweep of ``sampleCount``,
``cubeMapResolution`` and ``lodBias``. Measured by the parent's ``compute`` and kept at
``IblMeasurements.khronos``; without the tool or a Vulkan device the part is ``not_run`` with the reason.
"""

from __future__ import annotations

from .claims import khronos_claims as claims
from .compute import compute_khronos as compute
from .report import data, not_run
from .report import khronos_findings as findings
from .report import khronos_sections as sections

KEY = "khronos"

__all__ = ["KEY", "compute", "claims", "findings", "sections", "data", "not_run"]
