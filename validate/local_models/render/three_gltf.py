"""``three_gltf``: three.js 0.187 rendering the exported scene files through its own loaders.

``GLTFLoader`` reads the ``.glb`` (MeshStandardMaterial, or MeshPhysicalMaterial where ``KHR_materials_specular``
is used; its KHR_lights_punctual lights; the glTF camera), ``EXRLoader`` (float) the environment, set as
``scene.environment`` (the renderer's PMREM) turned by ``scene.environmentRotation`` about +y so that the image
centre faces +z as the manifest states (three's equirect lookup faces +x there). Tone mapping off, linear output,
a FloatType target: float radiance, alpha = coverage (``three_gltf.mjs``; :mod:`.gltf_page`).
"""

from __future__ import annotations

import math

from .gltf_page import GltfPageEngine

ENGINE = GltfPageEngine(
    name="three_gltf", product="three.js", precision="float",
    supports=("furnace", "environment", "directional", "point", "spot", "perspective", "textures"),
    shadow_types=(), page="three_gltf.html", packages=("three",),
    options={"envRotationY": -math.pi / 2, "shadows": True},
    defects={"spot cone": "SpotLight's penumbra is a smoothstep between the cones, not KHR_lights_punctual's "
                          "quadratic falloff (GLTFLoader maps penumbra = 1 − inner/outer)"})

__all__ = ["ENGINE"]
