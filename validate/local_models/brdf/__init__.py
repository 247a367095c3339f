"""The ``brdf`` family: analytic BRDFs, cosine-weighted: f_r(l, v) max(0, n·l).

One technique per module of this folder; the contract is :data:`validate.local_models.families.brdf`. A new
built-in is one new file here that registers with ``@brdf.register(...)`` (``from ..families import brdf``): it
is found by walking this folder. Shared code of the family, which registers nothing: common (geometry, Fresnel,
microfacet D and G, the printed Cook–Torrance and Oren–Nayar terms). A technique never imports a sibling
technique. Registration order (tables, ``results.json``): the modules of ``first`` below, then the rest
alphabetically.
This package stands for the family (:class:`~validate.local_models.registry.FamilyPackage`).
"""

from __future__ import annotations

from ..families import brdf
from ..registry import family_package

family_package(__name__, brdf, first=("classic_brdfs", "brdf_multiscatter"))
