"""The ``shadow`` family: shadow-map visibility V′ ∈ [0, 1] of a disc light.

One technique per module of this folder; the contract is :data:`validate.local_models.families.shadow`. A new
built-in is one new file here that registers with ``@shadow.register(...)`` (``from ..families import shadow``):
it is found by walking this folder. Shared code of the family, which registers nothing: shadow_map (the depth
map, its lookups and the filter footprint of the filterable maps). A technique never imports a sibling
technique. Registration order (tables, ``results.json``): the modules alphabetically.
This package stands for the family (:class:`~validate.local_models.registry.FamilyPackage`).
"""

from __future__ import annotations

from ..families import shadow
from ..registry import family_package

family_package(__name__, shadow)
