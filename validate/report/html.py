"""results.json ⇄ disk, and the HTML report rendered from it: an overview page and one page per experiment.

The page is a pure function of the results dict — the same dict :func:`write_results_json` stores —
so re-running one experiment and re-rendering never loses the others. Layout of the dict::

    {"meta": {"backend", "versions", "generated", "command", "quick", "wall_time_s",
              "skipped_inputs": [[file, reason], ...]},
     "experiments": {NAME: ExperimentResult.to_json(), ...}}   # page order = dict order

``index.html`` is the overview (every experiment with its pass count, power checks and a link; a
table of contents; every claim grouped by experiment in collapsible blocks; ``bench.json`` when
present); ``exp-<name>.html`` holds one experiment (contents, findings, claims with their power
checks, techniques, sections). Pages are self-contained files (CSS inlined from
``templates/style.css``, no scripts, no external resources) whose images are paths relative to the
report folder, so the folder can be moved or zipped and opened from disk. Templates are rendered
by Jinja2 with autoescaping on: every string
from the results (paragraphs, captions, findings) is text, never markup.

Number formatting (Jinja filters ``num``, ``pct``, ``measured``, ``threshold``, ``cell``):
``unit == "%"`` marks fractions shown as per cent (0.0086 → "0.86 %"); other values use 3
significant digits, scientific below 10⁻³ and from 10⁶ (1.2e-5).
"""

from __future__ import annotations

import functools
import json
import math
import re
from collections.abc import Mapping
from numbers import Integral, Real
from pathlib import Path, PurePosixPath
from typing import Any

import jinja2

from ..atomic import write_text
from ..errors import ValidateError

RESULTS_FILE = "results.json"
REPORT_FILE = "index.html"
BENCH_FILE = "bench.json"
EXPERIMENT_TEMPLATE = "experiment.html.j2"
PAGE_TITLE = "validate — real-time lighting vs physics"
TEMPLATE = "index.html.j2"
MEASURED_DIGITS = 3  # significant digits of measured values and thresholds
UNCERTAINTY_DIGITS = 2  # significant digits of uncertainties
THRESHOLD_DIGITS = 4  # thresholds are exact figures (3/32 = 9.375 %), shown without rounding them up
_TEMPLATES = Path(__file__).parent / "templates"


# ---------------------------------------------------------------------------------------------------
# Number formatting
# ---------------------------------------------------------------------------------------------------

def fmt_num(value: Any, digits: int = MEASURED_DIGITS) -> str:
    """Compact number: ``digits`` significant digits; scientific (1.23e-5) for |v| < 10⁻³ or ≥ 10⁶;
    integers as written; None → "—"; NaN → "NaN"; ±inf → "∞"/"−∞". Non-numbers are returned as text."""
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, Integral):
        return str(int(value))
    if not isinstance(value, Real):
        return str(value)
    v = float(value)
    if math.isnan(v):
        return "NaN"
    if math.isinf(v):
        return "∞" if v > 0 else "−∞"
    if v == 0.0:
        return "0"
    a = abs(v)
    if 1e-3 <= a < 1e3:
        s = f"{v:.{digits}g}"
        if "e" not in s:
            return s
    if 1e3 <= a < 1e6:
        return f"{v:.0f}"
    mantissa, exponent = f"{v:.{max(digits - 1, 0)}e}".split("e")
    if "." in mantissa:
        mantissa = mantissa.rstrip("0").rstrip(".")
    return f"{mantissa}e{int(exponent)}"


def fmt_pct(value: Any, digits: int = MEASURED_DIGITS) -> str:
    """A fraction as per cent: 0.0086 → "0.86 %" (``digits`` significant digits of the per cent value)."""
    if isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(float(value)):
        return f"{fmt_num(float(value) * 100.0, digits)} %"
    return fmt_num(value, digits)


def fmt_value(value: Any, unit: str = "", digits: int = MEASURED_DIGITS) -> str:
    """Value with its unit: "%" → :func:`fmt_pct`; another unit is appended ("0.5 sr")."""
    if unit == "%":
        return fmt_pct(value, digits)
    s = fmt_num(value, digits)
    return f"{s} {unit}" if unit and value is not None else s


def fmt_measured(claim: Mapping[str, Any]) -> str:
    """"measured ± uncertainty" in the claim's unit ("0.86 % ± 0.012 %"); no "±" when the uncertainty is
    0 or absent (deterministic figures)."""
    unit = claim.get("unit") or ""
    s = fmt_value(claim.get("measured"), unit)
    u = claim.get("uncertainty")
    if u is None or (isinstance(u, Real) and float(u) == 0.0):
        return s
    return f"{s} ± {fmt_value(u, unit, UNCERTAINTY_DIGITS)}"


def fmt_threshold(claim: Mapping[str, Any]) -> str:
    """Comparison and threshold in the claim's unit: "< 1 %", "> 0"."""
    # thresholds are exact published figures (3/32 = 9.375 %): show up to THRESHOLD_DIGITS, not rounded to 3
    return (f"{claim.get('comparison') or '<'} "
            f"{fmt_value(claim.get('threshold'), claim.get('unit') or '', THRESHOLD_DIGITS)}")


def fmt_cell(value: Any) -> str:
    """A table cell or setting: numbers via :func:`fmt_num`, lists and dicts as compact JSON, else text."""
    if isinstance(value, (Mapping, list, tuple)):
        return json.dumps(value, ensure_ascii=False, default=str)
    return fmt_num(value)


def fmt_seconds(value: Any) -> str:
    """Wall time: "0.42 s", "12.3 s", "4 min 05 s", "1 h 02 min"."""
    if not isinstance(value, Real) or isinstance(value, bool) or not math.isfinite(float(value)):
        return "—"
    s = float(value)
    if s < 60.0:
        return f"{fmt_num(s)} s"
    m, sec = divmod(int(round(s)), 60)
    if m < 60:
        return f"{m} min {sec:02d} s"
    h, m = divmod(m, 60)
    return f"{h} h {m:02d} min"


def anchor(name: str) -> str:
    """HTML id for an experiment: "exp-" + name with anything but [A-Za-z0-9_-] replaced by "-"."""
    return "exp-" + re.sub(r"[^A-Za-z0-9_-]", "-", str(name))


# ---------------------------------------------------------------------------------------------------
# results.json
# ---------------------------------------------------------------------------------------------------

def _sorted_keys(value: Any) -> Any:
    if isinstance(value, Mapping):
        return {k: _sorted_keys(value[k]) for k in sorted(value, key=str)}
    if isinstance(value, (list, tuple)):
        return [_sorted_keys(v) for v in value]
    return value


def _json_default(path: Path):
    def default(obj: Any) -> Any:
        # numpy scalars and arrays (float32, int64, ndarray) carry .tolist(); Paths become strings.
        if hasattr(obj, "tolist"):
            return obj.tolist()
        if isinstance(obj, Path):
            return obj.as_posix()
        raise ValidateError(f"{path}: cannot store a {type(obj).__name__} value in JSON")
    return default


def write_results_json(out_dir: Path, results: Mapping[str, Any]) -> Path:
    """Write ``out_dir/results.json`` atomically (indent 2, UTF-8). Keys inside "meta" are sorted;
    everything else keeps its order (experiments appear on the page in dict order). NaN and ±inf are
    written as the JSON extensions NaN / Infinity that Python reads back."""
    path = Path(out_dir) / RESULTS_FILE
    doc = {k: (_sorted_keys(v) if k == "meta" else v) for k, v in results.items()}
    text = json.dumps(doc, indent=2, ensure_ascii=False, default=_json_default(path))
    return write_text(path, text + "\n")


def load_results(out_dir: Path) -> dict[str, Any]:
    """Read ``out_dir/results.json``: {} when absent; :class:`ValidateError` naming it when corrupt."""
    path = Path(out_dir) / RESULTS_FILE
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        return {}
    except (OSError, UnicodeDecodeError) as e:
        raise ValidateError(f"{path}: cannot read results ({e}); delete it to start afresh") from e
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        raise ValidateError(f"{path}: corrupt results file ({e.msg} at line {e.lineno} column {e.colno}); "
                            "delete it to start afresh") from e
    if not isinstance(doc, dict):
        raise ValidateError(f"{path}: corrupt results file (top level is a {type(doc).__name__}, "
                            "expected an object); delete it to start afresh")
    return doc


# ---------------------------------------------------------------------------------------------------
# Page model: the results dict with defaults filled in and figure paths checked
# ---------------------------------------------------------------------------------------------------

def _claim_passed(c: Mapping[str, Any]) -> bool:
    if "passed" in c:
        return bool(c["passed"])
    m, u, t = c.get("measured"), c.get("uncertainty") or 0.0, c.get("threshold")
    if not all(isinstance(x, Real) for x in (m, u, t)):
        return False
    return bool(m + u < t) if (c.get("comparison") or "<") == "<" else bool(m - u > t)


def page_name(experiment: str) -> str:
    """File name of an experiment's page: ``exp-<name>.html``."""
    return f"{anchor(experiment)}.html"


def _claim(c: Mapping[str, Any], experiment: str) -> dict[str, Any]:
    out = {"id": "", "description": "", "metric": "", "threshold": None, "measured": None,
           "uncertainty": 0.0, "comparison": "<", "unit": "", "source": "", "power": None}
    out.update(c)
    out.update(passed=_claim_passed(c), experiment=experiment, anchor=anchor(experiment),
               page=page_name(experiment), anchor_id="claim-" + re.sub(r"[^A-Za-z0-9_-]", "-", str(out["id"])))
    return out


def _figure(f: Mapping[str, Any], out_dir: Path) -> dict[str, Any]:
    """src relative to the report folder (posix), whether the file is there, caption and width."""
    raw = str(f.get("path", ""))
    root = out_dir.resolve()
    p = Path(raw)
    target = (p if p.is_absolute() else out_dir / p).resolve()
    try:
        rel = target.relative_to(root).as_posix()
        inside = True
    except ValueError:
        rel, inside = PurePosixPath(raw).as_posix(), False
    return {"src": rel, "caption": f.get("caption") or "", "width": f.get("width"),
            "exists": inside and target.is_file(),
            "problem": "" if inside else "outside the report folder"}


def _is_number(v: Any) -> bool:
    return isinstance(v, Real) and not isinstance(v, bool)


def _table(t: Mapping[str, Any]) -> dict[str, Any]:
    """Headers, rows, caption, and which columns hold only numbers (right-aligned, header included)."""
    headers, rows = list(t.get("headers") or []), [list(r) for r in t.get("rows") or []]
    numeric = [bool(rows) and all(i < len(r) and (_is_number(r[i]) or r[i] is None) for r in rows)
               for i in range(max([len(headers), *map(len, rows)]))]
    return {"headers": headers, "rows": rows, "caption": t.get("caption") or "", "numeric": numeric}


def _section(s: Mapping[str, Any], out_dir: Path, experiment: str, index: int) -> dict[str, Any]:
    return {
        "title": s.get("title") or "",
        "anchor": f"{anchor(experiment)}-s{index + 1}",
        "paragraphs": list(s.get("paragraphs") or []),
        "tables": [_table(t) for t in s.get("tables") or []],
        "gallery": [[_figure(f, out_dir) for f in row] for row in s.get("gallery") or []],
        "figures": [_figure(f, out_dir) for f in s.get("figures") or []],
    }


def _page(out_dir: Path, results: Mapping[str, Any]) -> dict[str, Any]:
    meta = results.get("meta") or {}
    experiments = results.get("experiments") or {}
    if not isinstance(meta, Mapping) or not isinstance(experiments, Mapping):
        raise ValidateError(f"{out_dir / RESULTS_FILE}: 'meta' and 'experiments' must be objects")
    exps: list[dict[str, Any]] = []
    for name, e in experiments.items():
        if not isinstance(e, Mapping):
            raise ValidateError(f"{out_dir / RESULTS_FILE}: experiment {name!r} is not an object")
        claims = [_claim(c, name) for c in e.get("claims") or []]
        exps.append({
            "name": name,
            "anchor": anchor(name),
            "title": e.get("title") or name,
            "summary": e.get("summary") or "",
            "findings": list(e.get("findings") or []),
            "wall_time_s": e.get("wall_time_s"),
            "settings": dict(e.get("settings") or {}),
            "claims": claims,
            "n_passed": sum(c["passed"] for c in claims),
            "n_power_fails": sum(bool((c.get("power") or {}).get("fails")) for c in claims),
            "page": page_name(name),
            "techniques": _techniques(e.get("techniques")),
            "sections": [_section(s, out_dir, name, i)
                         for i, s in enumerate((e.get("report") or {}).get("sections") or [])],
        })
    claims = [c for e in exps for c in e["claims"]]
    wall = meta.get("wall_time_s")
    if wall is None and exps:
        wall = sum(float(e["wall_time_s"] or 0.0) for e in exps)
    return {
        "title": PAGE_TITLE,
        "meta": {
            "generated": meta.get("generated") or "",
            "backend": meta.get("backend") or "unknown",
            "command": meta.get("command") or "",
            "quick": bool(meta.get("quick", False)),
            "wall_time_s": wall,
            "versions": dict(meta.get("versions") or {}),
            "skipped_inputs": [list(s) for s in meta.get("skipped_inputs") or []],
        },
        "experiments": exps,
        "claims": claims,
        "n_passed": sum(c["passed"] for c in claims),
        "n_failed": sum(not c["passed"] for c in claims),
        "results_file": RESULTS_FILE,
        "bench": _bench(out_dir),
    }


def _techniques(entries: Any) -> list[dict[str, Any]]:
    if not isinstance(entries, Mapping):
        return []
    return [{"name": k, "family": v.get("family", ""), "description": v.get("description", ""),
             "builtin": bool(v.get("builtin", True)), "module": v.get("module", ""),
             "thresholds": dict(v.get("thresholds") or {})}
            for k, v in entries.items() if isinstance(v, Mapping)]


def _bench(out_dir: Path) -> dict[str, Any] | None:
    """``bench.json`` beside the report (written by ``python -m validate bench``): its tables, if any."""
    path = Path(out_dir) / BENCH_FILE
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(doc, Mapping):
        return None
    tables = [_table(t) for t in doc.get("tables") or [] if isinstance(t, Mapping)]
    return {"generated": str(doc.get("generated") or ""), "tables": tables} if tables else None


@functools.lru_cache(maxsize=1)
def _environment() -> jinja2.Environment:
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(_TEMPLATES), autoescape=True,
                             undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True,
                             keep_trailing_newline=True)
    env.filters.update(num=fmt_num, pct=fmt_pct, value=fmt_value, measured=fmt_measured,
                       threshold=fmt_threshold, cell=fmt_cell, seconds=fmt_seconds)
    return env


def render_pages(out_dir: Path, results: Mapping[str, Any]) -> dict[str, str]:
    """Every page for ``results``: {file name: HTML} (figure paths resolved against ``out_dir``)."""
    env = _environment()
    page = _page(Path(out_dir), results)
    pages = {REPORT_FILE: env.get_template(TEMPLATE).render(page=page)}
    for e in page["experiments"]:
        pages[e["page"]] = env.get_template(EXPERIMENT_TEMPLATE).render(page=page, e=e)
    return pages


def render_report(out_dir: Path, results: Mapping[str, Any]) -> str:
    """The overview page (``index.html``) for ``results``."""
    return render_pages(out_dir, results)[REPORT_FILE]


def write_report(out_dir: Path, results: Mapping[str, Any]) -> Path:
    """Render every page from ``results`` and write them atomically (experiment pages first, the overview
    last); pages of experiments no longer in the results are removed. Returns the overview's path."""
    out_dir = Path(out_dir)
    pages = render_pages(out_dir, results)
    for name, text in pages.items():
        if name != REPORT_FILE:
            write_text(out_dir / name, text)
    for stale in out_dir.glob("exp-*.html"):
        if stale.name not in pages:
            stale.unlink(missing_ok=True)
    return write_text(out_dir / REPORT_FILE, pages[REPORT_FILE])
