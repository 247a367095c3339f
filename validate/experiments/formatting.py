"""Number formatting for findings and report tables, shared by every experiment."""

from __future__ import annotations

import math


def _missing(x: float | None) -> bool:
    return x is None or not math.isfinite(float(x))


def pct(x: float | None, digits: int = 3) -> str:
    """A fraction as per cent with ``digits`` significant digits: 0.0086 → "0.86 %"; None/NaN → "—"."""
    return "—" if _missing(x) else f"{100 * float(x):.{digits}g} %"


def pct_fixed(x: float | None, digits: int = 2) -> str:
    """A fraction as per cent with ``digits`` decimals: 0.0086 → "0.86 %"; None/NaN → "n/a"."""
    return "n/a" if _missing(x) else f"{100 * float(x):.{digits}f} %"
