"""Judge a renderer per pixel against Mitsuba with ``check_render`` (issue 21).

``my_renderer`` here is an analytic Lambert shader (n·l·E·ρ/π at pixel centres) standing in for an engine:
replace it with a call into your engine that renders ``scene.engine_json()`` and returns linear radiance.

    /work/main/.venv/bin/python examples/check_my_renderer.py
"""

from __future__ import annotations

import numpy as np

from validate.scenes.render_scenes import RenderScene, lambert_sun_scene
from validate.testing_render import check_render


def my_renderer(scene: RenderScene) -> np.ndarray:
    """Lambert's law at each pixel centre of the orthographic camera: L = ρ E max(0, n·l)/π [PBR4 §4.3]."""
    x, y = scene.pixel_centres()
    r2 = x**2 + y**2
    n = np.stack([x, y, np.sqrt(np.clip(1.0 - r2, 0.0, 1.0))], axis=-1)
    img = np.zeros(x.shape + (4,))
    img[..., 3] = r2 < 1.0
    for light in scene.lights:
        cos = np.clip(n @ (-light.unit_direction()), 0.0, None)
        img[..., :3] += (light.intensity * cos / np.pi)[..., None] * np.asarray(scene.material.base_color)
    img[..., :3] *= img[..., 3:]
    return img


if __name__ == "__main__":
    for check in check_render(my_renderer, scenes=[(lambert_sun_scene(32), "directional")]):
        print(("PASS " if check.passed else "FAIL ") + check.summary())
