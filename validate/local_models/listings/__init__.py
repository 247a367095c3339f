"""The seeds' lighting listings and printed equations as techniques (index: ``docs/listings.md``).

:mod:`.catalog` holds every listing (text as printed in ``shaders/``, glue, edits);
:mod:`validate.gl.listing_harness` runs a vertex + fragment pair unchanged. The techniques that run
them are files of their family folders (``light/redbook_lights.py``, ``brdf/ganovelli_cook_torrance.py``,
``uberlight/orange_uberlight.py``, …); GLSL-backed ones register only where the compatibility runtime
starts (:mod:`.runner`). This package registers nothing.
"""

from __future__ import annotations
