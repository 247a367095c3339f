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

An engine that renders the exported scene files (``python -m validate scenes export``: ``manifest.json`` and one
``.glb`` per scene) implements :meth:`Engine.render_folder`: it renders the named scenes of a folder and writes, into
``out_dir``, the files the manifest asks for (``<scene>.exr``: linear radiance, float or half, alpha = coverage) —
exactly what an outside team hands to ``python -m validate judge``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

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


@dataclass(frozen=True)
class Engine:
    """One engine under test (module docstring)."""

    name: str
    product: str
    precision: str
    supports: tuple[str, ...]
    shadow_types: tuple[str, ...] = ()
    defects: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.precision not in PRECISIONS:
            raise ValueError(f"engine {self.name}: precision {self.precision!r} is not one of {PRECISIONS}")

    def version(self) -> str | None:
        """The installed version, or None when the engine is not installed (cheap: starts nothing)."""
        return None

    def unavailable(self) -> Unavailable | None:
        """Why the engine cannot render on this machine, or None when it can."""
        return None

    def render_folder(self, scenes_dir: Path, names: Sequence[str], out_dir: Path) -> FolderRender:
        """Render the scenes ``names`` of the exported folder ``scenes_dir`` into ``out_dir`` (module docstring)."""
        raise NotImplementedError(f"engine {self.name} renders no scene files")


__all__ = ["Engine", "FolderRender", "Unavailable", "PRECISIONS"]
