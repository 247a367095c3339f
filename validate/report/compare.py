"""Compare two runs: ``python -m validate compare OLD.json NEW.json [--strict]``.

For every claim, every technique metric and every judgement present in either ``results.json``, one
:class:`Row`: the old and new value with their uncertainties, the change new − old, and whether it
exceeds the combined uncertainty

    σ = √(σ_old² + σ_new²)        (independent runs; each σ as the run recorded it)

A value recorded without an uncertainty (``None``, absent, or NaN) counts as σ = 0: the suite is
deterministic (fixed seeds, cached references), so two runs of unchanged code give identical
numbers and any change beyond float round-off, ``ROUNDOFF`` = 10⁻⁹ × max(|old|, |new|), is
real. The same round-off floor applies when both uncertainties are given.

What is read. Technique metrics and judgements are measured values in the one schema of
:class:`validate.stats.Measured` (``{"value", "uncertainty", "unit"}``, optional ``stat``, ``better``):

* a claim is its ``id`` (experiments prefix their ids with their name; an id that does not is
  written ``<experiment>/<id>``);
* a technique metric is ``<experiment>/<technique>/<metric>``, where ``<metric>`` is the path of a
  measured value under the technique's ``metrics`` (``flux_luminance.max``, ``point/bias``,
  ``constant/flux_rgb/max``);
* a judgement is ``<experiment>/<path>``: a measured value inside any ``judgements`` (or
  ``judgement``) object of an experiment's entry outside ``techniques`` — the renders' engine × scene
  judgements, ``renders/scenes/<scene>/engines/<engine>/judgements/<kind>/fraction_accepted``.

Old files. A ``results.json`` written before that schema still loads: its technique metrics as
``{"value", "uncertainty"}`` without a unit, ``{"mean", "max", "rms", "mean_uncertainty",
"max_uncertainty"}`` (sh9, engines: one value per statistic, ``…/mean``, ``…/max``, ``…/rms``, rms
without an uncertainty) or a bare number (worstcase: no uncertainty), and its judgements as flat
dicts (``fraction_accepted``, ``max_abs_z``, ``mean_rel`` ± ``mean_rel_unc``, ``max_rel`` ±
``max_rel_unc``, ``mean_signed_rel``) give the same keys as the new shape, so an old and a new run
of the same code compare as unchanged; :attr:`Comparison.notes` says which file is old.

Status of a row:

* ``new`` / ``removed``: present in one run only;
* claims: ``newly_failing`` (passed, now fails: a regression), ``improved`` (failed, now passes),
  ``changed`` (same verdict, a different value), ``unchanged``;
* technique metrics and judgements: ``regressed`` (worse beyond σ: a regression), ``improved`` (better
  beyond σ), ``changed`` (different, within σ, or as good: a signed error whose sign flipped),
  ``unchanged``;
* a piece an experiment could not run (its ``not_run`` entries, keyed ``<experiment>/not_run/<what>``, no
  values): ``regressed`` when the new run left out what the old one ran (nothing judged is not a pass),
  ``improved`` the other way round, ``unchanged`` when both left it out.

Which way is worse. A measured value says it (``better``: ``"lower"``, ``"higher"`` — a score, the
fraction of pixels a judgement accepts — or ``"zero"``: a signed error, larger |value| is worse); the
newer file's word counts. Without it (the default, and old files) a technique metric is an error:
technique thresholds are upper bounds (:func:`validate.experiments.techniques.technique_claims` judges
``metric < limit``), so larger is worse; a signed metric (its last name part contains ``bias``, or
either value is negative) is an error by its magnitude; scores, higher is better, are recognised by a
last name part in :data:`HIGHER_IS_BETTER` (``fraction_accepted`` of an old judgement among them).

:func:`compare` is the function (also ``validate.testing.compare``); ``Comparison.to_json()`` is the
``changes`` entry ``all``/``run --baseline OLD.json`` writes into ``results.json``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterator, Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ValidateError
from ..format import pm, sig
from ..stats import is_measured

ROUNDOFF = 1e-9  # relative: below this, two values are the same number (float64 round-off of a re-run)
HIGHER_IS_BETTER = ("psnr", "ssim", "score", "correlation", "r2", "fraction_accepted")
REGRESSION_STATUSES = ("regressed", "newly_failing")
KINDS = ("claim", "metric", "judgement", "not_run")
JUDGEMENT_KEYS = ("judgements", "judgement")  # objects whose measured values are judgements
OLD_NOTE = "written before the measured-value schema; read its old shapes"
_STATS = ("mean", "max", "rms")  # the statistics of an old {mean, max, rms, *_uncertainty} metric
# an old flat judgement: value key → its uncertainty key (None: none recorded)
_OLD_JUDGEMENT = {"fraction_accepted": None, "max_abs_z": None, "mean_rel": "mean_rel_unc",
                  "max_rel": "max_rel_unc", "mean_signed_rel": None}


@dataclass(frozen=True)
class Row:
    """One compared claim or technique metric (the ``changes.rows`` schema of ``results.json``)."""

    kind: str  # "claim" | "metric" | "judgement" | "not_run"
    key: str
    old: float | None
    new: float | None
    old_uncertainty: float | None
    new_uncertainty: float | None
    change: float | None
    exceeds_uncertainty: bool
    status: str
    unit: str = ""  # a claim's or measured value's unit ("%": a fraction shown as per cent)


@dataclass
class Comparison:
    """Every row of two runs, the regressions among them, and notes on how the files were read."""

    baseline: str
    rows: list[Row] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def regressions(self) -> list[Row]:
        return [r for r in self.rows if r.status in REGRESSION_STATUSES]

    @property
    def changed(self) -> list[Row]:
        return [r for r in self.rows if r.status != "unchanged"]

    def to_json(self) -> dict[str, Any]:
        return {"baseline": self.baseline, "regressions": len(self.regressions), "notes": list(self.notes),
                "rows": [asdict(r) for r in self.rows]}

    def counts(self) -> dict[str, dict[str, int]]:
        """experiment → {kind: rows compared}, every kind of :data:`KINDS` (0 where there are none)."""
        out: dict[str, dict[str, int]] = {}
        for r in self.rows:
            exp = r.key.split("/", 1)[0] if "/" in r.key else r.key.split(".", 1)[0]
            out.setdefault(exp, dict.fromkeys(KINDS, 0))[r.kind] += 1
        return out

    def summary(self) -> str:
        counts: dict[str, int] = {}
        for r in self.rows:
            counts[r.status] = counts.get(r.status, 0) + 1
        parts = ", ".join(f"{counts[s]} {s.replace('_', ' ')}" for s in
                          ("regressed", "newly_failing", "improved", "changed", "new", "removed", "unchanged")
                          if counts.get(s))
        n = {k: sum(r.kind == k for r in self.rows) for k in KINDS}
        return (f"{len(self.regressions)} regression(s) against {self.baseline}: {n['claim']} claims, "
                f"{n['metric']} technique metrics and {n['judgement']} judgements compared "
                f"({parts or 'nothing to compare'})")

    def per_experiment(self) -> str:
        """One line per experiment: claims, technique metrics and judgements compared."""
        counts = self.counts()
        width = max((len(e) for e in counts), default=0)
        return "\n".join(f"  {e:<{width}}  {c['claim']:4d} claims  {c['metric']:5d} technique metrics  "
                         f"{c['judgement']:4d} judgements" for e, c in counts.items())

    def table(self) -> str:
        """The changed rows as an aligned text table (empty string when nothing changed)."""
        rows = self.changed
        if not rows:
            return ""
        head = ("status", "kind", "key", "old", "new", "change", "> σ")
        body = [(r.status, r.kind, r.key, _pm(r.old, r.old_uncertainty, r.unit), _pm(r.new, r.new_uncertainty, r.unit),
                 _pm(r.change, None, r.unit), "yes" if r.exceeds_uncertainty else "no") for r in rows]
        widths = [max(len(x[i]) for x in [head, *body]) for i in range(len(head))]
        right = {3, 4, 5}
        lines = ["  ".join(c.rjust(w) if i in right else c.ljust(w)
                           for i, (c, w) in enumerate(zip(x, widths, strict=True))) for x in [head, *body]]
        return "\n".join(line.rstrip() for line in lines)


def _pm(v: float | None, u: float | None, unit: str = "") -> str:
    """A value (4 significant digits) or value ± uncertainty (digits the uncertainty supports), in ``unit``
    ("%": the fraction as per cent)."""
    if unit == "%" and v is not None:
        return _pm(100.0 * v, None if u is None else 100.0 * u) + " %"
    text = sig(v, 4) if u is None or v is None or u == 0 else pm(v, u)
    return f"{text} {unit}" if unit and v is not None else text


def _float(v: Any) -> float | None:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def load(source: str | Path | Mapping[str, Any]) -> tuple[str, Mapping[str, Any]]:
    """(label, results dict) from a path to a ``results.json`` (or its folder) or an already loaded dict."""
    if isinstance(source, Mapping):
        return "(results)", source
    path = Path(source)
    if path.is_dir():
        path = path / "results.json"
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ValidateError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValidateError(f"{path}: cannot read ({getattr(exc, 'strerror', None) or exc})") from None
    except ValueError as exc:
        raise ValidateError(f"{path}: not valid JSON ({exc})") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("experiments"), dict):
        raise ValidateError(f"{path}: not a validate results.json (no 'experiments' object)")
    return str(path), doc


def claims_of(results: Mapping[str, Any]) -> dict[str, Mapping[str, Any]]:
    """claim key → its JSON entry, over every experiment."""
    out: dict[str, Mapping[str, Any]] = {}
    for exp, entry in (results.get("experiments") or {}).items():
        for c in (entry or {}).get("claims") or []:
            cid = str(c.get("id", ""))
            out[cid if cid.startswith(f"{exp}.") else f"{exp}/{cid}"] = c
    return out


def _join(prefix: str, key: Any) -> str:
    return f"{prefix}/{key}" if prefix else str(key)


def _old_metric_leaves(node: Any, prefix: str, old: list[str]) -> Iterator[tuple[str, Mapping[str, Any]]]:
    """The measured values of a technique's ``metrics``: new leaves as they are, old shapes mapped (module
    docstring); ``old`` gets a path for every old shape read."""
    if is_measured(node):
        yield prefix, node
    elif _float(node) is not None and prefix:  # worstcase before the schema: a bare number
        old.append(prefix)
        yield prefix, {"value": node}
    elif isinstance(node, Mapping) and "value" in node:  # {"value", "uncertainty"} without a unit
        old.append(prefix)
        yield prefix, node
    elif isinstance(node, Mapping) and "mean_uncertainty" in node and "mean" in node:  # ErrorStats JSON
        old.append(prefix)
        for st in _STATS:
            if st in node:
                yield _join(prefix, st), {"value": node[st], "uncertainty": node.get(f"{st}_uncertainty")}
    elif isinstance(node, Mapping):
        for k, v in node.items():
            yield from _old_metric_leaves(v, _join(prefix, k), old)


def _metrics(results: Mapping[str, Any], old: list[str]) -> dict[str, Mapping[str, Any]]:
    out: dict[str, Mapping[str, Any]] = {}
    for exp, entry in (results.get("experiments") or {}).items():
        techniques = (entry or {}).get("techniques") or {}
        for tech, t in techniques.items() if isinstance(techniques, Mapping) else ():
            metrics = (t or {}).get("metrics") if isinstance(t, Mapping) else None
            for metric, leaf in _old_metric_leaves(metrics or {}, "", old):
                out[f"{exp}/{tech}/{metric}"] = leaf
    return out


def metrics_of(results: Mapping[str, Any]) -> dict[str, Mapping[str, Any]]:
    """metric key ``<experiment>/<technique>/<metric>`` → its measured value (old shapes mapped)."""
    return _metrics(results, [])


def _judgement_leaves(node: Any, prefix: str, inside: bool, old: list[str]) -> Iterator[tuple[str, Mapping]]:
    if not isinstance(node, Mapping):
        if isinstance(node, list):
            for i, v in enumerate(node):
                yield from _judgement_leaves(v, _join(prefix, i), inside, old)
        return
    if inside and is_measured(node):
        yield prefix, node
    elif inside and _float(node.get("fraction_accepted")) is not None and "n_pixels" in node:  # old flat judgement
        old.append(prefix)
        for k, unc in _OLD_JUDGEMENT.items():
            if k in node:
                yield _join(prefix, k), {"value": node[k], "uncertainty": node.get(unc) if unc else None}
    else:
        for k, v in node.items():
            yield from _judgement_leaves(v, _join(prefix, k), inside or k in JUDGEMENT_KEYS, old)


def _judgements(results: Mapping[str, Any], old: list[str]) -> dict[str, Mapping[str, Any]]:
    out: dict[str, Mapping[str, Any]] = {}
    for exp, entry in (results.get("experiments") or {}).items():
        for k, v in (entry or {}).items() if isinstance(entry, Mapping) else ():
            if k in ("techniques", "claims", "report", "settings"):
                continue
            for path, leaf in _judgement_leaves(v, _join(exp, k), k in JUDGEMENT_KEYS, old):
                out[path] = leaf
    return out


def judgements_of(results: Mapping[str, Any]) -> dict[str, Mapping[str, Any]]:
    """judgement key ``<experiment>/<path>`` → its measured value (old flat judgements mapped)."""
    return _judgements(results, [])


def is_old(results: Mapping[str, Any]) -> bool:
    """Whether ``results`` holds a technique metric or judgement in a shape from before the schema."""
    old: list[str] = []
    _metrics(results, old)
    _judgements(results, old)
    return bool(old)


def _exceeds(old: float | None, new: float | None, su: float | None, nu: float | None) -> tuple[float | None, bool]:
    if old is None or new is None:
        return None, False
    change = new - old
    sigma = math.hypot(su or 0.0, nu or 0.0)
    floor = ROUNDOFF * max(abs(old), abs(new))
    return change, abs(change) > max(sigma, floor)


def _differs(old: float | None, new: float | None) -> bool:
    if old is None or new is None:
        return (old is None) != (new is None)
    return abs(new - old) > ROUNDOFF * max(abs(old), abs(new))


def worse_is_larger(key: str, old: float, new: float, better: str = "") -> tuple[float, float]:
    """(old, new) mapped so that larger means worse (module docstring: how direction is decided); ``better``:
    the measured value's own word (``"lower"``, ``"higher"``, ``"zero"``), "" for none."""
    if better == "higher":
        return -old, -new
    if better == "zero":
        return abs(old), abs(new)
    if better == "lower":
        return old, new
    last = key.rsplit("/", 1)[-1].rsplit(".", 1)[0].lower()
    if any(word in last for word in HIGHER_IS_BETTER):
        return -old, -new
    if "bias" in last or old < 0 or new < 0:
        return abs(old), abs(new)
    return old, new


def _claim_row(key: str, a: Mapping[str, Any] | None, b: Mapping[str, Any] | None) -> Row:
    old, new = (_float(c.get("measured")) if c else None for c in (a, b))
    su, nu = (_float(c.get("uncertainty")) if c else None for c in (a, b))
    change, exceeds = _exceeds(old, new, su, nu)
    if a is None or b is None:
        status = "new" if a is None else "removed"
    elif a.get("passed") and not b.get("passed"):
        status = "newly_failing"
    elif not a.get("passed") and b.get("passed"):
        status = "improved"
    else:
        status = "changed" if _differs(old, new) else "unchanged"
    unit = str((b or a or {}).get("unit") or "")
    return Row("claim", key, old, new, su, nu, change, exceeds, status, unit)


def _measured_row(kind: str) -> Any:
    def row(key: str, a: Mapping[str, Any] | None, b: Mapping[str, Any] | None) -> Row:
        old, new = (_float(m.get("value")) if m else None for m in (a, b))
        su, nu = (_float(m.get("uncertainty")) if m else None for m in (a, b))
        change, exceeds = _exceeds(old, new, su, nu)
        if a is None or b is None:
            status = "new" if a is None else "removed"
        elif exceeds and old is not None and new is not None:
            better = str(b.get("better") or a.get("better") or ("lower" if is_measured(b) else ""))
            o, n = worse_is_larger(key, old, new, better)  # equal (a sign flipped, |value| kept): changed
            status = "regressed" if n > o else "improved" if n < o else "changed"
        else:
            status = "changed" if _differs(old, new) else "unchanged"
        unit = str((b or {}).get("unit") or (a or {}).get("unit") or "")
        return Row(kind, key, old, new, su, nu, change, exceeds, status, unit)

    return row


def compare(old: str | Path | Mapping[str, Any], new: str | Path | Mapping[str, Any]) -> Comparison:
    """Compare two runs (paths to ``results.json`` or their folders, or loaded dicts): module docstring."""
    label, a = load(old)
    new_label, b = load(new)
    rows: list[Row] = []
    old_shapes: dict[str, list[str]] = {label: [], new_label: []}
    for extract, make in ((lambda r, _: claims_of(r), _claim_row), (_metrics, _measured_row("metric")),
                          (_judgements, _measured_row("judgement"))):
        ea, eb = extract(a, old_shapes[label]), extract(b, old_shapes[new_label])
        keys = list(ea) + [k for k in eb if k not in ea]
        rows.extend(make(k, ea.get(k), eb.get(k)) for k in keys)
    na, nb = _not_run(a), _not_run(b)
    rows.extend(Row("not_run", k, None, None, None, None, None, False,
                    "unchanged" if k in na and k in nb else "regressed" if k in nb else "improved")
                for k in list(na) + [k for k in nb if k not in na])
    notes = [f"{name}: {OLD_NOTE}" for name, paths in old_shapes.items() if paths]
    return Comparison(label, rows, notes)


def _not_run(results: Mapping[str, Any]) -> list[str]:
    """``<experiment>/not_run/<what>`` of every piece a run could not run (``experiments.<name>.not_run``)."""
    return [f"{name}/not_run/{n.get('what', '?')}" for name, e in (results.get("experiments") or {}).items()
            if isinstance(e, Mapping) for n in e.get("not_run") or [] if isinstance(n, Mapping)]
