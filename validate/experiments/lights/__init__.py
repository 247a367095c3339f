"""Experiment ``lights``: the textbooks' classic lights against Mitsuba.

Scene (:mod:`validate.scenes.light_scenes`): a diffuse ground plane, a sphere and a box, lit in
turn by Mitsuba ``point``, ``spot`` and ``directional`` emitters and by ``rectangle``, ``disk`` and
``sphere`` area emitters, physical units; plus one render with point + spot + directional +
rectangle together (and the three delta lights again with the rectangle's shape present but dark,
since an area light's shape casts shadows too), the rectangle over the bare ground, and a real lamp
(a disc at the end of a black tube: a spot beam with a physical edge).

Reference (:mod:`validate.reference.light_render`): Mitsuba's direct lighting at the pixel centres,
P independent passes → mean ± standard error; the G-buffer of the same rays.

Techniques: every registered ``light`` technique (:mod:`validate.local_models.light.classic_lights`,
``light_attenuation``, ``light_grid`` and plug-ins) shades the G-buffer, L = ρ/π · E, for each
standard light it models (meta ``lights``), with the scene's own shadow rays; its image errors
(:mod:`.image_metrics`: mean, max, bias, each ± uncertainty) go to the comparison table and to
``results.json`` at ``experiments.lights.techniques.<name>.metrics.<light>.<metric>``. Declared
thresholds (metric names ``<light>.<metric>``) become claims.

Claims (each with a power check that fails):
1. declared thresholds: inverse-square point light, Mitsuba-profile spot and directional light
   reproduce Mitsuba's renders to float32 rounding (max error < 10⁻⁴ of the mean lit radiance);
2. Lambert's closed form for the rectangle equals Mitsuba's ``rectangle`` emitter over the bare
   ground (|pooled z| < 4);
3. the n×n grid (midpoint rule) converges at the rate quadrature theory gives, O(n⁻²);
4. lights add linearly: the render with four lights equals the sum of the four single renders
   (|pooled z| < 4, and max |z| below the Šidák critical value).

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` → :func:`.claims.claims` →
:func:`.report.findings`, :func:`.report.sections`; :func:`..base.run` wires them.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, reported_settings, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "The textbooks' classic lights against physics"
DESCRIPTION = "point, spot, directional and area lights; attenuation sets, point stand-ins, n×n grids"
ORDER = 70




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "reported_settings", "summary", "techniques"]
