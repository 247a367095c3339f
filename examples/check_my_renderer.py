"""Judge a renderer per pixel against Mitsuba with ``check_render`` (issue 21).

``my_renderer`` here is an analytic Lambert shader standing in for an engine (a directional light: n·l·E·ρ/π;
a KHR_lights_punctual point or spot light: ρ/π · I f(θ) n·l / d², inverse square, no range) at pixel centres:
replace it with a call into your engine that renders ``scene.engine_json()`` and returns linear radiance.

    /work/main/.venv/bin/python examples/check_my_renderer.py
"""

from __future__ import annotations

import numpy as np

from validate.scenes.render_scenes import DirectionalLight, RenderScene, SpotLight, lambert_sun_scene, punctual_scenes
from validate.testing import check_render


def my_renderer(scene: RenderScene) -> np.ndarray:
    """Lambert's law at each pixel centre of the orthographic camera: L = ρ E max(0, n·l)/π [PBR4 §4.3, §12.1]."""
    p = scene.surface_points()
    hit = scene.hit_mask()
    n = p if scene.geometry == "sphere" else np.broadcast_to([0.0, 0.0, 1.0], p.shape)
    img = np.zeros(hit.shape + (4,))
    img[..., 3] = hit
    for light in scene.lights:
        if isinstance(light, DirectionalLight):
            e = light.intensity * np.clip(n @ (-light.unit_direction()), 0.0, None)
        else:  # point or spot, candela at ``position``
            v = np.asarray(light.position) - p
            d = np.linalg.norm(v, axis=-1)
            f = light.falloff((-v / d[..., None]) @ light.unit_direction()) if isinstance(light, SpotLight) else 1.0
            e = light.intensity * f * np.clip((n * v).sum(-1) / d, 0.0, None) / d**2
        img[..., :3] += np.nan_to_num(e / np.pi)[..., None] * np.asarray(scene.material.base_color)
    img[..., :3] *= img[..., 3:]
    return img


if __name__ == "__main__":
    point_plane, _, spot_plane = punctual_scenes(32)
    for check in check_render(my_renderer, scenes=[(lambert_sun_scene(32), "directional"), (point_plane, "point"),
                                                   (spot_plane, "spot")]):
        print(("PASS " if check.passed else "FAIL ") + check.summary())
