"""The report: ``results.json`` and the HTML pages rendered from it (:mod:`.html`), and the figure
helpers experiments use to draw into it (:mod:`.plots`, imported on demand: it loads matplotlib).

What a page opens with is read from results.json alone: the summary figure and verdict of each
experiment (:mod:`.summary`, drawn by :mod:`.summary_plots`), findings grouped under headings
(:mod:`.findings`) and truth / technique / error image sets for the comparison widget
(:mod:`.imagesets`). Numbers are written by :mod:`validate.format`."""

from __future__ import annotations

from .html import load_results, render_report, write_report, write_results_json

__all__ = ["load_results", "render_report", "write_report", "write_results_json"]
