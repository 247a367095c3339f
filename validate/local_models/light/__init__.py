"""The ``light`` family: classic punctual and area lights: irradiance E at each receiver.

One technique per module of this folder; the contract is :data:`validate.local_models.families.light`. A new
built-in is one new file here that registers with ``@light.register(...)`` (``from ..families import light``):
it is found by walking this folder. Shared code of the family, which registers nothing: common (light checks,
the shadow-ray hook, the point-light irradiance). A technique never imports a sibling technique. Registration
order (tables, ``results.json``): the modules alphabetically.
This package stands for the family (:class:`~validate.local_models.registry.FamilyPackage`).
"""

from __future__ import annotations

from ..families import light
from ..registry import family_package

family_package(__name__, light)
