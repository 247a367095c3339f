"""Experiment ``shadows``: every registered shadow technique against Mitsuba's soft shadows of a disc light.

Scene (:mod:`validate.scenes.shadow_scenes`): a ground plane with a floating sphere, a box, a thin
pole and a self-shadowing staircase, lit by a one-sided disc light of radius r (0.02 m, a near-point
light, up to 1 m) 4 m up, with the radiance scaled so that the on-axis irradiance is the same for
every r. Direct lighting only.

Reference (:mod:`validate.reference.shadow_render`): Mitsuba's ``direct`` integrator at the pixel
centres, P independent passes → mean ± standard error per pixel; the G-buffer (position, normal,
albedo) from the ``aov`` integrator; the visible fraction V of the disc per pixel (stratified shadow
rays), which splits the image into lit (V = 1), penumbra and umbra (V = 0).

Techniques: the ``shadow`` family (:mod:`validate.local_models.families`); built-ins ``hard``,
``pcf`` (3×3) and ``pcss`` register in :mod:`validate.local_models.shadow.shadow_map`, and a plug-in is one
file with ``@shadow.register``. Each is called as ``shadow.call(tech, shadow_map, light, points,
normals)`` and shaded as ρ/π · E_disc · V′ (E_disc the closed-form unoccluded irradiance). The light's
centre and direction do not change with r, so one shadow map per resolution serves every radius.

Metrics (:mod:`validate.metrics.shadow_error`): |ΔY| / L_norm per pixel (L_norm = mean lit reference
luminance), averaged over the image and per region, false-shadow (acne) and false-light
(peter-panning) areas, light leak, HDR-FLIP — each ± its uncertainty.

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` (numbers) →
:func:`.claims.claims` → :func:`.report.findings`, :func:`.report.sections`; :func:`..base.run` wires them.
:func:`.check.check_shadow` measures one function for :mod:`validate.testing`.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, reported_settings, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "Shadow maps vs path-traced soft shadows (disc light)"
DESCRIPTION = ("every registered shadow technique against Mitsuba's direct lighting, by lit / penumbra / umbra region, "
               "vs shadow-map resolution and light radius; bias and PCF-kernel sweeps")
ORDER = 50




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "reported_settings", "summary", "techniques"]
