"""``python -m validate``: :func:`validate.cli.main`, with SIGINT/SIGTERM handled from the first line
(:mod:`validate.interrupt`), and an interrupted run ended at once: child processes (Node, Chromium,
Dask workers) are ended and slow exit handlers skipped."""

import os
import sys

from .interrupt import Interrupted, announce, end_children, install

undo = install()  # before the heavy imports: a signal while they run is one line too
try:
    from .cli import main

    code = main()
except Interrupted as exc:
    announce(exc.signum)
    code = 128 + exc.signum
finally:
    undo()
if code in (130, 143):
    end_children()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
raise SystemExit(code)
