"""Experiment ``blender``: Blender's Cycles as a second path tracer beside Mitsuba, and EEVEE, on the exported scenes.

The scenes leave as files (:mod:`validate.scenes.manifest`), enter Blender through its own glTF importer — the path
users take — and render in a child process of Blender's own interpreter (:mod:`validate.local_models.render.blender`).
Cycles is judged per pixel against the Mitsuba truth of the renders experiment, where both describe the scene
identically (claims); the furnace (Principled's multiple scattering against glTF's BRDF), the importer's light
conversion under SPEC, COMPAT and RAW, and EEVEE on the sun-lit and point-lit spheres (the furnace too under
``VALIDATE_EEVEE=1``) are findings. Under ``VALIDATE_EEVEE=1`` also scenes built through bpy from the description
Mitsuba renders (:mod:`.world`: a Lambertian sphere lit only by a shared probe — Cycles against Mitsuba as claims,
EEVEE's world lighting by R&H's measure beside ``sh1``, ``sh1_geomerics`` and ``sh9``, sun extraction and the
indirect clamp on and off; :mod:`.shadows`: a sphere light and an occluder, EEVEE's jitter off and on, its filter
radius and overblur swept; :mod:`.probes`: white GGX spheres over roughness — Cycles against Mitsuba's glTF BSDF as
claims, EEVEE's world and sphere-probe reflections — and a Lambertian sphere on a plane under a baked irradiance
volume, with Cycles as its second truth). A package of its own, not a part of ``renders``: Blender is an optional
runtime with its own process, cache entries and cost, and without it this experiment alone reports not run.
Without Blender: not run, ``python -m validate setup --blender``.
"""

from __future__ import annotations

from .claims import claims
from .compute import compute
from .report import data, findings, not_run, sections, summary
from .settings import FULL, QUICK

NAME = "blender"
TITLE = "Blender under test: Cycles as a second truth beside Mitsuba, EEVEE judged per pixel"
DESCRIPTION = ("The exported glTF scenes through Blender's importer: Cycles against Mitsuba per pixel, the importer's "
               "light units, EEVEE")
ORDER = 96

__all__ = ["NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings", "sections",
           "data", "summary", "not_run"]
