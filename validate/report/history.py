"""Trends across runs: ``python -m validate history RESULTS.json… --out DIR``.

The runs are read in the order given (oldest first; a CI job keeps one ``results.json`` per commit) through
:mod:`.compare`, so every number is keyed as ``compare`` keys it and old files load too:

* a claim ``<id>``: its measured value ± σ and whether it passed;
* a technique metric ``<experiment>/<technique>/<metric>`` and a judgement ``<experiment>/<path>``: the
  measured value ± σ (:class:`validate.stats.Measured`).

A value is *changed* when two runs differ beyond float round-off (:data:`.compare.ROUNDOFF`) or a claim's
verdict differs. For each changed value (every value with ``--all``), one small plot: x = the run, y = the
value with a ±σ band; a run whose claim fails is a red ✕, a run that :func:`.compare.compare` calls a
regression against the run before it (``regressed``, ``newly_failing``) is circled in red. At most
:data:`MAX_PLOTS` plots are drawn, regressions first, then the largest relative changes; the CSV holds
every changed value.

Written into ``DIR``: ``history.html`` (one self-contained page: the plots are inlined as data URIs, a
table of regressions first), ``history.csv`` (one row per value and run: run, kind, key, value, σ, unit,
passed, status against the previous run, regression) and ``plots/<key>.png``.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .. import format as fmt
from ..atomic import check_writable_folder, write_text
from . import compare

MAX_PLOTS = 150  # plots drawn at most (a sweep of thousands of metrics would make an unreadable page)
PLOT_SIZE = (4.2, 2.6)  # inches at plots.FIG_DPI: three plots a row at 1280 px
HTML_FILE, CSV_FILE, PLOT_DIR = "history.html", "history.csv", "plots"


@dataclass
class Series:
    """One value across the runs: value, σ, passed (claims) and the status against the previous run, per run
    (None where the run lacks it)."""

    kind: str
    key: str
    unit: str
    values: list[float | None]
    sigmas: list[float | None]
    passed: list[bool | None]
    status: list[str] = field(default_factory=list)

    @property
    def regressions(self) -> list[int]:
        return [i for i, s in enumerate(self.status) if s in compare.REGRESSION_STATUSES]

    @property
    def changed(self) -> bool:
        vals = [v for v in self.values if v is not None]
        verdicts = {p for p in self.passed if p is not None}
        return (len(verdicts) > 1 or any(compare._differs(a, b) for a, b in zip(vals, vals[1:], strict=False))
                or any(v is None for v in self.values) and bool(vals))

    def relative_change(self) -> float:
        vals = [abs(v) for v in self.values if v is not None]
        return (max(vals) - min(vals)) / max(max(vals), 1e-300) if vals else 0.0


@dataclass
class History:
    runs: list[str]
    series: list[Series]
    plotted: list[str] = field(default_factory=list)
    out: Path | None = None

    @property
    def regressions(self) -> list[Series]:
        return [s for s in self.series if s.regressions]

    def summary(self) -> str:
        where = f" -> {self.out / HTML_FILE}, {self.out / CSV_FILE}" if self.out else ""
        return (f"{len(self.runs)} runs: {len(self.series)} values changed, {len(self.regressions)} with a regression; "
                f"{len(self.plotted)} plots{where}")


def _label(path: str, results: Mapping[str, Any]) -> str:
    """A run's name: its folder (``…/<folder>/results.json``) or file name, and the date it was generated."""
    p = Path(path)
    name = p.parent.name if p.name == "results.json" and p.parent.name else p.name
    when = str((results.get("meta") or {}).get("generated") or "")[:16].replace("T", " ")
    return f"{name} ({when})" if when else name


def _pick(kind: str, entry: Mapping[str, Any] | None) -> tuple[float | None, float | None, bool | None, str]:
    if entry is None:
        return None, None, None, ""
    if kind == "claim":
        return (compare._float(entry.get("measured")), compare._float(entry.get("uncertainty")),
                bool(entry.get("passed")), str(entry.get("unit") or ""))
    return (compare._float(entry.get("value")), compare._float(entry.get("uncertainty")), None,
            str(entry.get("unit") or ""))


def collect(sources: Sequence[str | Path | Mapping[str, Any]]) -> tuple[list[str], list[Series]]:
    """(run labels, every value across the runs with its status against the previous run)."""
    loaded = [compare.load(s) for s in sources]
    runs = [_label(label, r) for label, r in loaded]
    extract = {"claim": compare.claims_of, "metric": compare.metrics_of, "judgement": compare.judgements_of}
    per_run = {k: [f(r) for _, r in loaded] for k, f in extract.items()}
    statuses: list[dict[tuple[str, str], str]] = [{}]
    for (_, a), (_, b) in zip(loaded, loaded[1:], strict=False):
        statuses.append({(r.kind, r.key): r.status for r in compare.compare(a, b).rows})
    out: list[Series] = []
    for kind, maps in per_run.items():
        keys = list(dict.fromkeys(k for m in maps for k in m))
        for key in keys:
            picks = [_pick(kind, m.get(key)) for m in maps]
            unit = next((p[3] for p in picks if p[3]), "")
            out.append(Series(kind, key, unit, [p[0] for p in picks], [p[1] for p in picks], [p[2] for p in picks],
                              [st.get((kind, key), "") for st in statuses]))
    return runs, out


def _scale(unit: str) -> float:
    return 100.0 if unit == "%" else 1.0


def _slug(key: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", key).strip("_")[:150] or "value"


def draw_series(s: Series, runs: list[str], path: Path) -> None:
    """One small plot of ``s``: value ± σ band against the run; failing runs ✕, regressions circled in red."""
    import numpy as np

    from ..figures import plots

    k = _scale(s.unit)
    x = np.arange(len(runs), dtype=float)
    y = np.array([np.nan if v is None else v * k for v in s.values])
    e = np.array([0.0 if u is None else u * k for u in s.sigmas])
    fig = plots._new_figure(PLOT_SIZE)
    ax = fig.add_subplot()
    ax.fill_between(x, y - e, y + e, color="C0", alpha=0.25, linewidth=0, label="± σ")
    ax.plot(x, y, marker="o", color="C0", linewidth=1.5, markersize=4)
    fails = [i for i, p in enumerate(s.passed) if p is False]
    if fails:
        ax.plot(x[fails], y[fails], linestyle="none", marker="x", color="#c0392b", markersize=9, mew=2,
                label="claim fails")
    if s.regressions:
        ax.plot(x[s.regressions], y[s.regressions], linestyle="none", marker="o", markersize=13, mfc="none",
                mec="#c0392b", mew=2, label="regression")
    ax.set_xticks(x, [f"{i + 1}" for i in range(len(runs))])
    ax.set_xlabel("run (order given)", fontsize=9)
    ax.set_ylabel(s.unit or "value", fontsize=9)
    ax.set_title(s.key if len(s.key) <= 60 else "…" + s.key[-59:], fontsize=9)
    ax.tick_params(labelsize=8)
    ax.grid(True, alpha=0.3)
    if fails or s.regressions:
        ax.legend(fontsize=7, loc="best")
    plots._save_figure(path, fig)


def _fmt(v: float | None, u: float | None, unit: str) -> str:
    return fmt.fmt_quantity(v, unit, u if u else None) if v is not None else fmt.DASH


def to_csv(runs: list[str], series: list[Series]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["run", "run label", "kind", "key", "value", "uncertainty", "unit", "passed", "status", "regression"])
    for s in series:
        for i, run in enumerate(runs):
            v, u = s.values[i], s.sigmas[i]
            w.writerow([i + 1, run, s.kind, s.key, "" if v is None else repr(v), "" if u is None else repr(u),
                        s.unit, "" if s.passed[i] is None else ("pass" if s.passed[i] else "fail"),
                        s.status[i] if i else "", "yes" if i in s.regressions else ""])
    return buf.getvalue()


_CSS = """body{font:15px/1.45 system-ui,sans-serif;margin:1.5rem auto;max-width:1240px;color:#222}
h1{font-size:1.5rem}table{border-collapse:collapse;margin:.5rem 0 1.5rem}td,th{border-bottom:1px solid #ddd;
padding:.25rem .6rem;text-align:left}td.n{text-align:right;font-variant-numeric:tabular-nums}
.grid{display:grid;grid-template-columns:repeat(auto-fill,minmax(400px,1fr));gap:.8rem}
figure{margin:0;border:1px solid #ddd;padding:.3rem}figure img{width:100%}figcaption{font-size:.9rem}
.bad{color:#c0392b;font-weight:600}"""


def to_html(h: History, images: Mapping[str, bytes]) -> str:
    """The self-contained page: runs, regressions table, then one figure per plotted value (inlined PNG)."""
    e = html.escape
    parts = [f"<!doctype html><html lang='en'><head><meta charset='utf-8'><title>validate — history of "
             f"{len(h.runs)} runs</title><style>{_CSS}</style></head><body>",
             f"<h1>History of {len(h.runs)} runs</h1><p>{e(h.summary())}</p><ol>"]
    parts += [f"<li>{e(r)}</li>" for r in h.runs]
    parts.append("</ol>")
    regs = h.regressions
    parts.append(f"<h2 id='regressions'>Regressions ({len(regs)})</h2>")
    if regs:
        parts.append("<table><tr><th>key</th><th>kind</th><th>run</th><th>status</th><th>before</th>"
                     "<th>after</th></tr>")
        for s in regs:
            for i in s.regressions:
                before = _fmt(s.values[i - 1], s.sigmas[i - 1], s.unit)
                parts.append(f"<tr class='bad'><td>{e(s.key)}</td><td>{s.kind}</td><td class='n'>{i + 1}</td>"
                             f"<td>{e(s.status[i])}</td><td class='n'>{e(before)}"
                             f"</td><td class='n'>{e(_fmt(s.values[i], s.sigmas[i], s.unit))}</td></tr>")
        parts.append("</table>")
    else:
        parts.append("<p>None: no value is worse beyond its uncertainty and no claim newly fails.</p>")
    parts.append(f"<h2 id='plots'>Changed values ({len(h.plotted)} plotted of {len(h.series)})</h2><div class='grid'>")
    by_key = {s.key: s for s in h.series}
    for key in h.plotted:
        s = by_key[key]
        data = base64.b64encode(images[key]).decode("ascii")
        mark = " <span class='bad'>regression</span>" if s.regressions else ""
        last = next((i for i in range(len(h.runs) - 1, -1, -1) if s.values[i] is not None), 0)
        parts.append(f"<figure><img alt='{e(key)} across the runs' src='data:image/png;base64,{data}'>"
                     f"<figcaption>{e(s.kind)} <code>{e(key)}</code>{mark}: last "
                     f"{e(_fmt(s.values[last], s.sigmas[last], s.unit))}</figcaption></figure>")
    parts.append("</div></body></html>\n")
    return "".join(parts)


def write_history(sources: Sequence[str | Path | Mapping[str, Any]], out: str | Path,
                  changed_only: bool = True) -> History:
    """Read the runs, draw the plots, write ``history.html`` and ``history.csv`` into ``out``."""
    runs, series = collect(sources)  # every input read (and checked) before anything is written
    check_writable_folder(out)
    keep = [s for s in series if s.changed or not changed_only]
    h = History(runs, keep, out=Path(out))
    ranked = sorted(keep, key=lambda s: (not s.regressions, -s.relative_change()))
    h.plotted = [s.key for s in ranked[:MAX_PLOTS]]
    images: dict[str, bytes] = {}
    out = Path(out)
    by_key = {s.key: s for s in keep}
    for key in h.plotted:
        path = out / PLOT_DIR / f"{_slug(key)}.png"
        draw_series(by_key[key], runs, path)
        images[key] = path.read_bytes()
    h.plotted = [s.key for s in keep if s.key in images]  # page order: the order the values come in
    write_text(out / CSV_FILE, to_csv(runs, keep))
    write_text(out / HTML_FILE, to_html(h, images))
    return h
