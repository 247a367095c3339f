"""The seeds' lighting listings and printed equations as techniques (index: ``docs/listings.md``).

:mod:`.catalog` holds every listing (text as printed in ``shaders/``, glue, edits);
:mod:`validate.gl.listing_harness` runs a vertex + fragment pair unchanged. One module per listing or
printed equation; each registers its techniques in the existing families (``light``, ``brdf``,
``uberlight``); GLSL-backed ones only where the compatibility runtime starts (:mod:`.runner`).
"""

from __future__ import annotations

import importlib
import pkgutil

_NOT_TECHNIQUES = {"catalog", "runner"}

for _mod in pkgutil.iter_modules(__path__):
    if _mod.name not in _NOT_TECHNIQUES and not _mod.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_mod.name}")
