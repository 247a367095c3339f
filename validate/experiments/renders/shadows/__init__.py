"""(e) Shadows, a part of ``renders``: a directional and a spot light over the plane with a box occluder, each
engine's shadow types against the path-traced penumbra of a light with a size (scenes:
:mod:`validate.scenes.render_shadow_scenes`).
Measured by the parent's ``compute`` (its references traced while the browser renders the main scenes) and kept
at ``Measurements.shadows``; :func:`validate.experiments.base.run` appends this part's stages to the parent's.
"""

from __future__ import annotations

from .claims import shadow_claims as claims
from .compute import compute_shadows as compute
from .report import data
from .report import shadow_findings as findings
from .report import shadow_sections as sections

KEY = "shadows"

__all__ = ["KEY", "compute", "claims", "findings", "sections", "data"]
