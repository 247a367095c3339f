"""(g) Loaders, a part of ``renders``: the hosted engines through their own glTF loaders, ``export → engines →
judge`` — the road an outside team takes (issue 34, item 5).

The suite's scenes are exported as files (:func:`validate.scenes.manifest.export_scenes`), rendered by the engines
that load them with their own loaders (:mod:`validate.local_models.render.three_gltf`, ``filament_gltf``) and
judged by :func:`validate.judge.folder.judge_folder`; each scene's judgement is set beside the hand-built path's
(the parent's engine pages fed the suite's own scene JSON), and where they differ the cause is a finding.
Measured after the parent (``measure``: it needs the parent's judgements).
"""

from __future__ import annotations

from .claims import loader_claims as claims
from .compute import measure
from .compute import measure as compute
from .report import data
from .report import loader_findings as findings
from .report import loader_sections as sections

KEY = "loaders"

__all__ = ["KEY", "compute", "measure", "claims", "findings", "sections", "data"]
