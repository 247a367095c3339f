"""The ``irradiance`` family: irradiance from an environment map: E(n) = ∫ L max(0, n·ω) dω at each normal.

One technique per module of this folder; the contract is :data:`validate.local_models.families.irradiance`. A
new built-in is one new file here that registers with ``@irradiance.register(...)`` (``from ..families import
irradiance``): it is found by walking this folder. Shared code of the family, which registers nothing: sh (the
SH basis, projection and rendering), kernel_bounds (the near-directional bound), irradiance_map (cube and lat-
long irradiance maps, the zonal convolution the specular family also uses). A technique never imports a sibling
technique. Registration order (tables, ``results.json``): the modules of ``first`` below, then the rest
alphabetically.
This package stands for the family (:class:`~validate.local_models.registry.FamilyPackage`).
"""

from __future__ import annotations

from ..families import irradiance
from ..registry import family_package

family_package(__name__, irradiance,
               first=("sh_truncated", "cmgen_window", "engines", "hemisphere", "windowed_sh", "zh3"))
