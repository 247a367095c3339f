"""Units on every column of the report's own pages (issue 23): the tables validate/report/ renders around the
experiments' sections — claims, techniques, settings, the overview, "changes since", the bench tables.

``tests/infra/test_table_units.py`` reads the experiments' ``Table(...)`` headers in their source; these tables are
written by the templates and by ``validate/bench/``, so they are checked where a reader sees them: pages rendered
(:func:`validate.report.html.render_pages`, no figures drawn) from a small results dict holding every kind of table,
a ``changes`` entry and a ``bench.json`` built by the bench modules' own ``tables`` from made-up records (nothing is
measured). Every ``<th>`` of every ``<table>`` must name its unit or be a column of words
(:func:`validate.format.missing_units`). Cheap: well under a second.
"""

from __future__ import annotations

import json
from html.parser import HTMLParser
from pathlib import Path

from validate.bench import fits as bench_fits
from validate.bench import gl_runtimes as bench_gl
from validate.bench import kernels as bench
from validate.format import missing_units
from validate.report.html import render_pages


class _Tables(HTMLParser):
    """The ``<th>`` texts of each ``<table>`` of a page, and the ``<td class="unit">`` cells."""

    def __init__(self) -> None:
        super().__init__()
        self.tables: list[list[str]] = []
        self.units: list[str] = []
        self._cell: str | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "table":
            self.tables.append([])
        elif tag == "th":
            self._cell, self._kind = "", "th"
        elif tag == "td" and ("class", "unit") in attrs:
            self._cell, self._kind = "", "unit"

    def handle_endtag(self, tag: str) -> None:
        if tag in ("th", "td") and self._cell is not None:
            (self.tables[-1] if self._kind == "th" else self.units).append(self._cell.strip())
            self._cell = None

    def handle_data(self, data: str) -> None:
        if self._cell is not None:
            self._cell += data


def _parse(text: str) -> _Tables:
    p = _Tables()
    p.feed(text)
    return p


def _claim(cid: str, unit: str, measured: float) -> dict:
    return {"id": cid, "description": "d", "metric": "max |E − E_ref| / E_ref", "threshold": 0.05,
            "measured": measured, "uncertainty": 0.001, "comparison": "<", "unit": unit, "source": "s",
            "power": {"perturbation": "E × 1.1", "measured": 0.1, "fails": True, "uncertainty": 0.001}}


def _bench_tables() -> list[dict]:
    kernels = [{"task": "SH projection l≤2", "projection_s": 0.01, "plain_reduction_s": 0.008, "ratio_to_plain": 1.25,
                "plain_drjit_sum_s": 0.001, "direct_drjit_s": 0.2},
               {"task": "SH9 irradiance", "drjit_s": 0.002, "numpy_s": 0.01, "speedup": 5.0}]
    sizes = [{"task": "reference", "height": 1024, "width": 2048, "seconds": 3.0, "peak_rss_mib": 900.0,
              "convergence": 1e-4},
             {"task": "sh9", "height": 1024, "width": 2048, "seconds": 0.5, "peak_rss_mib": 400.0,
              "projection_s": 0.05, "plain_reduction_s": 0.04, "drjit_sum_s": 0.003}]
    starts = [{"kind": "egl", "import_s": 0.1, "start_s": 0.2, "first_compile_s": 0.05, "renderer": "llvmpipe",
               "version": "4.5"}]
    per = [{"family": "irradiance", "glsl": "glsl_sh9", "python": "sh9", "glsl_ns_per_receiver": 50.0,
            "python_ns_per_receiver": 20.0, "ratio": 2.5}]
    fits = [{"fit": "LTC entry (L³ error)", "data": "r = 0.5", "scipy_s": 0.1, "scipy_residual": 1e-3, "ad_s": 0.05,
             "ad_residual": 1e-3, "time_ratio": 0.5, "residual_ratio": 1.0, "matched": True,
             "experiment_uses": "scipy", "residual_unit": "sr⁻²"}]
    return bench.tables(kernels, sizes) + bench_gl.tables(starts, per) + bench_fits.tables(fits)


def _results() -> dict:
    exp = {"title": "E", "wall_time_s": 245.3, "settings": {"beta_step_deg": 10.0, "meter_spp": 16, "cells": 64},
           "claims": [_claim("e.pct", "%", 0.01), _claim("e.ratio", "", 0.02)],
           "techniques": {"sh9": {"family": "irradiance", "description": "SH9", "builtin": True,
                                  "thresholds": {"flux_rgb.max": 0.05}}},
           "report": {"sections": [{"title": "S", "tables": [
               {"headers": ["technique", "max (%)"], "rows": [["sh9", 0.1]]}]}]}}
    changes = {"baseline": "old", "regressions": 1, "rows": [
        {"kind": "claim", "key": "e.pct", "old": 0.01, "new": 0.02, "old_uncertainty": 0.001,
         "new_uncertainty": 0.001, "change": 0.01, "exceeds_uncertainty": True, "status": "regressed"},
        {"kind": "metric", "key": "e/sh9/flux_rgb.max", "old": 0.01, "new": 0.009, "old_uncertainty": None,
         "new_uncertainty": None, "change": -0.001, "exceeds_uncertainty": True, "status": "improved"}]}
    return {"meta": {"backend": "llvm_ad_rgb", "wall_time_s": 245.3}, "experiments": {"e": exp}, "changes": changes}


def test_every_column_of_every_page_table_names_its_unit(tmp_path: Path) -> None:
    tables = _bench_tables()
    assert all(len(r) == len(t["headers"]) for t in tables for r in t["rows"])
    (tmp_path / "bench.json").write_text(json.dumps({"generated": "now", "tables": tables}), encoding="utf-8")
    pages = {name: _parse(text) for name, text in render_pages(tmp_path, _results()).items()}
    # overview: changes, overview, claims, 6 bench tables; experiment page: claims, techniques, settings, section
    assert [len(p.tables) for p in pages.values()] == [9, 4]
    bad = [f"{name}: {h}" for name, p in pages.items() for t in p.tables for h in missing_units(t)]
    assert not bad, "page table columns without a unit:\n" + "\n".join(bad)
    assert all(t for p in pages.values() for t in p.tables)  # every table has its header row
    index, exp = pages["index.html"], pages["exp-e.html"]
    assert ["Unit", "Threshold (unit)", "Measured ± uncertainty (unit)"] == exp.tables[0][3:6]
    assert exp.units == ["%", "–", "°", "count", "—"]  # claims (% and dimensionless), then the settings
    assert index.units[:2] == ["%", "–"] and "Wall time (s)" in index.tables[1]  # changes: claim %, metric –


def test_the_page_check_finds_what_lacks_a_unit() -> None:
    """Power: the header forms the pages used before (and a row-unit column without its Unit column) fail."""
    assert missing_units(["Claim", "Threshold", "Measured ± uncertainty", "Power check (perturbation → outcome)"]
                         ) == ["Threshold", "Measured ± uncertainty", "Power check (perturbation → outcome)"]
    assert missing_units(["Experiment", "Wall time", "projection ms", "speed-up"]) == [
        "Wall time", "projection ms", "speed-up"]
    assert missing_units(["Claim", "Threshold (unit)"]) == ["Threshold (unit)"]  # no Unit column: no row unit
    assert missing_units(["Claim", "Unit", "Threshold (unit)", "projection (ms)", "map size (MiB)"]) == []
