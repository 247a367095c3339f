"""``filament_gltf``: Filament 1.53.4 (npm, WebAssembly) rendering the exported scene files through gltfio.

gltfio's ``AssetLoader`` reads the ``.glb`` — its ubershader materials, its ``KHR_lights_punctual`` lights as
gltfio converts them, the glTF camera — and the page only picks the exposure (8-bit canvas filled to 250 of 255),
turns shadows on and corrects gltfio's orthographic projection (``ORTHO_DEFECT``) (``filament_gltf.mjs``;
:mod:`.gltf_page`). Output: the canvas's RGBA8 (linear, post-processing off) decoded as q/(255·e), its
quantisation step written into the EXR for the judge. No environment: the npm package has no IBL prefilter (the
hand-built path's reason, :mod:`validate.experiments.renders.compute`).
"""

from __future__ import annotations

from .gltf_page import GltfPageEngine

NO_IBL = ("Filament 1.53.4's npm package has no IBL prefilter (cmgen/libibl are not in the WebAssembly build): "
          "an environment file cannot go through Filament's own pipeline")

# measured (renders.loaders): gltfio's projection for the exported orthographic camera (xmag = ymag = 1.1) was
# diag(2/1.1, 2/1.1, …): xmag read as the full width, the image at twice glTF's magnification (glTF 2.0 §3.10.3,
# "Orthographic projection": x scaled by 1/xmag). The page sets glTF's projection from the file's own camera.
ORTHO_DEFECT = ("gltfio reads an orthographic camera's xmag/ymag as the full width/height (projection 2/xmag, glTF "
                "2.0 §3.10.3 says 1/xmag): twice the magnification; filament_gltf.mjs sets glTF's projection")

ENGINE = GltfPageEngine(
    name="filament_gltf", product="Filament", precision="unorm8",
    supports=("directional", "point", "spot", "perspective", "textures"), shadow_types=("pcf",),
    page="filament_gltf.html", packages=("filament",), options={"shadows": True, "orthoHalfExtent": True},
    skip_reasons={"environment": NO_IBL},
    defects={"orthographic camera": ORTHO_DEFECT})

__all__ = ["ENGINE"]
