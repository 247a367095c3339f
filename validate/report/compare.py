"""Compare two runs: ``python -m validate compare OLD.json NEW.json [--strict]``.

For every claim and every technique metric present in either ``results.json``, one :class:`Row`:
the old and new value with their uncertainties, the change new − old, and whether it exceeds the
combined uncertainty

    σ = √(σ_old² + σ_new²)        (independent runs; each σ as the run recorded it)

A value recorded without an uncertainty (``None``, absent, or NaN) counts as σ = 0: the suite is
deterministic (fixed seeds, cached references), so two runs of unchanged code give identical
numbers and any change beyond float round-off, ``ROUNDOFF`` = 10⁻⁹ × max(|old|, |new|), is
real. The same round-off floor applies when both uncertainties are given.

Keys: a claim is its ``id`` (experiments prefix their ids with their name; an id that does not is
written ``<experiment>/<id>``); a technique metric is ``<experiment>/<technique>/<metric>``, where
``<metric>`` is the path of a ``{"value", "uncertainty"}`` leaf under the technique's ``metrics``
(``flux_luminance.max``, ``point/bias``).

Status of a row:

* ``new`` / ``removed``: present in one run only;
* claims: ``newly_failing`` (passed, now fails: a regression), ``improved`` (failed, now passes),
  ``changed`` (same verdict, a different value), ``unchanged``;
* metrics: ``regressed`` (worse beyond σ: a regression), ``improved`` (better beyond σ), ``changed``
  (different, within σ), ``unchanged``.

Which way is worse. Every technique metric in ``results.json`` is an error: technique thresholds are
upper bounds (:func:`validate.experiments.techniques.technique_claims` judges ``metric < limit``), so
larger is worse. A signed metric (its last name part contains ``bias``, or either value is negative)
is an error by its magnitude: larger |value| is worse. The exceptions are scores, higher is better,
recognised by a last name part in :data:`HIGHER_IS_BETTER`.

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

ROUNDOFF = 1e-9  # relative: below this, two values are the same number (float64 round-off of a re-run)
HIGHER_IS_BETTER = ("psnr", "ssim", "score", "correlation", "r2")
REGRESSION_STATUSES = ("regressed", "newly_failing")


@dataclass(frozen=True)
class Row:
    """One compared claim or technique metric (the ``changes.rows`` schema of ``results.json``)."""

    kind: str  # "claim" | "metric"
    key: str
    old: float | None
    new: float | None
    old_uncertainty: float | None
    new_uncertainty: float | None
    change: float | None
    exceeds_uncertainty: bool
    status: str


@dataclass
class Comparison:
    """Every row of two runs, and the regressions among them."""

    baseline: str
    rows: list[Row] = field(default_factory=list)

    @property
    def regressions(self) -> list[Row]:
        return [r for r in self.rows if r.status in REGRESSION_STATUSES]

    @property
    def changed(self) -> list[Row]:
        return [r for r in self.rows if r.status != "unchanged"]

    def to_json(self) -> dict[str, Any]:
        return {"baseline": self.baseline, "regressions": len(self.regressions),
                "rows": [asdict(r) for r in self.rows]}

    def summary(self) -> str:
        counts: dict[str, int] = {}
        for r in self.rows:
            counts[r.status] = counts.get(r.status, 0) + 1
        parts = ", ".join(f"{counts[s]} {s.replace('_', ' ')}" for s in
                          ("regressed", "newly_failing", "improved", "changed", "new", "removed", "unchanged")
                          if counts.get(s))
        claims = sum(r.kind == "claim" for r in self.rows)
        return (f"{len(self.regressions)} regression(s) against {self.baseline}: {claims} claims and "
                f"{len(self.rows) - claims} technique metrics compared ({parts or 'nothing to compare'})")

    def table(self) -> str:
        """The changed rows as an aligned text table (empty string when nothing changed)."""
        rows = self.changed
        if not rows:
            return ""
        head = ("status", "kind", "key", "old", "new", "change", "> σ")
        body = [(r.status, r.kind, r.key, _pm(r.old, r.old_uncertainty), _pm(r.new, r.new_uncertainty),
                 sig(r.change, 4), "yes" if r.exceeds_uncertainty else "no") for r in rows]
        widths = [max(len(x[i]) for x in [head, *body]) for i in range(len(head))]
        right = {3, 4, 5}
        lines = ["  ".join(c.rjust(w) if i in right else c.ljust(w)
                           for i, (c, w) in enumerate(zip(x, widths, strict=True))) for x in [head, *body]]
        return "\n".join(line.rstrip() for line in lines)


def _pm(v: float | None, u: float | None) -> str:
    """A value (4 significant digits) or value ± uncertainty (digits the uncertainty supports)."""
    return sig(v, 4) if u is None or v is None or u == 0 else pm(v, u)


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


def _leaves(node: Any, prefix: str) -> Iterator[tuple[str, Mapping[str, Any]]]:
    if not isinstance(node, Mapping):
        return
    if "value" in node:
        yield prefix, node
        return
    for k, v in node.items():
        yield from _leaves(v, f"{prefix}/{k}" if prefix else str(k))


def metrics_of(results: Mapping[str, Any]) -> dict[str, Mapping[str, Any]]:
    """metric key ``<experiment>/<technique>/<metric>`` → its ``{"value", "uncertainty"}`` leaf."""
    out: dict[str, Mapping[str, Any]] = {}
    for exp, entry in (results.get("experiments") or {}).items():
        techniques = (entry or {}).get("techniques") or {}
        for tech, t in techniques.items() if isinstance(techniques, Mapping) else ():
            for metric, leaf in _leaves((t or {}).get("metrics") or {}, ""):
                out[f"{exp}/{tech}/{metric}"] = leaf
    return out


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


def worse_is_larger(key: str, old: float, new: float) -> tuple[float, float]:
    """(old, new) mapped so that larger means worse (module docstring: how direction is decided)."""
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
    return Row("claim", key, old, new, su, nu, change, exceeds, status)


def _metric_row(key: str, a: Mapping[str, Any] | None, b: Mapping[str, Any] | None) -> Row:
    old, new = (_float(m.get("value")) if m else None for m in (a, b))
    su, nu = (_float(m.get("uncertainty")) if m else None for m in (a, b))
    change, exceeds = _exceeds(old, new, su, nu)
    if a is None or b is None:
        status = "new" if a is None else "removed"
    elif exceeds and old is not None and new is not None:
        o, n = worse_is_larger(key, old, new)
        status = "regressed" if n > o else "improved"
    else:
        status = "changed" if _differs(old, new) else "unchanged"
    return Row("metric", key, old, new, su, nu, change, exceeds, status)


def compare(old: str | Path | Mapping[str, Any], new: str | Path | Mapping[str, Any]) -> Comparison:
    """Compare two runs (paths to ``results.json`` or their folders, or loaded dicts): module docstring."""
    label, a = load(old)
    _, b = load(new)
    rows: list[Row] = []
    for extract, make in ((claims_of, _claim_row), (metrics_of, _metric_row)):
        ea, eb = extract(a), extract(b)
        keys = list(ea) + [k for k in eb if k not in ea]
        rows.extend(make(k, ea.get(k), eb.get(k)) for k in keys)
    return Comparison(label, rows)
