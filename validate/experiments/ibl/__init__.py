"""Experiment ``ibl``: prefiltered environment maps against Mitsuba path-traced BRDF integrals.

The pipeline, one module per stage:

* :mod:`.settings` — ``QUICK`` and ``FULL``; :mod:`.scene` — BRDF cases, the scene and render jobs;
* :mod:`.compute` — measurements: the irradiance quadrature, the diffuse-map sweep, every
  ``irradiance`` technique and map on a rendered Lambertian sphere, every ``specular`` technique on every
  BRDF case it declares (modified Phong, GGX conductor, GGX plastic), the mixing shader, the dented sphere;
* :mod:`.reference_checks` — χ² and white-furnace checks of the reference BSDFs, split sum under a constant
  environment, the independent bound for the Phong map at normal incidence;
* :mod:`.claims` — claims with sources and power checks; technique entries and declared thresholds;
* :mod:`.report` — findings and report sections;
* :mod:`.khronos` (``PARTS``) — Khronos's glTF-IBL-Sampler: units, orientation, the paper's probes, a sweep.

Errors on rendered pixels are relative luminance errors with the renders' Monte Carlo standard errors
(:mod:`validate.metrics.image_error`), FLIP beside them; the map sweep uses the peak-normalised error
|Y(E′) − Y(E)| / max Y(E) of :mod:`validate.metrics.irradiance_error`.

:func:`.check.check_specular` is the ``validate.testing`` entry point for a specular technique.
"""

from __future__ import annotations

from . import khronos
from .claims import claims
from .compute import compute
from .report import data, findings, reported_settings, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "IBL convolution vs Mitsuba"
DESCRIPTION = ("Diffuse irradiance maps (cube 4…256, lat-long, SH), every irradiance and specular technique "
               "(Phong-prefiltered maps, split-sum GGX, plug-ins), the seed's mixing shader, against Mitsuba "
               "path-traced BRDF integrals.")
ORDER = 40
PARTS = (khronos,)




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "reported_settings", "summary", "techniques", "PARTS"]
