"""Engines under test: one module per engine in this folder, each declaring an ``ENGINE`` (:mod:`.engine`), found
by :mod:`.registry`.

* hosted in the run's one headless Chromium (:mod:`.hosted`): ``three`` (three.js, :mod:`.three`), ``babylon``
  (Babylon.js, :mod:`.babylon`), ``filament`` (Filament, :mod:`.filament`) and their variants — the ``renders``
  experiment's engines, rendering a :class:`~validate.scenes.render_scenes.RenderScene` in this process;
* Blender's Cycles and EEVEE in Blender's own interpreter (:mod:`.blender`, :mod:`.blender_cycles`,
  :mod:`.blender_eevee`) — the ``blender`` experiment's, rendering the exported scene files.

:func:`render` is ``registry.get(engine).render(scene)``: (R, R, 4) float32 with row 0 = TOP (the scene's
convention), the alpha channel = coverage (0 off the sphere). Adding an engine: ``docs/engines.md``.
"""

from __future__ import annotations

from . import registry
from .engine import Engine, EngineRender, FolderRender, Unavailable
from .hosted import HALF_FLOAT_RTOL, SWIFTSHADER_TRIG_ATOL, decode_unorm8, missing_runtime

Missing = Unavailable  # the name the renders experiment's not-run record uses


def render(engine: str, scene) -> EngineRender:  # noqa: ANN001 - a RenderScene (validate.scenes.render_scenes)
    """``engine`` renders ``scene``; raises with the reason when it cannot run (an unknown name: ValidateError)."""
    return registry.get(engine).render(scene)


def product(engine: str) -> str:
    """The product an engine name renders with (``babylon_cdf64_shipped`` → Babylon.js)."""
    return registry.product(engine)


__all__ = ["Engine", "EngineRender", "FolderRender", "Missing", "Unavailable", "registry", "render", "product",
           "missing_runtime", "decode_unorm8", "HALF_FLOAT_RTOL", "SWIFTSHADER_TRIG_ATOL"]
