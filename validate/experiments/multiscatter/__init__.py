"""Experiment ``multiscatter``: the white furnace of every ``brdf`` technique over roughness × cos θ_v × F₀ and
metalness grids, against the closed target (albedo 1 when nothing is absorbed).

Techniques: the ``brdf`` family (every registered technique is measured; the multiple-scattering compensations
are :mod:`validate.local_models.brdf.brdf_multiscatter`). The reference is a theorem, not a render: a microsurface of
reflectance F = 1 absorbs nothing, so all the light that reaches it leaves it, W(v) = 1 for every v and α
(Heitz 2014 §2.4, the furnace test of Heitz et al. 2016 fig. 7; Kulla & Conty 2017 slide 16); with the metalness
workflow and base colour 1 (diffuse albedo 1, metal F₀ = 1), W = 1 for every metalness.

Metrics (luminance; W(v) = ∫ q(l, v) dω_l, Gauss–Legendre cos θ_l × uniform φ, n and n/2 nodes):
* ``furnace_error.f0_1`` = max over α × μ_v of |W − 1| with F = 1 (η = 0, k = 1, metalness 1, base colour 1);
* ``furnace_error.metalness`` = max over α × μ_v × metalness m of |W − 1| with base colour 1, albedo 0, F = 1;
* ``albedo.<f0>``: W at α = 1, μ_v = 0.5 for F₀ ∈ {0.04, 0.5} (η real; the metalness techniques: metalness 1,
  base colour F₀) (reported, no target).
* ``walk_albedo_error`` = max over the walk's α × F₀ of |W − W_walk| at μ_v = 0.5 (± the walk's standard error)
  against the multiple-scattering reference :mod:`validate.reference.microsurface_walk` (Heitz et al. 2016's
  random walk on the height-correlated Smith microsurface, Schlick F per bounce), which is first checked: its
  first bounce equals the height-correlated single-scattering albedo and its F = 1 albedo is 1. Reported, not
  claimed: the techniques' single scattering is the separable G₁G₁ (Mitsuba's), ≈ 4 % below the walk's first
  bounce at α = 1, and the exact-Fresnel techniques see η real where the walk sees Schlick's F₀.
Uncertainty: |value(n) − value(n/2)| (quadrature). Power of the technique claims: output × 0.98 (a 2 % loss).

The same walk as a Mitsuba 3 BSDF (:mod:`validate.reference.microsurface_bsdf`, plug-in ``microsurface_walk``:
sample = the walk, eval = Heitz et al. 2016 §6's next-event estimator, pdf = that estimator at F = 1, the walk's
exit density), checked with Mitsuba's own machinery (JIT variants only; skipped, and said so, on scalar_rgb):
* ``walk.chi2``: min over (α, θ_i) of the χ² p-value of sample() vs pdf() — Mitsuba's ``ChiSquareTest`` histogram
  through ``BSDFAdapter``, expected counts = pdf() integrated on the harness's grid (4 seeds), Pearson's X² with
  their Monte Carlo variance added (Σ (O − Ê)²/(Ê + Var Ê)); > Šidák(0.01, cases). Power: sampler α × 1.1.
* ``walk.reciprocity``: max |z| of (f̂(a→b) − f̂(b→a))/se over direction pairs × α × F₀ < Šidák z. Power: the
  next-event shadowing by the distant G₁(ω_o) instead of G¹(ω_o, h).
* ``walk.eval_furnace``: max |A − 1|/se of ∫ eval dω_o at F₀ = 1 over α × μ_i < Šidák z (same power).
* ``walk.render_furnace``: a sphere of it in Mitsuba's ``path`` integrator under a unit constant environment,
  max |pixel mean − 1|/se over α < Šidák z. Power: the walk stopped after one bounce.
* ``walk.mitsuba_single_scatter``: the closed first order F D G₂/(4μ_i) against Mitsuba's ``roughconductor``
  × G₂/(G₁G₁), max relative difference < 10⁻⁴. Power: α × 1.01.

Pipeline: :mod:`.settings` (``QUICK``, ``FULL``) → :func:`.compute.compute` → :func:`.claims.claims` →
:func:`.report.findings`, :func:`.report.sections`; :func:`..base.run` wires them.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, sections, summary, techniques
from .settings import FULL, NAME, QUICK

TITLE = "Multiple-scattering compensation (white furnace)"
DESCRIPTION = ("every brdf technique's furnace albedo over roughness × view × F₀ × metalness grids against the "
               "closed target 1 (F = 1); the blended-F₀ engine bug as a regression technique")
ORDER = 72




__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "summary", "techniques"]
