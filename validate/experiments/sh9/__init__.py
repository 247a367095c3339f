"""Experiment ``sh9``: SH9 irradiance (Ramamoorthi & Hanrahan 2001) against Mitsuba's radiance.

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` (numbers) →
:func:`.claims.claims` → :func:`.report.findings`, :func:`.report.sections`; :func:`..base.run` wires them.

Claims (each with a power check that fails; sources in :mod:`.claims`):

* ``sh9.paper.<probe>.mean|max`` — the paper's headline on its own probes (Debevec angular maps whose
  stem is exactly a ``debevec_file`` of ``probe_aliases.csv``): flux-normalised luminance error mean
  < 1 %, max < 5 %. Power: a Condon–Shortley phase mismatch.
* ``sh9.published.<probe>`` — the coefficients in R&H's ``prefilter`` convention equal the published
  table up to one exposure factor (every scaled coefficient within ±0.01). Power: the frame z-mirrored.
* ``sh9.bound.max|mean`` — the "any lighting" theorem on every environment: per channel, max error ≤
  3/32 Φ and mean ≤ 3.07 % Φ; ``sh9.worst_case.near_directional.*`` — a 0.5° disc attains > 95 % of
  both; ``sh9.bandlimited.exact`` — exact on order-≤ 2 lighting (< 0.1 %).
* ``reference.convergence``, ``reference.closed_form.<env>`` (constant, two-tone, band-limited from its
  analytic coefficients, near-directional cap), ``reference.pathtrace.<env>[.bias]`` — the reference
  judged by convergence, closed forms and a path-traced Lambertian sphere.
* ``sh9.technique.<name>.<metric>`` — each registered irradiance technique's declared thresholds.

Every registered irradiance technique is evaluated on every environment and gets a row in the
technique comparison and ``results.json`` entries at ``experiments.sh9.techniques.<name>``.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "SH9 irradiance vs Mitsuba (Ramamoorthi & Hanrahan 2001)"
DESCRIPTION = ("SH9 coefficients, errors under every metric, error vs order, published table, every registered "
               "irradiance technique, claims")
ORDER = 10




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "summary", "techniques"]
