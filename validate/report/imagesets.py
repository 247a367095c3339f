"""Truth / technique / error image sets found in a gallery row, for the page's comparison widget.

A gallery row (``report.sections[].gallery[]`` in results.json) is a set when it holds

* a **truth** image: path or caption names the ground truth ("reference", "truth", "quadrature");
* a **technique** image of exactly the same pixel size (read from the PNG header), which is not the
  truth and not an error map — the first such one in the row;
* an **error** map: path or caption says "error", "|z|", "diff" or "Δ" — the first one in the row.

Same size is required because the widget stacks the two images and wipes between them; an error map
of any size sits beside them, linked by a crosshair at the same relative position. A row without such
a set is drawn as a plain gallery.
"""

from __future__ import annotations

import re
import struct
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

_TRUTH = re.compile(r"reference|truth|quadrature", re.I)
_ERROR = re.compile(r"error|\|z\||diff|Δ|_z\.png$", re.I)
_PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def png_size(path: Path) -> tuple[int, int] | None:
    """(width, height) from a PNG's IHDR chunk; None when the file is absent or not a PNG."""
    try:
        with open(path, "rb") as f:
            head = f.read(24)
    except OSError:
        return None
    if len(head) < 24 or not head.startswith(_PNG_MAGIC) or head[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", head[16:24])


def _text(f: Mapping[str, Any]) -> str:
    return f"{Path(str(f.get('src', ''))).name} {f.get('caption', '')}"


def find_set(row: Sequence[Mapping[str, Any]], out_dir: Path) -> dict[str, Any] | None:
    """{"truth", "technique", "error", "rest"} from a row of page figures (html._figure dicts, which carry
    ``src`` relative to ``out_dir`` and ``exists``), or None when the row is not a set."""
    figs = [f for f in row if f.get("exists")]
    errors = [f for f in figs if _ERROR.search(_text(f))]
    truths = [f for f in figs if _TRUTH.search(_text(f)) and f not in errors]
    if not errors or not truths:
        return None
    truth, error = truths[0], errors[0]
    size = png_size(out_dir / str(truth["src"]))
    if size is None:
        return None
    for f in figs:
        if f is truth or f in errors or f in truths:
            continue
        if png_size(out_dir / str(f["src"])) == size:
            rest = [g for g in row if g is not truth and g is not f and g is not error]
            linked = png_size(out_dir / str(error["src"])) == size  # same pixels: a crosshair can follow
            return {"truth": truth, "technique": f, "error": error, "rest": rest,
                    "width": size[0], "height": size[1], "linked": linked}
    return None
