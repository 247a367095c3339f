"""The ``arealight`` family: diffuse irradiance from a sphere or disc light.

One technique per module of this folder; the contract is :data:`validate.local_models.families.arealight`. A new
built-in is one new file here that registers with ``@arealight.register(...)`` (``from ..families import
arealight``): it is found by walking this folder. Shared code of the family, which registers nothing: sphere_cap
(the cap closed form and the light geometry, also used by the shadow family). A technique never imports a
sibling technique. Registration order (tables, ``results.json``): the modules alphabetically.
This package stands for the family (:class:`~validate.local_models.registry.FamilyPackage`).
"""

from __future__ import annotations

from ..families import arealight
from ..registry import family_package

family_package(__name__, arealight)
