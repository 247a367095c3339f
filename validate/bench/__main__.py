"""The bench's child process: ``python -m validate.bench TASK HEIGHT`` prints one JSON record
(:func:`validate.bench.kernels.child`)."""

import json
import sys

from .kernels import child

print(json.dumps(child(sys.argv[1], int(sys.argv[2]))))
