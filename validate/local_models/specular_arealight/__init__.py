"""The ``specular_arealight`` family: GGX specular from area lights (rectangle, disc, sphere, tube).

One technique per module of this folder; the contract is
:data:`validate.local_models.families.specular_arealight`. A new built-in is one new file here that registers
with ``@specular_arealight.register(...)`` (``from ..families import specular_arealight``): it is found by
walking this folder. Shared code of the family, which registers nothing: common (the GGX parameters of the
family's brdf mapping). A technique never imports a sibling technique. Registration order (tables,
``results.json``): the modules alphabetically.
This package stands for the family (:class:`~validate.local_models.registry.FamilyPackage`).
"""

from __future__ import annotations

from ..families import specular_arealight
from ..registry import family_package

family_package(__name__, specular_arealight)
