"""Engines' images of ``renders`` (and its parts), cached like every reference.

:func:`render` is the registered engine's :meth:`~validate.local_models.render.engine.Engine.render`, its result kept
in the reference cache (:mod:`validate.reference.cache`, kind ``engine_render``) under the engine's
:meth:`~validate.local_models.render.engine.Engine.cache_parts` — its name, version and own sources (page and
scripts), the scene's content and the engine's options — so a warm run renders again only what changed. The entry
holds the image, the readback's uncertainty, the page's version and report, and the frame and wall times of the
render that made it (a cached render's times are those of that render). An engine without a known version is not
cached. ``VALIDATE_CACHE=off`` turns the cache off, as for the references.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from ...local_models.render import registry
from ...local_models.render.engine import EngineRender
from ...reference.cache import lookup, store

CACHE_KIND = "engine_render"


def cached(name: str, scene: Any) -> EngineRender | None:
    """The cached render of ``scene`` by the engine ``name``, or None (a miss, no version, the cache off)."""
    parts = registry.get(name).cache_parts(scene)
    return _decoded(lookup(CACHE_KIND, parts)) if parts is not None else None


def _decoded(hit: dict[str, np.ndarray] | None) -> EngineRender | None:
    if hit is None:
        return None
    return EngineRender(hit["image"], float(hit["frame_ms"]), float(hit["wall_s"]), str(hit["version"]),
                        json.loads(str(hit["info"])), float(hit["stderr"]))


def render(name: str, scene: Any) -> EngineRender:
    """The engine ``name``'s render of ``scene``: cached, else rendered and stored (module docstring)."""
    engine = registry.get(name)
    parts = engine.cache_parts(scene)
    hit = _decoded(lookup(CACHE_KIND, parts)) if parts is not None else None
    if hit is not None:
        return hit
    er = engine.render(scene)
    if parts is not None:
        store(CACHE_KIND, parts, {"image": np.asarray(er.image, np.float32), "frame_ms": np.float64(er.frame_ms),
                                  "wall_s": np.float64(er.wall_s), "version": np.str_(er.version),
                                  "info": np.str_(json.dumps(er.info, sort_keys=True)),
                                  "stderr": np.float64(er.stderr)})
    return er


def to_render(names: list[str], scenes: list[Any]) -> set[str]:
    """The engines among ``names`` with an image of ``scenes`` not in the cache (their pages, runtimes are needed)."""
    return {n for n in names for sc in scenes if cached(n, sc) is None}


__all__ = ["render", "cached", "to_render", "CACHE_KIND"]
