"""``worstcase``: the worst lighting for each irradiance technique (issue 22, items 1 and 2).

Linear techniques (tested, :func:`.certificate.linearity_defect`) get an exact certificate — the supremum of
the flux-normalised error over all non-negative lighting, attained by one direction (:mod:`.certificate`);
every technique gets a worst-case search over suns and skies (:mod:`.search`: drjit AD where a drjit version
exists, :mod:`.dr_models`; SPSA otherwise), whose worst lighting is written as an EXR probe.
"""

from __future__ import annotations

from .claims import claims
from .compute import NAME, compute
from .report import data, findings, sections, techniques
from .settings import FULL, QUICK

TITLE = "Worst case for any lighting: certificates of linear techniques and a differentiable search"
DESCRIPTION = ("sup of the flux-normalised irradiance error over all non-negative lighting (one direction for a "
               "linear technique), and a drjit-AD / SPSA search over spherical-Gaussian suns and soft skies")
ORDER = 15




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "techniques"]
