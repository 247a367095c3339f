"""What an engine under test declares: one module of this folder, one ``ENGINE`` object.

An engine is the product whose pixels the suite judges against Mitsuba. Its module (``<engine>.py``, plus its page,
script or worker beside it) declares a module-level ``ENGINE``: an :class:`Engine` (or a subclass that knows how
to drive it) stating

* ``name`` — the suite's engine name (report rows, ``results.json`` keys, ``judge --engine``);
* ``product`` — what it is, for a person (``"three.js"``, ``"Blender Cycles"``);
* ``precision`` — what its output is stored in (``"float"``, ``"half"``, ``"unorm8"``): the rounding a reader adds
  to the per-pixel uncertainty (``half``: relative 2⁻¹¹; ``unorm8``: ±½ LSB uniform, σ = 1/(255·√12) of full scale);
* ``supports`` — the scene features it renders as the truth describes them (``"furnace"``, ``"directional"``,
  ``"point"``, ``"spot"``, ``"environment"``, ``"rect"``, ``"textures"``, ``"perspective"`` …); scenes needing a
  feature it lacks are reported as skipped with the reason, never silently dropped;
* ``shadow_types`` — the shadow filters it offers (``"hard"``, ``"pcf"``, ``"pcss"``, ``"vsm"`` …);
* ``defects`` — what it is known to get wrong → where that is stated (an upstream issue number or a manual page).
  The renders claims look their topics up here (``"furnace"``, ``"probe_lambert"``, ``"spot.khr_falloff"``,
  ``"rect_plane"``, ``"shadows.<type>.umbra"`` …: ``docs/engines.md``): a topic present is claimed as the regression
  the engine keeps (its power check the corrected behaviour), a topic absent as the behaviour the truth asks for;
* ``lacks`` — a scene feature it does not render → why (the skip reason a report shows);
* ``notes`` — a scene feature it renders with a stated substitution → the label (travels with the report row);
* ``variant_of`` / ``with_kinds`` — a variant of another engine (its product is that engine's) rendered beside it
  for the scene kinds named (three's ``three_probe`` for the hemisphere light); a variant with no kinds renders
  only where it is asked for by name (Babylon's CDF irradiance sizes).

An engine that renders in this process implements :meth:`Engine.render` (one :class:`RenderScene` in, an
:class:`EngineRender` out: the ``renders`` experiment's path). Its images are cached by :meth:`Engine.cache_parts`
(the engine's name, version and own sources, the scene's content and the engine's options) in the reference cache,
so a warm run does not render again what has not changed.

An engine that renders the exported scene files (``python -m validate scenes export``: ``manifest.json`` and one
``.glb`` per scene) implements :meth:`Engine.render_folder`: it renders the named scenes of a folder and writes, into
``out_dir``, the files the manifest asks for (``<scene>.exr``: linear radiance, float or half, alpha = coverage) —
exactly what an outside team hands to ``python -m validate judge``.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

PRECISIONS = ("float", "half", "unorm8")


@dataclass(frozen=True)
class Unavailable:
    """A runtime an engine needs that this machine lacks: what it is, why, and the command that installs it."""

    piece: str
    why: str
    fix: str


@dataclass
class FolderRender:
    """What :meth:`Engine.render_folder` wrote: scene → image file, and what the run measured."""

    version: str
    images: dict[str, Path]  # scene name → the image file written (``<out_dir>/<scene>.exr``)
    skipped: dict[str, str] = field(default_factory=dict)  # scene name → why the engine did not render it
    frame_ms: dict[str, float] = field(default_factory=dict)  # scene name → the engine's own frame time
    startup_s: float = 0.0  # starting the engine's process or page, once for the batch
    wall_s: float = 0.0  # the whole batch, start to finish
    info: dict[str, dict] = field(default_factory=dict)  # scene name → what the engine reported besides pixels


@dataclass
class EngineRender:
    """One in-process render (:meth:`Engine.render`): the image and what the run measured."""

    image: np.ndarray  # (R, R, 4) float32, row 0 = top, alpha = coverage
    frame_ms: float
    wall_s: float
    version: str
    info: dict = field(default_factory=dict)  # what the engine reports besides pixels (e.g. three's light.power)
    stderr: float = 0.0  # the readback's own standard uncertainty per value (radiance; 0 for a float target)


@dataclass(frozen=True)
class Engine:
    """One engine under test (module docstring)."""

    name: str
    product: str
    precision: str
    supports: tuple[str, ...]
    shadow_types: tuple[str, ...] = ()
    defects: dict[str, str] = field(default_factory=dict)
    lacks: dict[str, str] = field(default_factory=dict)  # scene feature → why the engine does not render it
    notes: dict[str, str] = field(default_factory=dict)  # scene feature → the substitution it renders it with
    variant_of: str = ""  # the engine this one is a variant of (its product), "" for none
    with_kinds: tuple[str, ...] = ()  # a variant: the scene kinds it renders beside ``variant_of``
    # facts the claims read besides defects: "spot_reference" (the reference of the spot profile it implements),
    # "rect_units" (where its area light's unit is stated), "<topic>.corrected_by" (the engine, or "truth", whose
    # image is the corrected behaviour of a defect), "shadows.<type>.penumbra" ("wider" / "narrower")
    facts: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.precision not in PRECISIONS:
            raise ValueError(f"engine {self.name}: precision {self.precision!r} is not one of {PRECISIONS}")

    def version(self) -> str | None:
        """The installed version, or None when the engine is not installed (cheap: starts nothing)."""
        return None

    def unavailable(self) -> Unavailable | None:
        """Why the engine cannot render on this machine, or None when it can."""
        return None

    def skip_reason(self, features: Sequence[str]) -> str | None:
        """Why the engine does not render a scene needing ``features`` (its ``lacks``), or None when it does."""
        return next((self.lacks[f] for f in features if f in self.lacks), None)

    def pages(self) -> tuple[str, ...]:
        """Pages of the run's browser the engine renders in (opened ahead, side by side: :func:`validate.gl.
        browser_page.preload`); () for an engine without one."""
        return ()

    def render(self, scene: Any) -> EngineRender:
        """Render one scene in this process (a ``RenderScene`` of :mod:`validate.scenes`); raises with the reason
        when the engine cannot run."""
        raise NotImplementedError(f"engine {self.name} renders no scene in this process")

    def sources(self) -> tuple[Path, ...]:
        """The files whose content decides the engine's pixels besides its version (its page, script, module)."""
        return ()

    def cache_parts(self, scene: Any) -> dict[str, Any] | None:
        """What one cached image of ``scene`` is keyed by — the engine's name, version and own sources, the scene's
        content — or None when it is not cached (no version known)."""
        version = self.version()
        if version is None:
            return None
        digest = hashlib.sha256()
        for p in self.sources():
            digest.update(p.name.encode() + b"\0" + p.read_bytes())
        content = scene.engine_json() if hasattr(scene, "engine_json") else repr(scene)
        return {"engine": self.name, "version": version, "sources": digest.hexdigest()[:16],
                "scene": hashlib.sha256(json.dumps(content, sort_keys=True, default=repr).encode()).hexdigest()}

    def render_folder(self, scenes_dir: Path, names: Sequence[str], out_dir: Path) -> FolderRender:
        """Render the scenes ``names`` of the exported folder ``scenes_dir`` into ``out_dir`` (module docstring)."""
        raise NotImplementedError(f"engine {self.name} renders no scene files")


__all__ = ["Engine", "EngineRender", "FolderRender", "Unavailable", "PRECISIONS"]
