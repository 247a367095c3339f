"""(b) Babylon's CDF irradiance (Babylon PR 16247), a part of ``renders``: the Lambertian sphere under a sunny probe
rendered by Babylon with its CDF irradiance at several cube sizes, as shipped and as before the PR, against Mitsuba
(scenes: :mod:`validate.scenes.render_cdf_scenes`). Measured by the parent's ``compute`` and kept at
``Measurements.cdf``; :func:`validate.experiments.base.run` appends this part's stages to the parent's.
"""

from __future__ import annotations

from .claims import cdf_claims as claims
from .compute import compute_cdf as compute
from .report import cdf_findings as findings
from .report import cdf_sections as sections
from .report import data

KEY = "cdf"

__all__ = ["KEY", "compute", "claims", "findings", "sections", "data"]
