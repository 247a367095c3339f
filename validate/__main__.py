import os
import sys

from .cli import main
from .interrupt import end_children

code = main()
if code in (130, 143):  # interrupted: end child processes (Node, Chromium, Dask) and skip slow atexit work
    end_children()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
raise SystemExit(code)
