"""The ``specular`` family: specular image-based lighting: outgoing radiance of an environment through a BRDF.

One technique per module of this folder; the contract is :data:`validate.local_models.families.specular`. A new
built-in is one new file here that registers with ``@specular.register(...)`` (``from ..families import
specular``): it is found by walking this folder. Shared code of the family, which registers nothing: common
(reflection, map sizing, the map cache). A technique never imports a sibling technique. Registration order
(tables, ``results.json``): the modules alphabetically.
This package stands for the family (:class:`~validate.local_models.registry.FamilyPackage`).
"""

from __future__ import annotations

from ..families import specular
from ..registry import family_package

family_package(__name__, specular)
