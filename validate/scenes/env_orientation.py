"""Where an equirect environment's texels point, in glTF's frame, and the turned variants a judge tries.

The suite's equirect maps (:mod:`validate.scenes.render_scenes`, ``Environment.texels``; the probes' convention)
put texel (i, j) of an H × W map (row i from the top, column j from the left) at the direction of its centre

    θ = π(i + ½)/H,  φ = 2π(j + ½)/W,  d = (sin φ sin θ, cos θ, −cos φ sin θ)

in the scene's world, which is glTF's (right-handed, +y up; a glTF asset's front faces +z). So row 0 is the zenith
(+y), the left edge (φ = 0) faces −z, a quarter across faces +x, the image centre faces +z — towards the camera at
(0, 0, 5): a mirror sphere shows the image centre at its own centre — and three quarters across −x. Seen from
inside the sphere of directions, facing the image centre with +y up, the image's right half is on the viewer's
right (−x): the panorama is not mirrored. This is Mitsuba 3's ``envmap`` with an identity ``to_world``
(its lookup u = atan2(d_x, −d_z)/2π, v = acos(d_y)/π; ``tests/infra/test_scene_files.py`` measures it with
``emitter.eval``). three.js and Babylon.js read u = atan2(d_z, d_x)/2π + ½ instead: their image centre faces +x,
so the suite's own pages roll the columns by W/4 (:func:`validate.scenes.render_scenes.engine_texels`).

Variants (:data:`VARIANTS`): what an engine that reads the panorama in another convention shows. A right-handed
turn about +y by α takes the texel at φ to φ − α (d = −z, φ = 0, turned by +90° about +y is −x, φ = 3π/2), i.e. the
columns roll by −αW/2π; the x mirror (d → (−d_x, d_y, d_z)) is φ → −φ, the columns reversed; upside down
(d → (d_x, −d_y, d_z)) the rows reversed.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from ..errors import ValidateError
from .render_scenes import Environment, HemisphereLight, RenderScene

ORIENTATION: dict[str, Any] = {
    "projection": "equirectangular (latitude-longitude), row 0 = top",
    "frame": "glTF world: right-handed, +y up, metres; the environment is not rotated",
    "texel_direction": "texel (i, j) of H x W (row i from the top, column j from the left): theta = pi (i + 1/2) / H, "
                       "phi = 2 pi (j + 1/2) / W, d = (sin phi sin theta, cos theta, -cos phi sin theta)",
    "top_row_faces": [0.0, 1.0, 0.0],
    "left_edge_faces": [0.0, 0.0, -1.0],
    "quarter_width_faces": [1.0, 0.0, 0.0],
    "centre_faces": [0.0, 0.0, 1.0],
    "three_quarter_width_faces": [-1.0, 0.0, 0.0],
    "handedness": "not mirrored: seen from inside, facing the image centre (+z) with +y up, the image's right half "
                  "is on the viewer's right (-x)",
    "same_as": "Mitsuba 3 envmap with an identity to_world",
    "three_js_babylon": "their equirect lookup faces +x at the image centre: roll the columns by +W/4 "
                        "(numpy.roll(texels, W // 4, axis=1)) to match, as the suite's own engine pages do",
    "sampling": "bilinear between texel centres, wrapping in phi, clamped at the poles",
}

# name → (a description, the texel transform); the hemisphere light (azimuth-independent) has only "upside down"
VARIANTS = ("turned +90° about +y", "turned 180° about +y", "turned −90° about +y", "mirrored in x", "upside down")


def texel_direction(i: np.ndarray | float, j: np.ndarray | float, height: int, width: int) -> np.ndarray:
    """(…, 3) direction of the centre of texel (row i, column j) (module docstring)."""
    th = np.pi * (np.asarray(i, np.float64) + 0.5) / height
    ph = 2.0 * np.pi * (np.asarray(j, np.float64) + 0.5) / width
    return np.stack([np.sin(ph) * np.sin(th), np.cos(th), -np.cos(ph) * np.sin(th)], axis=-1)


def turned_texels(texels: np.ndarray, variant: str) -> np.ndarray:
    """The (H, W, 3) map as the ``variant`` of :data:`VARIANTS` shows it (module docstring; W a multiple of 4)."""
    t = np.asarray(texels)
    w = t.shape[1]
    if variant.startswith("turned") and w % 4:
        raise ValidateError(f"environment texels: width {w} is not a multiple of 4 (a quarter turn)")
    rolls = {"turned +90° about +y": -w // 4, "turned 180° about +y": w // 2, "turned −90° about +y": w // 4}
    if variant in rolls:
        return np.roll(t, rolls[variant], axis=1)
    if variant == "mirrored in x":
        return t[:, ::-1]
    if variant == "upside down":
        return t[::-1]
    raise ValidateError(f"environment variant {variant!r} not one of {VARIANTS}")


def variants_of(scene: RenderScene) -> list[str]:
    """The variants that change what ``scene`` looks like: none for a constant environment, "upside down" for a
    hemisphere light (symmetric about y), all of them for an equirect map."""
    if any(isinstance(li, HemisphereLight) for li in scene.lights):
        return ["upside down"]
    if scene.environment is not None and scene.environment.texels is not None:
        return list(VARIANTS)
    return []


def turned_scene(scene: RenderScene, variant: str) -> RenderScene:
    """``scene`` with its environment as ``variant`` shows it (its name tagged, so its reference is cached apart)."""
    lights = tuple(HemisphereLight(li.ground, li.sky) if isinstance(li, HemisphereLight) and variant == "upside down"
                   else li for li in scene.lights)
    env = scene.environment
    if env is not None and env.texels is not None:
        env = Environment(f"{env.name}:{variant}", env.radiance, turned_texels(env.texels, variant))
    return replace(scene, name=f"{scene.name} [{variant}]", lights=lights, environment=env)
