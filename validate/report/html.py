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
``templates/style.css``, the comparison script inlined, no external resources) whose images are paths relative to the
report folder, so the folder can be moved or zipped and opened from disk. Templates are rendered
by Jinja2 with autoescaping on: every string
from the results (paragraphs, captions, findings) is text, never markup.

Number formatting (Jinja filters ``num``, ``pct``, ``measured``, ``threshold``, ``cell``) goes through
:mod:`validate.format`: ``unit == "%"`` marks fractions shown as per cent (0.0086 → "0.86 %"); a
value with an uncertainty shows the digits the uncertainty supports ("0.860 ± 0.010 %"); other values
use 3 significant digits, scientific below 10⁻³ and from 10⁶ (1.2e-5). Every column of every table names
its unit (:func:`validate.format.missing_units`, ``tests/infra/test_report_units.py``): the claims and the
"changes since" rows, whose units differ from row to row, carry a Unit column ("%" or "–", dimensionless) and
headers ending "(unit)"; the overview's wall time is in seconds; a setting's unit is the one its name states.

Each experiment page opens with its summary figure (:mod:`.summary`, drawn by :func:`write_report`
into ``figures/summary/``) and a three-line verdict; findings are grouped (:mod:`.findings`); gallery
rows holding a truth / technique / error set (:mod:`.imagesets`) get a wipe slider and a linked error
map, driven by a small script inlined in the page (``templates/compare.js``, no external resources).
A top-level ``changes`` entry (written by ``--baseline``, :mod:`validate.report.compare`) becomes the
overview's "Changes since <baseline>" section.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import re
from collections.abc import Mapping
from numbers import Real
from pathlib import Path, PurePosixPath
from typing import Any

import jinja2

from .. import format as fmt
from ..atomic import write_text
from ..errors import ValidateError
from . import findings as findings_mod
from . import imagesets, summary

RESULTS_FILE = "results.json"
REPORT_FILE = "index.html"
BENCH_FILE = "bench.json"
EXPERIMENT_TEMPLATE = "experiment.html.j2"
PAGE_TITLE = "validate — real-time lighting vs physics"
TEMPLATE = "index.html.j2"
MEASURED_DIGITS = 3  # significant digits of measured values and thresholds
UNCERTAINTY_DIGITS = 2  # significant digits of uncertainties
THRESHOLD_DIGITS = 4  # thresholds are exact figures (3/32 = 9.375 %), shown without rounding them up
SUMMARY_DIR = "figures/summary"  # summary figures, drawn by write_report from results.json
_TEMPLATES = Path(__file__).parent / "templates"


# ---------------------------------------------------------------------------------------------------
# Number formatting
# ---------------------------------------------------------------------------------------------------

def fmt_num(value: Any, digits: int = MEASURED_DIGITS) -> str:
    """Compact number (:func:`validate.format.sig`): ``digits`` significant digits; scientific (1.23e-5)
    for |v| < 10⁻³ or ≥ 10⁶; integers as written; None → "—"; NaN → "NaN"; ±inf → "∞"/"−∞";
    booleans → "yes"/"no". Non-numbers are returned as text."""
    if isinstance(value, bool):
        return "yes" if value else "no"
    return fmt.sig(value, digits)


def fmt_pct(value: Any, digits: int = MEASURED_DIGITS) -> str:
    """A fraction as per cent: 0.0086 → "0.86 %" (:func:`validate.format.pct`); non-numbers as text."""
    if isinstance(value, Real) and not isinstance(value, bool) and math.isfinite(float(value)):
        return fmt.pct(value, digits)
    return fmt_num(value, digits)


def fmt_value(value: Any, unit: str = "", digits: int = MEASURED_DIGITS) -> str:
    """Value with its unit (:func:`validate.format.fmt_quantity`): "%" → per cent of a fraction;
    another unit is appended ("0.5 sr")."""
    if unit == "%":
        return fmt_pct(value, digits)
    s = fmt_num(value, digits)
    return f"{s} {unit}" if unit and value is not None else s


def fmt_measured(claim: Mapping[str, Any]) -> str:
    """"measured ± uncertainty unit" with the digits the uncertainty supports
    (:func:`validate.format.pm`: "0.860 ± 0.010 %"); the value alone, with MEASURED_DIGITS, when the
    uncertainty is 0 or absent (deterministic figures)."""
    unit = claim.get("unit") or ""
    m, u = claim.get("measured"), claim.get("uncertainty")
    if not (isinstance(u, Real) and not isinstance(u, bool) and math.isfinite(float(u)) and float(u) > 0.0):
        return fmt_value(m, unit)
    if not (isinstance(m, Real) and not isinstance(m, bool)):
        return fmt_value(m, unit)
    return fmt.pm(m, u, unit)


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


def fmt_in_seconds(value: Any) -> str:
    """Wall time as a number of seconds for a "(s)" column: 3 significant digits, "—" when absent."""
    if not isinstance(value, Real) or isinstance(value, bool) or not math.isfinite(float(value)):
        return "—"
    return fmt_num(float(value))


DIMENSIONLESS = "–"  # the unit of a number shown as it is (validate.format.UNITS)


def claim_unit(claim: Mapping[str, Any]) -> str:
    """The unit a claim's measured value and threshold are shown in: its ``unit`` ("%": a fraction shown as per
    cent), "–" for a dimensionless claim (``unit`` empty)."""
    return str(claim.get("unit") or "") or DIMENSIONLESS


# A setting's unit, where its name states it: "beta_step_deg" → °, "sphere_px" → px, "meter_spp" → count
# (samples per pixel), "passes" → count; other settings are listed as configured and their unit is "—" (not stated).
SETTING_UNITS = (("_deg", "°"), ("_px", "px"), ("spp", "count"), ("passes", "count"))


def setting_unit(name: str) -> str:
    """The unit of a setting whose name states it (:data:`SETTING_UNITS`); "—" otherwise."""
    return next((u for suffix, u in SETTING_UNITS if str(name).endswith(suffix)), fmt.DASH)


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
    out.update(passed=_claim_passed(c), experiment=experiment, anchor=anchor(experiment), unit_shown=claim_unit(out),
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


def _gallery_row(row: list[Any], out_dir: Path) -> dict[str, Any]:
    """A gallery row: its figures, and the truth / technique / error set in it (None when there is none)."""
    figs = [_figure(f, out_dir) for f in row]
    return {"figures": figs, "compare": imagesets.find_set(figs, out_dir)}


def _section(s: Mapping[str, Any], out_dir: Path, experiment: str, index: int) -> dict[str, Any]:
    return {
        "title": s.get("title") or "",
        "anchor": f"{anchor(experiment)}-s{index + 1}",
        "paragraphs": list(s.get("paragraphs") or []),
        "tables": [_table(t) for t in s.get("tables") or []],
        "gallery": [_gallery_row(list(row), out_dir) for row in s.get("gallery") or []],
        "figures": [_figure(f, out_dir) for f in s.get("figures") or []],
    }


def summary_path(experiment: str, spec: summary.Summary) -> str:
    """Report-relative path of an experiment's summary figure, named by what it shows:
    ``figures/summary/exp-<name>-<hash of the plotted numbers>.png`` (an unchanged figure is not redrawn)."""
    digest = hashlib.sha1(repr((summary.FIGURE_VERSION, spec)).encode("utf-8")).hexdigest()[:12]
    return f"{SUMMARY_DIR}/{anchor(experiment)}-{digest}.png"


def matrix_path(experiment: str, spec: summary.Spread) -> str:
    """Report-relative path of the full matrix beside a :class:`~.summary.Spread` summary."""
    return summary_path(experiment, spec).replace(".png", "-matrix.png")


def _accept_grid(spec: summary.Acceptance, out_dir: Path) -> dict[str, Any]:
    """The engine × scene acceptance matrix as HTML cells (scenes down, engines across, in two blocks side by
    side): per cell its per cent, reference, colour, title and the anchor of the scene's strip."""
    from .summary_plots import accept_colour  # matplotlib's colour maps: loaded only when pages are written

    rows = []
    for j, scene in enumerate(spec.cols):
        strip = spec.strips[j]
        cells = []
        for i, engine in enumerate(spec.rows):
            v, ref, skipped = spec.values[i][j], spec.refs[i][j], spec.skipped[i][j]
            measured = math.isfinite(v)
            text = f"{100 * v:.1f} %" if measured else ("skipped" if skipped else "—")
            title = (f"{engine} on {scene}: {text} of the pixels accepted against the {ref} reference"
                     + (f"; also {spec.others[i][j]}" if spec.others[i][j] else "") if measured else
                     f"{engine} on {scene}: skipped — {skipped}" if skipped else f"{engine} did not render {scene}")
            cells.append({"text": text, "ref": ref if measured else "", "colour": accept_colour(v),
                          "title": title, "measured": measured})
        rows.append({"scene": scene, "cells": cells, "href": f"#{strip_anchor(scene)}" if strip else "",
                     "strip": strip})
    half = (len(rows) + 1) // 2
    return {"engines": list(spec.rows), "blocks": [rows[:half], rows[half:]] if len(rows) > 8 else [rows]}


def strip_anchor(scene: str) -> str:
    """HTML id of a scene's image strip on the renders page."""
    return "strip-" + re.sub(r"[^A-Za-z0-9_-]", "-", str(scene))


def _summary(name: str, e: Mapping[str, Any], claims: list[dict[str, Any]], out_dir: Path) -> dict[str, Any]:
    """The summary figure (path, caption, whether drawn, the size its text is drawn at), the verdict lines, and
    where the spec has them: the acceptance grid and its image strips, the full matrix further down."""
    spec = summary.summary_for(name, e)
    out: dict[str, Any] = {"figure": None, "verdict": summary.verdict(spec, claims), "grid": None, "strips": [],
                           "matrix": None, "font_px": round(summary.FONT_PX, 2)}
    if spec is None:
        return out
    out["figure"] = _figure({"path": summary_path(name, spec), "caption": f"{spec.title} — {spec.metric}"}, out_dir)
    if isinstance(spec, summary.Acceptance):
        out["grid"] = _accept_grid(spec, out_dir)
        out["strips"] = [dict(_figure({"path": p, "caption": f"{scene}: truth | engine | error"}, out_dir),
                              anchor=strip_anchor(scene), scene=scene)
                         for scene, p in zip(spec.cols, spec.strips, strict=True) if p]
    if isinstance(spec, summary.Spread) and spec.matrix is not None:
        out["matrix"] = _figure({"path": matrix_path(name, spec),
                                 "caption": f"{spec.matrix.title} — {spec.matrix.metric}"}, out_dir)
    return out


def _experiment(name: str, e: Mapping[str, Any], out_dir: Path) -> dict[str, Any]:
    claims = [_claim(c, name) for c in e.get("claims") or []]
    techniques = _techniques(e.get("techniques"))
    findings = list(e.get("findings") or [])
    overview = _summary(name, e, claims, out_dir)
    sections = [_section(s, out_dir, name, i) for i, s in enumerate((e.get("report") or {}).get("sections") or [])]
    strips = {f["src"] for f in overview["strips"]}
    for s in sections:  # the strips are shown once, beside the findings
        s["figures"] = [f for f in s["figures"] if f["src"] not in strips]
    return {
        "name": name,
        "anchor": anchor(name),
        "title": e.get("title") or name,
        "summary": e.get("summary") or "",
        "findings": findings,
        "finding_groups": findings_mod.group_findings(findings, [t["name"] for t in techniques],
                                                      findings_mod.input_names(e)),
        "wall_time_s": e.get("wall_time_s"),
        "settings": [{"name": k, "value": v, "unit": setting_unit(k)}
                     for k, v in dict(e.get("settings") or {}).items()],
        "claims": claims,
        "n_passed": sum(c["passed"] for c in claims),
        "n_power_fails": sum(bool((c.get("power") or {}).get("fails")) for c in claims),
        "page": page_name(name),
        "techniques": techniques,
        "overview": overview,
        "not_run": [_not_run_line(n) for n in e.get("not_run") or []],
        "sections": sections,
    }


def _not_run_line(n: Mapping[str, Any]) -> str:
    """One line of an experiment's ``not_run`` entry (:class:`validate.experiments.base.NotRun`)."""
    fix = f" — run `{n['fix']}`" if n.get("fix") else ""
    return f"{n.get('what', '?')} not run: {n.get('why', '')}{fix}"


_STATUS_ORDER = ("regressed", "newly_failing", "removed", "new", "changed", "improved")


def _changes(changes: Any, exps: list[dict[str, Any]]) -> dict[str, Any] | None:
    """The ``changes`` entry (validate.report.compare) for the overview: rows other than "unchanged",
    regressions first; claim values in their claim's unit."""
    if not isinstance(changes, Mapping):
        return None
    units = {key: c.get("unit") or "" for e in exps for c in e["claims"]  # the keys of validate.report.compare
             for key in (c["id"], f"{c.get('experiment')}/{c['id']}")}
    rows = [dict(r) for r in changes.get("rows") or [] if isinstance(r, Mapping) and r.get("status") != "unchanged"]
    rank = {s: i for i, s in enumerate(_STATUS_ORDER)}
    rows.sort(key=lambda r: rank.get(str(r.get("status")), len(rank)))
    for r in rows:
        # a measured value's row carries its unit (validate.stats.Measured; "" in rows from before the schema)
        unit = units.get(str(r.get("key")), "") if r.get("kind") == "claim" else str(r.get("unit") or "")
        r["old_text"] = fmt_quantity(r.get("old"), r.get("old_uncertainty"), unit)
        r["new_text"] = fmt_quantity(r.get("new"), r.get("new_uncertainty"), unit)
        r["change_text"] = fmt_quantity(r.get("change"), None, unit)
        # a claim this run lacks: its unit is not known
        known = r.get("kind") != "claim" or str(r.get("key")) in units
        r["unit_shown"] = (unit or DIMENSIONLESS) if known else fmt.DASH
    return {"baseline": str(changes.get("baseline") or "the baseline"), "rows": rows,
            "regressions": changes.get("regressions", 0)}


def fmt_quantity(value: Any, sigma: Any = None, unit: str = "") -> str:
    """A value from results.json with its σ and unit (:func:`validate.format.fmt_quantity`); booleans as
    "pass" / "fail", None as "—", text as it is."""
    if isinstance(value, bool):
        return "pass" if value else "fail"
    if not isinstance(value, Real):
        return fmt_num(value)
    s = sigma if isinstance(sigma, Real) and not isinstance(sigma, bool) and math.isfinite(float(sigma)) else None
    return fmt.fmt_quantity(value, unit, s if s and s > 0 else None)



def _clamped(meta: dict[str, Any]) -> list[list[Any]]:
    """[environment, texels, min] for each environment whose float-noise negatives were clamped to 0
    (``meta.environments.<name>.clamped_negative``, validate.scenes.loaders)."""
    out = []
    for name, env in (meta.get("environments") or {}).items():
        c = (env or {}).get("clamped_negative") if isinstance(env, dict) else None
        if c:
            out.append([name, c.get("texels"), c.get("min")])
    return out

def _page(out_dir: Path, results: Mapping[str, Any]) -> dict[str, Any]:
    meta = results.get("meta") or {}
    experiments = results.get("experiments") or {}
    if not isinstance(meta, Mapping) or not isinstance(experiments, Mapping):
        raise ValidateError(f"{out_dir / RESULTS_FILE}: 'meta' and 'experiments' must be objects")
    exps: list[dict[str, Any]] = []
    for name, e in experiments.items():
        if not isinstance(e, Mapping):
            raise ValidateError(f"{out_dir / RESULTS_FILE}: experiment {name!r} is not an object")
        exps.append(_experiment(name, e, out_dir))
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
            "clamped_inputs": _clamped(meta),
        },
        "experiments": exps,
        "claims": claims,
        "n_passed": sum(c["passed"] for c in claims),
        "n_failed": sum(not c["passed"] for c in claims),
        "results_file": RESULTS_FILE,
        "bench": _bench(out_dir),
        "changes": _changes(results.get("changes"), exps),
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
                       threshold=fmt_threshold, cell=fmt_cell, seconds=fmt_seconds,
                       in_seconds=fmt_in_seconds)
    return env


def render_pages(out_dir: Path, results: Mapping[str, Any]) -> dict[str, str]:
    """Every page for ``results``: {file name: HTML} (figure paths resolved against ``out_dir``)."""
    env = _environment()
    page = _page(Path(out_dir), results)
    pages = {REPORT_FILE: env.get_template(TEMPLATE).render(page=page)}
    for e in page["experiments"]:
        pages[e["page"]] = env.get_template(EXPERIMENT_TEMPLATE).render(page=page, e=e)
    return pages


def draw_summaries(out_dir: Path, results: Mapping[str, Any]) -> list[Path]:
    """Draw every experiment's summary figure (:mod:`.summary`) into ``out_dir/figures/summary/``, unless
    the file for the same numbers is already there; other files in that folder are removed."""
    from . import summary_plots  # matplotlib: loaded only when pages are written

    out_dir = Path(out_dir)
    experiments = results.get("experiments") or {}
    written = []
    for name, e in experiments.items() if isinstance(experiments, Mapping) else ():
        spec = summary.summary_for(name, e) if isinstance(e, Mapping) else None
        if spec is not None:
            path = out_dir / summary_path(name, spec)
            if not path.is_file():
                summary_plots.draw(spec, path)
            written.append(path)
            if isinstance(spec, summary.Spread) and spec.matrix is not None:
                path = out_dir / matrix_path(name, spec)
                if not path.is_file():
                    summary_plots.draw_matrix(spec.matrix, path)
                written.append(path)
    for stale in (out_dir / SUMMARY_DIR).glob("*.png"):
        if stale not in written:
            stale.unlink(missing_ok=True)
    return written


def render_report(out_dir: Path, results: Mapping[str, Any]) -> str:
    """The overview page (``index.html``) for ``results``."""
    return render_pages(out_dir, results)[REPORT_FILE]


def write_report(out_dir: Path, results: Mapping[str, Any]) -> Path:
    """Render every page from ``results`` and write them atomically (experiment pages first, the overview
    last); pages of experiments no longer in the results are removed. Returns the overview's path."""
    out_dir = Path(out_dir)
    draw_summaries(out_dir, results)
    pages = render_pages(out_dir, results)
    for name, text in pages.items():
        if name != REPORT_FILE:
            write_text(out_dir / name, text)
    for stale in out_dir.glob("exp-*.html"):
        if stale.name not in pages:
            stale.unlink(missing_ok=True)
    return write_text(out_dir / REPORT_FILE, pages[REPORT_FILE])
