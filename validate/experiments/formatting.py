"""The experiments' per-cent ± forms for findings and section tables, on top of :mod:`validate.format`
(the one number-formatting module: :func:`~validate.format.pct`, :func:`~validate.format.pct_fixed` and the
table-header form :func:`~validate.format.col` are re-exported from it)."""

from __future__ import annotations

import math

from ..format import col, pct, pct_fixed


def _missing(x: float | None) -> bool:
    return x is None or not math.isfinite(float(x))


def pm(value: float | None, uncertainty: float | None, digits: int = 3, fixed: bool = False) -> str:
    """A value ± its uncertainty, both as per cent: :func:`pct` (``digits`` significant digits) or, with ``fixed``,
    :func:`pct_fixed` (``digits`` decimals): 0.0086, 0.0004 → "0.86 % ± 0.04 %"; a missing value → "—"."""
    f = pct_fixed if fixed else pct
    return "—" if _missing(value) else f"{f(value, digits)} ± {f(uncertainty, digits)}"


def pm_entry(entry: dict[str, float] | None) -> str:
    """A ``{"value", "uncertainty"}`` entry with one per-cent sign, value to 3 and uncertainty to 2 significant
    digits: "0.86 ± 0.041 %"; None or empty → "—"."""
    if not entry:
        return "—"
    return f"{100 * entry['value']:.3g} ± {100 * entry['uncertainty']:.2g} %"


__all__ = ["col", "pct", "pct_fixed", "pm", "pm_entry"]
