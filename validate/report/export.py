"""Results a paper or a dashboard can use: ``python -m validate export RESULTS.json --to DIR [--format …]``.

Read from ``results.json`` alone (the experiments are never imported), written into ``DIR``:

* ``tables/<experiment>/<nn>-<title>.csv`` and ``.tex`` — every table of every page: the tables of the
  page's sections (``experiments.<name>.report.sections[].tables``), its claims (``claims``), its
  technique metrics (``techniques``: one row per measured value, :func:`validate.report.compare.metrics_of`)
  and its judgements (``judgements``: the renders' engine × scene judgements,
  :func:`validate.report.compare.judgements_of`).

  CSV (RFC 4180, UTF-8): one file per table; every header ends with its unit in parentheses (a column of
  words has none); a value with an uncertainty is two columns, ``X (u)`` and ``X ± (u)``. The page's cells
  are text written for reading ("0.947 % ± 0.00323 %", "9.375 %", "—"): :func:`parse_cell` reads them back
  into numbers in the column's unit (a "%" column holds per cent), "—" becomes an empty cell, and a column
  of "mean / max" pairs becomes two columns (``X, 1st of 2``…). Claims and technique metrics are written
  from their JSON numbers, unrounded (a "%" value as the stored fraction × 100).

  LaTeX: a ``tabular`` with booktabs rules (``\\toprule``, ``\\midrule``, ``\\bottomrule``) in a ``table``
  float with its caption (a ``longtable`` when it is longer than a page); a value with an uncertainty as
  "value ± σ" with the digits σ supports (:func:`validate.format.pm`: PDG rounding), the unit in the column
  head. Needs the packages ``booktabs``, ``array``, ``longtable`` and, for accented names, ``fontenc`` with
  T1; Greek letters and symbols are written as math (:data:`LATEX_SYMBOLS`), so pdfLaTeX compiles it.

* ``figures/`` — every figure the pages reference, as its PNG; beside it a PDF and an SVG where the
  figure can be redrawn as vector from results.json: the summary figures
  (``figures/summary/exp-<name>.{png,pdf,svg}``, :mod:`.summary_plots`). The experiments' own figures
  (image strips, error maps, plots of arrays not stored in results.json) are raster only: copied, and
  marked ``"vector": false`` in the manifest.

* ``provenance.json`` — what a paper cites: the suite's and its dependencies' versions, the Mitsuba
  backend and variant, every seed in the experiments' settings, the command that produced the results,
  their date, the git commit of the source tree (``git rev-parse HEAD`` when available, else null), and
  the export's own command and date.

* ``export.json`` — the manifest: every file written, what it is (table caption, figure caption,
  vector or raster).

Bad input (a missing file, a file that is not a results.json, a ``--to`` that cannot be written) is one
:class:`~validate.errors.ValidateError` line and nothing is written: everything is staged in a temporary
folder beside ``DIR`` and moved into place at the end.
"""

from __future__ import annotations

import csv
import datetime as _dt
import io
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .. import format as fmt
from ..atomic import check_writable_folder, output_error
from ..errors import ValidateError
from . import compare, summary

FORMATS = ("csv", "latex", "png", "pdf", "svg")  # what --format may name (default: all)
VECTOR_FORMATS = ("pdf", "svg")
MANIFEST = "export.json"
PROVENANCE = "provenance.json"
PM = "±"
_NUMBER = r"[-+−]?(?:\d+(?:\.\d*)?|\.\d+)(?:e[-+−]?\d+)?"
_UNIT_TAIL = r"(?:\s*(?P<unit>%|°|×|px|s|ms|µs|ns|m|sr|lm|texels|count|B|MiB|W/m²|W/\(m²·sr\)|W/sr|sr⁻¹))?"
_PLAIN = re.compile(rf"^(?P<v>{_NUMBER}){_UNIT_TAIL}$", re.I)
_PM_CELL = re.compile(rf"^(?P<v>{_NUMBER})\s*(?:%|°)?\s*±\s*(?P<u>{_NUMBER}){_UNIT_TAIL}$", re.I)
_PM_SCI = re.compile(rf"^\((?P<v>{_NUMBER})\s*±\s*(?P<u>{_NUMBER})\)e(?P<e>[-+−]?\d+){_UNIT_TAIL}$", re.I)
_EMPTY = {"", "—", "–", "-", "n/a", "NaN", "nan"}


# ---------------------------------------------------------------------------------------------------
# Cells: the page's text back into numbers
# ---------------------------------------------------------------------------------------------------

def _to_float(text: str) -> float:
    return float(text.replace("−", "-"))


def parse_cell(cell: Any) -> tuple[float | None, float | None] | None:
    """(value, σ or None) of a table cell, in the unit its column states; None for a cell of words.

    Numbers are themselves; text reads as the report wrote it: "9.375 %" → (9.375, None),
    "0.947 % ± 0.00323 %" → (0.947, 0.00323), "(2.3 ± 1.1)e-6" → (2.3e-6, 1.1e-6); an empty or "—" cell is
    (None, None)."""
    if isinstance(cell, bool):
        return None
    if cell is None:
        return None, None
    if isinstance(cell, (int, float)):
        return (float(cell) if math.isfinite(float(cell)) else None), None
    text = str(cell).strip()
    if text in _EMPTY:
        return None, None
    if m := _PLAIN.match(text):
        return _to_float(m["v"]), None
    if m := _PM_CELL.match(text):
        return _to_float(m["v"]), _to_float(m["u"])
    if m := _PM_SCI.match(text):
        k = 10.0 ** int(m["e"].replace("−", "-"))
        return _to_float(m["v"]) * k, _to_float(m["u"]) * k
    return None


def _split_header(header: str) -> tuple[str, str]:
    """("name", "unit") of a header ending "(unit)"; (header, "") for a column of words."""
    unit = fmt.header_unit(header)
    if unit:
        return header[: -len(unit) - 3].rstrip(), unit
    return header, ""


def _with_unit(name: str, unit: str) -> str:
    return f"{name} ({unit})" if unit else name


@dataclass
class Column:
    """One column of an exported table: a header (name + unit), its cells, and, for a measured column, the
    uncertainty of each cell (None where the cell has none)."""

    name: str
    unit: str
    values: list[Any]
    sigmas: list[float | None] | None = None

    @property
    def numeric(self) -> bool:
        return all(v is None or isinstance(v, (int, float)) for v in self.values) and any(
            v is not None for v in self.values)


@dataclass
class Table:
    """A table ready to leave: its file stem, caption, where it came from, and its columns."""

    stem: str
    caption: str
    source: str
    columns: list[Column] = field(default_factory=list)

    @property
    def n_rows(self) -> int:
        return max((len(c.values) for c in self.columns), default=0)


def _part_names(caption: str, n: int) -> list[str]:
    """Names of the n parts of an "a / b" cell, read from the caption ("mean / max over normals" → mean, max);
    "1st of 2", "2nd of 2" when the caption names none."""
    m = re.search(r"(\w[\w′]*)" + r" / (\w[\w′]*)" * (n - 1), caption)
    return list(m.groups()) if m else [f"{_ordinal(i + 1)} of {n}" for i in range(n)]


def _columns_from_cells(header: str, cells: list[Any], caption: str = "") -> list[Column]:
    """The exported column(s) of one page column: words, numbers, value ± σ, or "a / b" pairs split (their names
    from the caption, :func:`_part_names`)."""
    name, unit = _split_header(str(header))
    parsed = [parse_cell(c) for c in cells]
    if cells and all(p is not None for p in parsed):
        values = [p[0] for p in parsed]  # type: ignore[index]
        sigmas = [p[1] for p in parsed]  # type: ignore[index]
        return [Column(name, unit, values, sigmas if any(s is not None for s in sigmas) else None)]
    parts = [str(c).split(" / ") if isinstance(c, str) else None for c in cells]
    n = len(parts[0]) if parts and parts[0] else 0
    if n > 1 and all(p is not None and len(p) == n for p in parts):
        names = _part_names(caption, n)
        split = [_columns_from_cells(f"{name}, {names[i]}" + (f" ({unit})" if unit else ""),
                                     [p[i] for p in parts]) for i in range(n)]  # type: ignore[index]
        if all(cs[0].numeric for cs in split):
            return [c for cs in split for c in cs]
    return [Column(name, unit, ["" if c is None else c for c in cells])]


def _ordinal(i: int) -> str:
    return {1: "1st", 2: "2nd", 3: "3rd"}.get(i, f"{i}th")


def _merge_pm_columns(cols: list[Column]) -> list[Column]:
    """A page column "± (u)" right after "X (u)" is X's uncertainty: one measured column."""
    out: list[Column] = []
    for c in cols:
        prev = out[-1] if out else None
        if (c.name.strip() in (PM, "±σ", "σ") and prev is not None and prev.sigmas is None and prev.numeric
                and c.numeric and c.unit == prev.unit):
            prev.sigmas = [None if v is None else float(v) for v in c.values]
            continue
        out.append(c)
    return out


def page_table(t: Mapping[str, Any], stem: str, source: str) -> Table:
    """A table of a page's section (headers, rows of cells as written, caption) as a :class:`Table`."""
    headers = [str(h) for h in t.get("headers") or []]
    rows = [list(r) for r in t.get("rows") or []]
    width = max([len(headers), *map(len, rows)], default=0)
    headers += [f"column {i + 1}" for i in range(len(headers), width)]
    cols: list[Column] = []
    for i, h in enumerate(headers):
        cols.extend(_columns_from_cells(h, [r[i] if i < len(r) else None for r in rows], str(t.get("caption") or "")))
    return Table(stem, str(t.get("caption") or ""), source, _merge_pm_columns(cols))


def _num(x: Any) -> float | None:
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        return None
    return float(x) if math.isfinite(float(x)) else None


def _display(value: Any, unit: str) -> float | None:
    """A stored number in the unit it is shown in: a "%" value is a fraction, shown × 100."""
    v = _num(value)
    return None if v is None else (100.0 * v if unit == "%" else v)


def claims_table(exp: str, claims: list[Mapping[str, Any]]) -> Table:
    """The page's claims: id, description, metric, measured ± σ and threshold in the row's unit, the verdict and
    the power check; numbers as stored ("%" rows × 100)."""
    units = [str(c.get("unit") or "") for c in claims]
    shown = [u or "–" for u in units]
    power = [c.get("power") or {} for c in claims]
    cols = [
        Column("claim", "", [str(c.get("id") or "") for c in claims]),
        Column("description", "", [str(c.get("description") or "") for c in claims]),
        Column("metric", "", [str(c.get("metric") or "") for c in claims]),
        Column("measured", fmt.ROW_UNIT, [_display(c.get("measured"), u) for c, u in zip(claims, units, strict=True)],
               [_display(c.get("uncertainty"), u) for c, u in zip(claims, units, strict=True)]),
        Column("comparison", "", [str(c.get("comparison") or "<") for c in claims]),
        Column("threshold", fmt.ROW_UNIT,
               [_display(c.get("threshold"), u) for c, u in zip(claims, units, strict=True)]),
        Column("unit", "", shown),
        Column("result", "", ["pass" if c.get("passed") else "fail" for c in claims]),
        Column("power check", "", [("fails ✓" if p.get("fails") else "still passes") if p else "none"
                                   for p in power]),
        Column("reference", "", [str(c.get("source") or "") for c in claims]),  # the claim's source
    ]
    return Table("claims", f"{exp}: claims, each with its power check", f"experiments.{exp}.claims", cols)


def measured_table(exp: str, stem: str, caption: str, source: str, label: str,
                   items: Mapping[str, Mapping[str, Any]]) -> Table:
    """One row per measured value ``{key: {"value", "uncertainty", "unit", …}}``: where, value ± σ, unit."""
    keys = list(items)
    units = [str(items[k].get("unit") or "") for k in keys]
    prefix = f"{exp}/"
    cols = [
        Column(label, "", [k[len(prefix):] if k.startswith(prefix) else k for k in keys]),
        Column("value", fmt.ROW_UNIT, [_display(items[k].get("value"), u) for k, u in zip(keys, units, strict=True)],
               [_display(items[k].get("uncertainty"), u) for k, u in zip(keys, units, strict=True)]),
        Column("unit", "", [u or "–" for u in units]),
        Column("kind", "", [str(items[k].get("stat") or "") for k in keys]),  # the statistic: mean, max, rms
        Column("lower, higher or zero is better?", "", [str(items[k].get("better") or "lower") for k in keys]),
    ]
    return Table(stem, caption, source, cols)


def _slug(text: str, limit: int = 48) -> str:
    s = re.sub(r"[^A-Za-z0-9]+", "-", text.encode("ascii", "ignore").decode()).strip("-").lower()
    return s[:limit].rstrip("-") or "table"


def tables_of(results: Mapping[str, Any]) -> dict[str, list[Table]]:
    """experiment → every table of its page, in page order (sections', then claims, techniques, judgements)."""
    out: dict[str, list[Table]] = {}
    for exp, e in (results.get("experiments") or {}).items():
        if not isinstance(e, Mapping):
            continue
        tables: list[Table] = []
        n = 0
        for si, s in enumerate((e.get("report") or {}).get("sections") or []):
            for ti, t in enumerate(s.get("tables") or [] if isinstance(s, Mapping) else []):
                if not isinstance(t, Mapping) or not t.get("rows"):
                    continue
                n += 1
                title = str(s.get("title") or "")
                cap = str(t.get("caption") or "")
                tables.append(page_table(t, f"{n:02d}-{_slug(title)}", f"experiments.{exp}.report.sections[{si}]"
                                                                      f".tables[{ti}]"))
                tables[-1].caption = f"{title}: {cap}" if cap and title else (title or cap)
        claims = [c for c in e.get("claims") or [] if isinstance(c, Mapping)]
        if claims:
            tables.append(claims_table(exp, claims))
        one = {"experiments": {exp: e}}
        metrics = compare.metrics_of(one)
        if metrics:
            tables.append(measured_table(exp, "techniques", f"{exp}: every technique metric (value ± σ)",
                                         f"experiments.{exp}.techniques.*.metrics", "key", metrics))
        judgements = compare.judgements_of(one)
        if judgements:
            tables.append(measured_table(exp, "judgements", f"{exp}: every judgement (value ± σ)",
                                         f"experiments.{exp} judgements", "key", judgements))
        out[exp] = tables
    return out


# ---------------------------------------------------------------------------------------------------
# Writers
# ---------------------------------------------------------------------------------------------------

def _csv_number(v: float | None) -> str:
    return "" if v is None else repr(float(v)) if not float(v).is_integer() or abs(v) >= 1e16 else str(int(v))


def to_csv(t: Table) -> str:
    """The table as CSV: a measured column is two, ``X (u)`` and ``X ± (u)``; numbers unrounded."""
    head: list[str] = []
    for c in t.columns:
        head.append(_with_unit(c.name, c.unit))
        if c.sigmas is not None:
            head.append(_with_unit(f"{c.name} {PM}", c.unit))
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(head)
    for i in range(t.n_rows):
        row: list[str] = []
        for c in t.columns:
            v = c.values[i] if i < len(c.values) else None
            row.append(_csv_number(v) if c.numeric or v is None or isinstance(v, float) else str(v))
            if c.sigmas is not None:
                row.append(_csv_number(c.sigmas[i] if i < len(c.sigmas) else None))
        w.writerow(row)
    return buf.getvalue()


# Symbols pdfLaTeX lacks in text mode, written as math or text commands
LATEX_SYMBOLS = {
    "±": r"\ensuremath{\pm}", "×": r"\ensuremath{\times}", "·": r"\ensuremath{\cdot}", "°": r"\ensuremath{^\circ}",
    "²": r"\textsuperscript{2}", "³": r"\textsuperscript{3}", "¹": r"\textsuperscript{1}",
    "⁴": r"\textsuperscript{4}", "⁵": r"\textsuperscript{5}", "⁶": r"\textsuperscript{6}",
    "⁷": r"\textsuperscript{7}", "⁸": r"\textsuperscript{8}", "⁹": r"\textsuperscript{9}",
    "⁺": r"\textsuperscript{+}", "⁻": r"\textsuperscript{\ensuremath{-}}", "₀": r"\ensuremath{_0}",
    "₁": r"\ensuremath{_1}", "₂": r"\ensuremath{_2}", "₃": r"\ensuremath{_3}", "¼": r"\ensuremath{\frac14}",
    "½": r"\ensuremath{\frac12}", "§": r"\S{}", "–": "--", "—": "---", "…": r"\ldots{}", "′": r"\ensuremath{'}",
    "−": r"\ensuremath{-}", "→": r"\ensuremath{\rightarrow}", "∂": r"\ensuremath{\partial}",
    "∈": r"\ensuremath{\in}", "√": r"\ensuremath{\surd}", "∝": r"\ensuremath{\propto}", "∞": r"\ensuremath{\infty}",
    "∫": r"\ensuremath{\int}", "≈": r"\ensuremath{\approx}", "≠": r"\ensuremath{\neq}", "≤": r"\ensuremath{\leq}",
    "≥": r"\ensuremath{\geq}", "≲": r"\ensuremath{\lesssim}", "⊕": r"\ensuremath{\oplus}", "⊥": r"\ensuremath{\perp}",
    "ℓ": r"\ensuremath{\ell}", "µ": r"\ensuremath{\mu}", "✓": r"\ensuremath{\surd}", "Δ": r"\ensuremath{\Delta}",
    "Λ": r"\ensuremath{\Lambda}", "Σ": r"\ensuremath{\Sigma}", "Φ": r"\ensuremath{\Phi}", "Ω": r"\ensuremath{\Omega}",
    "α": r"\ensuremath{\alpha}", "β": r"\ensuremath{\beta}", "γ": r"\ensuremath{\gamma}", "δ": r"\ensuremath{\delta}",
    "ε": r"\ensuremath{\varepsilon}", "η": r"\ensuremath{\eta}", "θ": r"\ensuremath{\theta}",
    "κ": r"\ensuremath{\kappa}", "λ": r"\ensuremath{\lambda}", "μ": r"\ensuremath{\mu}", "ν": r"\ensuremath{\nu}",
    "π": r"\ensuremath{\pi}", "ρ": r"\ensuremath{\rho}", "σ": r"\ensuremath{\sigma}", "τ": r"\ensuremath{\tau}",
    "φ": r"\ensuremath{\varphi}", "χ": r"\ensuremath{\chi}", "ψ": r"\ensuremath{\psi}", "ω": r"\ensuremath{\omega}",
}
_LATEX_SPECIAL = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_",
                  "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}",
                  "<": r"\textless{}", ">": r"\textgreater{}", "|": r"\textbar{}"}
_LATIN1 = set("ÀÁÂÄÅÇÈÉÊËÌÍÎÏÑÒÓÔÖØÙÚÛÜÝàáâäåçèéêëìíîïñòóôöøùúûüýÿŠšŽžßæÆœŒ")  # T1 fontenc + utf8 handle these


def latex_escape(text: str) -> str:
    """``text`` for pdfLaTeX: its specials escaped, symbols as math (:data:`LATEX_SYMBOLS`), accented Latin letters
    as they are (T1 + UTF-8); combining marks and any other character outside that set are dropped."""
    out = []
    for ch in str(text):
        if ch in _LATEX_SPECIAL:
            out.append(_LATEX_SPECIAL[ch])
        elif ch in LATEX_SYMBOLS:
            out.append(LATEX_SYMBOLS[ch])
        elif ord(ch) < 128 or ch in _LATIN1:
            out.append(ch)
    return "".join(out)


def _latex_cell(c: Column, i: int) -> str:
    v = c.values[i] if i < len(c.values) else None
    s = c.sigmas[i] if c.sigmas is not None and i < len(c.sigmas) else None
    if v is None or v == "":
        return "---" if c.numeric or c.sigmas is not None else ""
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return latex_number(v, s)
    return latex_escape(str(v))


def latex_number(value: float, sigma: float | None = None) -> str:
    """value ± σ to the digits σ supports (:func:`validate.format.pm`) in LaTeX math: "$9.375000 \\pm 0.000014$",
    a shared exponent as "$(2.3 \\pm 1.1)\\times 10^{-6}$"; the value alone (3 significant digits) without σ."""
    text = fmt.pm(value, sigma) if sigma else fmt.sig(value)
    m = re.fullmatch(r"\((.+) ± (.+)\)e(-?\d+)", text)
    if m and sigma and abs(int(m[3])) <= 3:  # a small σ on a plain-sized value: fixed point, σ's decimals
        d = fmt.decimals_for(float(sigma))
        return f"${float(value):.{d}f} \\pm {fmt.round_sigma(float(sigma)):.{d}f}$"
    if m:
        body = f"{m[1]} \\pm {m[2]}"
        return f"${body}$" if m[3] == "0" else f"$({body})\\times 10^{{{m[3]}}}$"
    m = re.fullmatch(r"(-?[\d.]+)e(-?\d+)", text)
    if m:
        return f"${m[1]}\\times 10^{{{m[2]}}}$"
    return "$" + text.replace(" ± ", " \\pm ").replace("−", "-").replace("∞", "\\infty") + "$"


LONG_TABLE_ROWS = 40  # more rows than fit a page: a longtable (breaks across pages) instead of a table float
WRAP_CHARS = 32  # a column of words with a longer cell is set as a paragraph column of WRAP_WIDTH
WRAP_WIDTH = "4.5cm"


def _align(c: Column) -> str:
    if c.numeric or c.sigmas is not None:
        return "r"
    longest = max((len(str(v)) for v in c.values), default=0)
    return f">{{\\raggedright\\arraybackslash}}p{{{WRAP_WIDTH}}}" if longest > WRAP_CHARS else "l"


def to_latex(t: Table, label: str = "") -> str:
    """The table in booktabs rules — a ``table`` float, or a ``longtable`` beyond :data:`LONG_TABLE_ROWS` rows —
    value ± σ with σ's digits, units in the head, long text columns wrapped."""
    align = "".join(_align(c) for c in t.columns)
    head = " & ".join(latex_escape(_with_unit(c.name, c.unit if c.unit != fmt.ROW_UNIT else "unit"))
                      for c in t.columns)
    caption = f"\\caption{{{latex_escape(t.caption)}}}" if t.caption else ""
    lab = f"\\label{{{label}}}" if label else ""
    body = [" & ".join(_latex_cell(c, i) for c in t.columns) + " \\\\" for i in range(t.n_rows)]
    lines = ["% generated by `python -m validate export`; needs \\usepackage[T1]{fontenc}, \\usepackage{booktabs},"
             " \\usepackage{array} and \\usepackage{longtable}",
             f"% source: results.json {t.source}"]
    if t.n_rows > LONG_TABLE_ROWS:
        lines += ["{\\small", f"\\begin{{longtable}}{{{align}}}", caption + (lab + " \\\\" if caption else ""),
                  "\\toprule", head + " \\\\", "\\midrule", "\\endhead", "\\bottomrule", "\\endfoot",
                  *body, "\\end{longtable}", "}"]
    else:
        lines += ["\\begin{table}[htbp]", "\\centering", "\\small", caption, lab,
                  f"\\begin{{tabular}}{{{align}}}", "\\toprule", head + " \\\\", "\\midrule", *body,
                  "\\bottomrule", "\\end{tabular}", "\\end{table}"]
    return "\n".join(line for line in lines if line) + "\n"


# ---------------------------------------------------------------------------------------------------
# Figures and provenance
# ---------------------------------------------------------------------------------------------------

def _figures_of(e: Mapping[str, Any]) -> list[tuple[str, str]]:
    """(path, caption) of every figure a page references: its sections' figures and gallery rows."""
    out: list[tuple[str, str]] = []
    for s in (e.get("report") or {}).get("sections") or []:
        if not isinstance(s, Mapping):
            continue
        figs = list(s.get("figures") or []) + [f for row in s.get("gallery") or [] for f in row or []]
        for f in figs:
            if isinstance(f, Mapping) and f.get("path"):
                out.append((str(f["path"]), str(f.get("caption") or "")))
    return out


def git_commit(where: Path) -> str | None:
    """``git rev-parse HEAD`` of the tree holding ``where``; None without git or outside a repository."""
    try:
        r = subprocess.run(["git", "-C", str(where), "rev-parse", "HEAD"], capture_output=True, text=True,
                           timeout=10, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    out = r.stdout.strip()
    return out if r.returncode == 0 and re.fullmatch(r"[0-9a-f]{40}", out) else None


def _seeds(node: Any, prefix: str = "") -> dict[str, Any]:
    out: dict[str, Any] = {}
    if isinstance(node, Mapping):
        for k, v in node.items():
            key = f"{prefix}.{k}" if prefix else str(k)
            if "seed" in str(k).lower() and not isinstance(v, Mapping):
                out[key] = v
            else:
                out.update(_seeds(v, key))
    return out


def provenance(results: Mapping[str, Any], source: str, argv: list[str] | None = None) -> dict[str, Any]:
    """What produced the results (their ``meta``) and this export: versions, backend, seeds, commands, commit,
    dates."""
    meta = results.get("meta") or {}
    exps = results.get("experiments") or {}
    try:
        from importlib.metadata import version

        suite = version("validate")
    except Exception:  # not installed as a distribution (a source checkout on PYTHONPATH)
        suite = None
    import matplotlib

    return {
        "results": source,
        "generated": meta.get("generated"),
        "command": meta.get("command"),
        "quick": meta.get("quick"),
        "backend": meta.get("backend"),
        "variant": meta.get("variant"),
        "versions": dict(meta.get("versions") or {}),
        "seeds": {name: _seeds((e or {}).get("settings") or {}) for name, e in exps.items()
                  if isinstance(e, Mapping) and _seeds((e or {}).get("settings") or {})},
        "settings": {name: (e or {}).get("settings") or {} for name, e in exps.items() if isinstance(e, Mapping)},
        "commit": meta.get("commit") or git_commit(Path(__file__).resolve().parent),
        "export": {"command": " ".join(["python -m validate", *(argv if argv is not None else sys.argv[1:])]),
                   "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                   "validate": suite, "python": sys.version.split()[0], "matplotlib": matplotlib.__version__},
    }


# ---------------------------------------------------------------------------------------------------
# The command
# ---------------------------------------------------------------------------------------------------

def parse_formats(text: str | None) -> tuple[str, ...]:
    """``--format csv,latex`` → ("csv", "latex"); None → every format; an unknown name is a ValidateError."""
    if text is None:
        return FORMATS
    names = tuple(dict.fromkeys(v.strip().lower() for v in text.split(",") if v.strip()))
    bad = [n for n in names if n not in FORMATS]
    if bad or not names:
        raise ValidateError(f"--format {text}: unknown format {', '.join(bad) or '(none)'}; "
                            f"expected some of {', '.join(FORMATS)}")
    return names


def export(results_path: str | Path, to: str | Path, formats: Iterable[str] = FORMATS,
           argv: list[str] | None = None) -> dict[str, Any]:
    """Write the exports of ``results_path`` into ``to`` (module docstring); returns the manifest."""
    formats = tuple(formats)
    label, results = compare.load(results_path)
    src = Path(label)
    root = src.parent
    to = Path(to)
    check_writable_folder(to)
    tables = tables_of(results)
    manifest: dict[str, Any] = {"results": label, "formats": list(formats), "tables": [], "figures": []}
    try:
        to.mkdir(parents=True, exist_ok=True)
        stage = Path(tempfile.mkdtemp(prefix=".export-", dir=to))
    except OSError as exc:
        raise output_error(to, exc) from None
    try:
        for exp, ts in tables.items():
            for t in ts:
                entry = {"experiment": exp, "caption": t.caption, "source": t.source, "rows": t.n_rows, "files": []}
                for kind, ext, text in (("csv", "csv", lambda t=t: to_csv(t)),
                                        ("latex", "tex", lambda t=t, exp=exp: to_latex(t, f"tab:{exp}-{t.stem}"))):
                    if kind in formats:
                        rel = f"tables/{exp}/{t.stem}.{ext}"
                        _write(stage / rel, text())
                        entry["files"].append(rel)
                manifest["tables"].append(entry)
        _export_figures(results, root, stage, formats, manifest)
        prov = provenance(results, label, argv)
        _write(stage / PROVENANCE, json.dumps(prov, indent=2, ensure_ascii=False, default=str) + "\n")
        _write(stage / MANIFEST, json.dumps(manifest, indent=2, ensure_ascii=False) + "\n")
        for p in sorted(stage.rglob("*")):
            if p.is_file():
                dest = to / p.relative_to(stage)
                dest.parent.mkdir(parents=True, exist_ok=True)
                os.replace(p, dest)
    except OSError as exc:
        raise output_error(getattr(exc, "filename", None) or to, exc) from None
    finally:
        shutil.rmtree(stage, ignore_errors=True)
    return manifest


def _write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


def _export_figures(results: Mapping[str, Any], root: Path, stage: Path, formats: tuple[str, ...],
                    manifest: dict[str, Any]) -> None:
    """Summary figures redrawn (PNG and vector), the pages' figures copied (raster: vector false)."""
    from . import summary_plots

    for exp, e in (results.get("experiments") or {}).items():
        if not isinstance(e, Mapping):
            continue
        spec = summary.summary_for(exp, e)
        if spec is not None:
            files = []
            for ext in ("png", *VECTOR_FORMATS):
                if ext in formats:
                    rel = f"figures/summary/exp-{exp}.{ext}"
                    summary_plots.draw(spec, stage / rel)
                    files.append(rel)
            if files:
                manifest["figures"].append({"experiment": exp, "caption": f"{spec.title} — {spec.metric}",
                                            "vector": any(f.endswith(VECTOR_FORMATS) for f in files),
                                            "files": files, "drawn_from": "results.json"})
        if "png" not in formats:
            continue
        for path, caption in _figures_of(e):
            src = (root / path).resolve()
            try:
                rel = src.relative_to(root.resolve()).as_posix()
            except ValueError:
                continue  # outside the report folder: not ours to copy
            if not src.is_file():
                manifest["figures"].append({"experiment": exp, "caption": caption, "vector": False, "files": [],
                                            "missing": rel})
                continue
            (stage / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(src, stage / rel)
            manifest["figures"].append({"experiment": exp, "caption": caption, "vector": False, "files": [rel],
                                        "note": "raster: drawn by the experiment from arrays results.json "
                                                "does not hold; copied as it is"})
