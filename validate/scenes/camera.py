"""The pinhole camera the path-traced scenes share (shadows, lights, überlight).

A perspective camera at ``origin`` looking at ``target`` with +y up (Mitsuba's ``look_at``),
horizontal field of view ``fov_deg``, ``width`` × ``height`` pixels and a box pixel filter, so that a
pixel's value is the mean radiance over its footprint — what per-pixel comparisons with a local
model shading the pixel centre's G-buffer assume. Scenes subclass it to set their own framing.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..errors import ValidateError

MIN_SIDE, MAX_SIDE = 8, 4096


@dataclass(frozen=True)
class PerspectiveCamera:
    origin: tuple[float, float, float]
    target: tuple[float, float, float]
    fov_deg: float  # horizontal
    width: int
    height: int

    def __post_init__(self) -> None:
        if not (MIN_SIDE <= self.width <= MAX_SIDE and MIN_SIDE <= self.height <= MAX_SIDE):
            raise ValidateError(f"camera resolution {self.width}×{self.height}: each side must be in "
                                f"[{MIN_SIDE}, {MAX_SIDE}]")

    def mitsuba(self) -> dict[str, Any]:
        """The Mitsuba ``perspective`` sensor dict (hdrfilm, box filter)."""
        import mitsuba as mi

        return {"type": "perspective", "fov": self.fov_deg, "fov_axis": "x",
                "to_world": mi.ScalarTransform4f().look_at(origin=list(self.origin), target=list(self.target),
                                                           up=[0.0, 1.0, 0.0]),
                "film": {"type": "hdrfilm", "width": self.width, "height": self.height, "rfilter": {"type": "box"}}}

    mitsuba_sensor = mitsuba
