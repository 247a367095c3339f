"""``python -m validate``: :func:`validate.cli.main`, with SIGINT/SIGTERM handled from the first line
(:mod:`validate.run.interrupt`), and an interrupted run ended at once: child processes (Node, Chromium,
Dask workers) are ended and slow exit handlers skipped."""

import os
import sys

try:  # the handlers first, before the heavy imports: a signal while they run is one line too
    from .run.interrupt import Interrupted, announce, end_children, install

    undo = install()
except BaseException as exc:  # SIGINT in the milliseconds before the handlers were in place
    if not isinstance(exc, KeyboardInterrupt) and type(exc).__name__ != "Interrupted":
        raise
    signum = getattr(exc, "signum", 2)
    print(f"validate: interrupted by {'SIGTERM' if signum == 15 else 'SIGINT'}; nothing was written",
          file=sys.stderr, flush=True)
    os._exit(128 + signum)
try:
    from .run.process import tune

    tune()  # before numpy loads: OpenBLAS reads its settings once (inherited by the lane and the Dask workers)
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
