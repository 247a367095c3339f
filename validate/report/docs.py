"""Measured figures in ``docs/`` that cannot drift: generated blocks rendered from a ``results.json``.

A Markdown file under ``docs/`` quotes measured numbers only inside generated blocks::

    <!-- results:begin sh9.claims -->
    ... (written by `python -m validate docs`; never edited by hand)
    <!-- results:end -->

The text between the markers is a pure function of the results dict: :func:`render_doc_blocks` maps
every block name to its Markdown. Names, for each experiment ``<exp>`` in ``results["experiments"]``:

* ``<exp>.claims``     one row per claim: id, measured ± uncertainty, threshold, pass, the power
  check (perturbation → measured, fails), then each claim's description and source;
* ``<exp>.findings``   the experiment's findings, one bullet each;
* ``<exp>.techniques`` every technique the experiment measured: family, built-in or plug-in,
  declared thresholds, description;
* ``<exp>.settings``   the settings the run used and the experiment's wall time;

and ``experiments`` (one row per experiment: claims passed, power checks failing, wall time). Each
block opens with one line naming the run it comes from (``meta.command``, quick or full, date,
Mitsuba/drjit versions, variant).

:func:`update_docs` rewrites every block of every ``*.md`` under ``docs_dir`` in place (atomically)
and stores the part of the results the blocks read in ``docs_dir/results.json`` (:func:`doc_subset`),
so that the committed docs can be checked against the committed subset without rerunning anything
(``tests/infra/test_docs.py``). The subset also keeps every technique's metrics (value, uncertainty,
unit and direction of each :class:`~validate.stats.Measured`, one line each), so that
``python -m validate compare docs/results.json NEW`` tracks every claim and technique metric against
the run the docs quote. With ``check=True`` nothing is written; the stale files are returned.
An unknown block name, an unclosed block, or results without ``experiments`` are
:class:`~validate.errors.ValidateError` naming the file.

Number formatting is the HTML report's (:mod:`validate.report.html`): fractions with ``unit == "%"``
as per cent, 3 significant digits for measured values, 2 for uncertainties, thresholds unrounded.
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..atomic import write_text
from ..errors import ValidateError
from ..stats import is_measured
from .html import claim_unit, fmt_cell, fmt_measured, fmt_seconds, fmt_threshold, fmt_value, setting_unit

BEGIN = re.compile(r"^<!-- results:begin (?P<name>[A-Za-z0-9_.-]+) -->[ \t]*$", re.MULTILINE)
END = "<!-- results:end -->"
SUBSET_FILE = "results.json"  # inside docs_dir: the figures the committed blocks were rendered from
_META_KEYS = ("command", "quick", "generated", "versions", "variant")
_EXPERIMENT_KEYS = ("title", "claims", "findings", "settings", "wall_time_s")
_TECHNIQUE_KEYS = ("family", "description", "builtin", "thresholds")
_MEASURED_KEYS = ("value", "uncertainty", "unit", "better")  # of a technique metric: what `compare` reads
_LEAF = re.compile(r'\{\n\s*("value": [^\n]*(?:\n\s*"(?:uncertainty|unit|better)": [^\n]*)*)\n\s*\}')


def doc_subset(results: Mapping[str, Any]) -> dict[str, Any]:
    """The part of a results dict the blocks read: ``meta`` (command, quick, generated, versions,
    variant) and, per experiment, title, claims, findings, settings, wall time and each technique's
    family, description, built-in flag, declared thresholds and metrics (each measured value's
    :data:`_MEASURED_KEYS`)."""
    meta = results.get("meta") or {}
    experiments = {}
    for name, exp in _experiments(results).items():
        entry = {k: exp[k] for k in _EXPERIMENT_KEYS if k in exp}
        entry["techniques"] = {t: {**{k: v[k] for k in _TECHNIQUE_KEYS if k in v},
                                   **({"metrics": _measured_subset(v["metrics"])} if v.get("metrics") else {})}
                               for t, v in (exp.get("techniques") or {}).items()}
        experiments[name] = entry
    return {"meta": {k: meta[k] for k in _META_KEYS if k in meta}, "experiments": experiments}


def _measured_subset(tree: Any) -> Any:
    if is_measured(tree):
        return {k: tree[k] for k in _MEASURED_KEYS if k in tree}
    if isinstance(tree, Mapping):
        return {k: _measured_subset(v) for k, v in tree.items()}
    return tree


def _experiments(results: Mapping[str, Any]) -> Mapping[str, Any]:
    exps = results.get("experiments")
    if not isinstance(exps, Mapping) or not exps:
        raise ValidateError("results: no experiments (run `python -m validate all` first)")
    return exps


def _cell(text: Any) -> str:
    """Table-cell text: pipes escaped, line breaks folded, ``<tag``-like runs defused."""
    s = str(text).replace("\\", "\\\\").replace("|", "\\|").replace("\n", " ")
    return re.sub(r"<(?=[A-Za-z/!])", "&lt;", s)


def _text(text: Any) -> str:
    """Paragraph text: as :func:`_cell` but pipes kept."""
    return re.sub(r"<(?=[A-Za-z/!])", "&lt;", str(text).replace("\n", " "))


def provenance(results: Mapping[str, Any]) -> str:
    """One line naming the run: "from a quick run (`python -m validate all --quick …`, 2026-12-01,
    Mitsuba 3.9.1, drjit 1.5.0, llvm_ad_rgb)"."""
    meta = results.get("meta") or {}
    kind = "quick" if meta.get("quick") else "full"
    v = meta.get("versions") or {}
    parts = [f"`{meta['command']}`" if meta.get("command") else "command not recorded",
             str(meta.get("generated", ""))[:10] or "date not recorded"]
    parts += [f"{lib} {v[key]}" for lib, key in (("Mitsuba", "mitsuba"), ("drjit", "drjit")) if key in v]
    if meta.get("variant"):
        parts.append(str(meta["variant"]))
    return (f"*Generated by `python -m validate docs` from the {kind} run ({', '.join(parts)}); "
            "do not edit by hand.*")


def _power(c: Mapping[str, Any]) -> tuple[str, str]:
    p = c.get("power")
    if not p:
        return "none", "—"
    measured = fmt_measured({"measured": p.get("measured"), "uncertainty": p.get("uncertainty"),
                             "unit": c.get("unit")})
    return f"{_cell(p.get('perturbation', ''))} → {measured}", "yes" if p.get("fails") else "**no**"


def render_claims(name: str, exp: Mapping[str, Any]) -> str:
    """Claims table (id, measured ± uncertainty, threshold, passes, power → measured, power fails), then
    one line per claim with its description and source."""
    claims = exp.get("claims") or []
    passed = sum(bool(c.get("passed")) for c in claims)
    fails = sum(bool((c.get("power") or {}).get("fails")) for c in claims)
    lines = [f"{passed}/{len(claims)} claims pass; {fails}/{len(claims)} power checks fail (as they must).", "",
             "| claim | unit | measured (unit) | threshold (unit) | passes | power check → measured | power fails |",
             "|---|---|---|---|---|---|---|"]
    for c in claims:
        power, power_fails = _power(c)
        lines.append(f"| `{c['id']}` | {claim_unit(c)} | {_cell(fmt_measured(c))} | {_cell(fmt_threshold(c))} | "
                     f"{'yes' if c.get('passed') else '**no**'} | {power} | {power_fails} |")
    lines += ["", "Descriptions and sources:", ""]
    lines += [f"- `{c['id']}` — {_text(c.get('description', ''))} *Source:* {_text(c.get('source') or '—')}"
              for c in claims]
    return "\n".join(lines)


def render_findings(name: str, exp: Mapping[str, Any]) -> str:
    findings = exp.get("findings") or []
    return "\n".join(f"- {_text(f)}" for f in findings) if findings else "(no findings recorded)"


def render_techniques(name: str, exp: Mapping[str, Any]) -> str:
    techniques = exp.get("techniques") or {}
    if not techniques:
        return "(no registered techniques measured)"
    lines = ["| technique | family | kind | declared thresholds (–) | description |", "|---|---|---|---|---|"]
    for t, v in techniques.items():
        thr = ", ".join(f"`{k}` < {fmt_value(x, '', 4)}" for k, x in (v.get("thresholds") or {}).items()) or "—"
        kind = "built-in" if v.get("builtin", True) else "plug-in"
        lines.append(f"| `{t}` | {v.get('family', '—')} | {kind} | {_cell(thr)} | {_cell(v.get('description', ''))} |")
    return "\n".join(lines)


def render_settings(name: str, exp: Mapping[str, Any]) -> str:
    settings = exp.get("settings") or {}
    lines = [f"Wall time of the experiment in that run: {fmt_seconds(exp.get('wall_time_s'))}.", ""]
    if settings:
        lines += ["| setting | value (unit) | unit |", "|---|---|---|"]
        lines += [f"| `{k}` | {_cell(fmt_cell(v))} | {setting_unit(k)} |" for k, v in settings.items()]
    return "\n".join(lines)


def render_overview(results: Mapping[str, Any]) -> str:
    """One row per experiment: title, claims passed, power checks failing, wall time."""
    lines = ["| experiment | title | claims pass (count) | power checks fail (count) | wall time |",
             "|---|---|---|---|---|"]
    total = passed = fails = 0
    for name, exp in _experiments(results).items():
        claims = exp.get("claims") or []
        p = sum(bool(c.get("passed")) for c in claims)
        f = sum(bool((c.get("power") or {}).get("fails")) for c in claims)
        total, passed, fails = total + len(claims), passed + p, fails + f
        lines.append(f"| [`{name}`]({name}.md) | {_cell(exp.get('title', ''))} | {p}/{len(claims)} | "
                     f"{f}/{len(claims)} | {fmt_seconds(exp.get('wall_time_s'))} |")
    lines.append(f"| all | | {passed}/{total} | {fails}/{total} | |")
    return "\n".join(lines)


_PARTS = {"claims": render_claims, "findings": render_findings, "techniques": render_techniques,
          "settings": render_settings}


def render_doc_blocks(results: Mapping[str, Any]) -> dict[str, str]:
    """Every block name → its Markdown (provenance line first), for the experiments in ``results``."""
    head = provenance(results)
    blocks = {"experiments": f"{head}\n\n{render_overview(results)}"}
    for name, exp in _experiments(results).items():
        for part, render in _PARTS.items():
            blocks[f"{name}.{part}"] = f"{head}\n\n{render(name, exp)}"
    return blocks


def fill_blocks(text: str, blocks: Mapping[str, str], where: str) -> str:
    """``text`` with the body of every ``results:begin NAME`` … ``results:end`` block replaced by
    ``blocks[NAME]``; :class:`ValidateError` naming ``where`` for an unknown name or a missing end."""
    out, pos = [], 0
    for m in BEGIN.finditer(text):
        if m.start() < pos:
            raise ValidateError(f"{where}: block '{m['name']}' starts inside another block")
        end = text.find(END, m.end())
        if end < 0:
            raise ValidateError(f"{where}: block '{m['name']}' has no '{END}'")
        if m["name"] not in blocks:
            raise ValidateError(f"{where}: unknown results block '{m['name']}' (the results have no such "
                                "experiment or part)")
        out += [text[pos:m.end()], "\n", blocks[m["name"]], "\n"]
        pos = end
    out.append(text[pos:])
    return "".join(out)


def block_names(text: str) -> list[str]:
    """The names of the generated blocks in ``text``, in order."""
    return [m["name"] for m in BEGIN.finditer(text)]


def _subset_text(results: Mapping[str, Any]) -> str:
    """:func:`doc_subset` as JSON (indent 1), each measured value on one line."""
    text = json.dumps(doc_subset(results), indent=1, ensure_ascii=False)
    return _LEAF.sub(lambda m: "{" + re.sub(r"\n\s*", " ", m[1]) + "}", text) + "\n"


def load_results_file(path: Path) -> dict[str, Any]:
    """Read a results.json; :class:`ValidateError` naming it when missing or corrupt."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ValidateError(f"{path}: results file not found (run `python -m validate all` first)") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise ValidateError(f"{path}: cannot read results ({e})") from None
    if not isinstance(doc, dict):
        raise ValidateError(f"{path}: corrupt results file (top level is not an object)")
    return doc


def update_docs(results_path: Path, docs_dir: Path, check: bool = False) -> list[Path]:
    """Render every generated block of every ``*.md`` under ``docs_dir`` from ``results_path`` and
    store :func:`doc_subset` in ``docs_dir/results.json``. Returns the files whose content differs
    (with ``check=True`` they are only reported, nothing is written)."""
    docs_dir = Path(docs_dir)
    if not docs_dir.is_dir():
        raise ValidateError(f"{docs_dir}: docs folder not found")
    results = load_results_file(Path(results_path))
    if not isinstance(results.get("experiments"), Mapping) or not results["experiments"]:
        raise ValidateError(f"{results_path}: no experiments in the results (run `python -m validate all` first)")
    blocks = render_doc_blocks(results)
    changed: dict[Path, str] = {}
    for md in sorted(docs_dir.rglob("*.md")):
        old = md.read_text(encoding="utf-8")
        new = fill_blocks(old, blocks, str(md))
        if new != old:
            changed[md] = new
    subset_path = docs_dir / SUBSET_FILE
    subset = _subset_text(results)
    if not subset_path.is_file() or subset_path.read_text(encoding="utf-8") != subset:
        changed[subset_path] = subset
    if not check:
        for path, text in changed.items():
            write_text(path, text)
    return list(changed)
