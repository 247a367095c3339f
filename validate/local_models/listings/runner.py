"""Shared by the listing techniques: whether the compatibility runtime starts here, and running a catalogued
listing through :func:`validate.gl.listing_harness.render_points`.

GL-backed techniques register only where the runtime starts (:func:`register_gl`); elsewhere
:data:`GL_SKIPPED` records which were left out and :func:`gl_status` says why.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numpy as np

from ...geometry import unit
from ...gl.listing_harness import KIND, render_points
from ..registry import Family
from .catalog import listing

GL_SKIPPED: list[str] = []  # GLSL listing techniques not registered (no runtime)


@lru_cache(maxsize=1)
def gl_status() -> tuple[bool, str]:
    """(True, renderer and version) when the OpenGL 4.5 compatibility runtime starts, else (False, why)."""
    from ...gl import runtime  # noqa: PLC0415
    from ..glsl_technique import STATUS  # noqa: PLC0415 — `validate list` and results.json meta.gl report it

    ok, why = runtime.available(KIND)
    STATUS[KIND] = "" if ok else why
    return ok, why


def register_gl(family: Family, name: str, description: str, listing_name: str,
                **kwargs: Any) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """``family.register`` when GL is available (meta ``glsl`` = the listing's shader files, ``runtime`` = the
    compatibility kind, so ``validate list`` tags it); otherwise the function is kept unregistered (named in
    :data:`GL_SKIPPED`)."""
    lst = listing(listing_name)
    files = " + ".join(f for f in (lst.vert, lst.frag) if f)

    def deco(fn: Callable[..., Any]) -> Callable[..., Any]:
        if gl_status()[0]:
            return family.register(name, description, glsl=f"listings/shaders/{files}", runtime=KIND,
                                   **kwargs)(fn)
        GL_SKIPPED.append(f"{family.name}/{name}")
        return fn
    return deco


def run(name: str, positions: np.ndarray, **kwargs: Any) -> np.ndarray:
    """(N, 4) float32: the catalogued listing ``name`` (glue and edits applied) over the receivers."""
    lst = listing(name)
    return render_points(lst.source("vert"), lst.source("frag"), positions, who=f"listing {name}", **kwargs)


def smoothstep(e0: Any, e1: Any, x: Any) -> np.ndarray:
    """GLSL smoothstep: t = clamp((x − e₀)/(e₁ − e₀), 0, 1), t²(3 − 2t) (GLSL 4.50 §8.3; undefined for e₀ ≥ e₁)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.clip((np.asarray(x, dtype=np.float64) - e0) / (np.asarray(e1, dtype=np.float64) - e0), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


__all__ = ["GL_SKIPPED", "gl_status", "register_gl", "run", "smoothstep", "unit"]
