"""The ``uberlight`` family: Barzel's überlight (the Orange Book listing) and its variants: outgoing radiance.

One technique per module of this folder; the contract is :data:`validate.local_models.families.uberlight`. A new
built-in is one new file here that registers with ``@uberlight.register(...)`` (``from ..families import
uberlight``): it is found by walking this folder. Shared code of the family, which registers nothing: none (one
technique file). A technique never imports a sibling technique. Registration order (tables, ``results.json``):
the modules alphabetically.
This package stands for the family (:class:`~validate.local_models.registry.FamilyPackage`).
"""

from __future__ import annotations

from ..families import uberlight
from ..registry import family_package

family_package(__name__, uberlight)
