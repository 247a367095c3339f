"""The command line (``python -m validate``): :mod:`.commands` parses the arguments and dispatches (a ``run``/``all``
to :mod:`validate.run`, ``bench`` to :mod:`validate.bench`); :mod:`.worst` is the ``worst`` command."""

from ..run.plugins import load_plugin
from .commands import main

__all__ = ["load_plugin", "main"]
