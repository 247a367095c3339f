"""Experiment ``uberlight``: Barzel's überlight (Orange Book §12.4) against physical luminaires.

Scenes (:mod:`validate.scenes.uberlight_scenes`): a diffuse wall and floor (with a sphere), lit by
(a) Mitsuba's ``projector`` carrying exactly the überlight's angular mask as a bitmap texture — a point
light of intensity I₀·A(ω), so only the falloff and the reflection remain to compare; (b) a physical
barn-door luminaire (a Lambertian disc in a black housing behind a rectangular aperture), direct
lighting path-traced, P independent passes → per-pixel mean ± standard error.

Techniques: every registered ``uberlight`` technique (:mod:`validate.local_models.uberlight` and
plug-ins) shades the G-buffer with the light's visibility; metrics (:mod:`.compute`) go to
the tables and to ``results.json`` at ``experiments.uberlight.techniques.<name>.metrics``. Declared
thresholds (``projector.max_rel``, ``barndoor.edge_rms``) become claims.

Claims (each with a power check that fails):
1. with edge widths 0 and 1/d², the überlight equals the projector reference to float32 rounding
   (declared threshold of ``uberlight_inverse_square``); power: the width 1 % too large, and the light
   rolled by 1° about its axis;
2. for each barn-door size the fitted soft edge reproduces the penumbra within the error budget
   of :func:`.compute.error_budget` (numbers in the claim's source); power: edge × 1.5.

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` → :func:`.claims.claims` →
:func:`.report.findings`, :func:`.report.sections`; :func:`..base.run` wires them. :mod:`.check` serves
``validate.testing.check_uberlight``.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "The überlight against physical luminaires"
DESCRIPTION = "Barzel's überlight (Orange Book §12.4) vs a Mitsuba projector and a barn-door luminaire"
ORDER = 75




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "summary", "techniques"]
