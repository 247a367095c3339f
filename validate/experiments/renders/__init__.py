"""Experiment ``renders``: engines' pixels (three.js, Babylon.js, Filament) against the Mitsuba path tracer (issue 21).

Scenes (:mod:`validate.scenes.render_scenes`: (a) furnace, (b) the shared probe ``ict_uffizi_256x128.hdr`` of
``--probes`` on white metal spheres over roughness and a Lambertian sphere, and white glTF spheres over metalness ×
roughness against (i) glTF 2.0 as specified (:mod:`validate.reference.gltf_bsdf`) and (ii) the multiscatter
microsurface (:mod:`validate.reference.microsurface_bsdf`), kept apart, (c) directional, point and spot lights,
(d) a rectangular area light on the plane and the sphere (three.js; Babylon.js through its own shader with Heitz's
tables — its own areaLightsLTC.bin is not obtainable offline), (f) hemisphere light) are rendered by Mitsuba
at pixel centres (:mod:`validate.reference.render_reference`) and by each engine through its own pipeline in headless
Chromium (:mod:`validate.local_models.render`), then judged per pixel (:mod:`validate.metrics.pixel_z`).
Without Chromium or node_modules every engine is skipped with the reason. Filament renders only the punctual
lights (c) (its engine's ``lacks``: no IBL prefilter, no area lights in its npm package); its 8-bit canvas readback
carries its quantisation as an uncertainty added in quadrature to Mitsuba's.
(e) Shadows — a directional and a spot light over the plane with a box occluder, each engine's shadow types against
the path-traced penumbra of a light with a size — and (b) Babylon's CDF irradiance are parts with their own stages:
PARTS = (shadows, cdf, khronos, loaders)
"""

from __future__ import annotations

from . import cdf, khronos, loaders, shadows
from .claims import claims
from .compute import compute
from .report import data, findings, not_run, reported_settings, sections, summary
from .settings import FULL, QUICK

NAME = "renders"
TITLE = "Engines' pixels against the path tracer: three.js, Babylon.js and Filament vs Mitsuba"
DESCRIPTION = ("Furnace, probe, directional, point, spot and hemisphere lights rendered by the engines, judged "
               "per pixel with uncertainty")
ORDER = 95


PARTS = (shadows, cdf, khronos, loaders)


__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "reported_settings", "summary", "not_run", "PARTS"]
