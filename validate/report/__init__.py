"""The report: ``results.json`` and the HTML pages rendered from it (:mod:`.html`), and the comparison of two runs
(:mod:`.compare`). The figures experiments draw live below, in :mod:`validate.figures`.

What a page opens with is read from results.json alone: the summary figure and verdict of each
experiment (:mod:`.summary`, drawn by :mod:`.summary_plots`), findings grouped under headings
(:mod:`.findings`) and truth / technique / error image sets for the comparison widget
(:mod:`.imagesets`). Numbers are written by :mod:`validate.format`.

Importing this package loads nothing: the HTML layer (jinja2) comes in when one of its names is first asked for
(``validate.report.load_results`` …) or :mod:`.html` is imported, so :mod:`.compare` and :mod:`.summary` stay
light."""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["load_results", "render_report", "write_report", "write_results_json"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        return getattr(importlib.import_module(".html", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
