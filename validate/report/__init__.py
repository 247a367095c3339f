"""The report: ``results.json`` and the one-page HTML rendered from it (:mod:`.html`), and the figure
helpers experiments use to draw into it (:mod:`.plots`, imported on demand: it loads matplotlib)."""

from __future__ import annotations

from .html import load_results, render_report, write_report, write_results_json

__all__ = ["load_results", "render_report", "write_report", "write_results_json"]
