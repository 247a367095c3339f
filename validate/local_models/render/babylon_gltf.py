"""``babylon_gltf``: Babylon.js rendering the exported scene files through ``@babylonjs/loaders``.

The glTF loader (``SceneLoader.ImportMeshAsync``) reads the ``.glb`` into a right-handed scene — its PBRMaterials,
``KHR_lights_punctual`` lights, the glTF camera — and core's ``EXRCubeTexture`` the environment file, turned by
``rotationY`` so that the image centre faces +z as the manifest states. Image processing off (no tone mapping,
exposure 1), a float render target: float radiance, alpha = coverage (``babylon_gltf.mjs``; :mod:`.gltf_page`).
``@babylonjs/loaders`` 9.28.0 beside ``@babylonjs/core`` 9.35.0: 9.28.0 is the newest loaders release the registry
offered (its peer dependency: core ^9.0.0).
"""

from __future__ import annotations

import math

from .gltf_page import GltfPageEngine

ENGINE = GltfPageEngine(
    name="babylon_gltf", product="Babylon.js", precision="float",
    supports=("furnace", "environment", "directional", "point", "spot", "perspective", "textures"),
    page="babylon_gltf.html", packages=("@babylonjs/core", "@babylonjs/loaders"),
    options={"envRotationY": math.pi})

__all__ = ["ENGINE"]
