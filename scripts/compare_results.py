"""Compare two ``results.json`` files number for number, ignoring timings and ``meta``.

    python scripts/compare_results.py BASELINE/results.json NEW/results.json [--text]

Prints one line per difference (JSON path, then the two values) and exits 1 if there is any; prints nothing
and exits 0 when the files agree. Ignored: the top-level ``meta`` object and every key that names a timing
(``wall_time_s``, ``*_seconds``, ``*_time``, ``*_time_s``, ``elapsed*``, ``build_seconds``). Compared: the
structure (keys, list lengths) and every number, bool and null — claims (measured, uncertainty, threshold,
passed, power), measured values, technique metrics, settings — exactly (the run is deterministic: same seeds,
same reference cache). Strings (findings, claim sources, report text, technique module paths) only with
``--text``: they legitimately change when code moves (a technique's ``module``, a source naming a module).
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path
from typing import Any

TIMING = re.compile(r"(^wall_time_s$|_seconds$|_time$|_time_s$|^elapsed|^build_seconds$)")
MAX_LINES = 200


def _differences(a: Any, b: Any, path: str, text: bool = False) -> list[str]:
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b), key=str):
            if TIMING.search(str(k)):
                continue
            if k not in a or k not in b:
                out.append(f"{path}/{k}: {'missing' if k not in a else 'present'} → "
                           f"{'missing' if k not in b else 'present'}")
                continue
            out += _differences(a[k], b[k], f"{path}/{k}", text)
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: length {len(a)} → {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b, strict=True)) for d in _differences(x, y, f"{path}[{i}]", text)]
    if isinstance(a, str) and isinstance(b, str) and not text:
        return []
    if a != b and not (isinstance(a, float) and isinstance(b, float) and a != a and b != b):
        return [f"{path}: {str(a)[:120]!r} → {str(b)[:120]!r}"]
    return []


def compare(baseline: Path, new: Path, text: bool = False) -> list[str]:
    """Every difference between the two results files outside ``meta`` and the timings (strings with ``text``)."""
    a, b = (json.loads(p.read_text()) for p in (baseline, new))
    a.pop("meta", None)
    b.pop("meta", None)
    return _differences(a, b, "", text)


def main(argv: list[str]) -> int:
    text = "--text" in argv
    files = [a for a in argv if a != "--text"]
    if len(files) != 2:
        print("usage: compare_results.py BASELINE/results.json NEW/results.json [--text]", file=sys.stderr)
        return 2
    diffs = compare(Path(files[0]), Path(files[1]), text)
    for line in diffs[:MAX_LINES]:
        print(line)
    if len(diffs) > MAX_LINES:
        print(f"… {len(diffs) - MAX_LINES} more")
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
