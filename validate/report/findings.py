"""Findings grouped under headings, derived from the sentences themselves (results.json has no groups).

A finding goes to the first rule that fits:

1. it opens with ``technique NAME:`` or ``NAME:`` / ``NAME (…):`` / ``NAME under …`` where NAME is one of the
   experiment's registered techniques → "By technique";
2. it opens with ``NAME:`` / ``NAME,`` / ``NAME (…):`` where NAME is an input the experiment measured (an
   environment, sky, scene or material key of its JSON) → "By input";
3. its first two words (lower-cased, without punctuation) are shared with another finding → a topic
   group headed by those words as the first such finding writes them ("White-furnace albedo");
4. otherwise → "Other findings".

Groups keep the order of their first finding ("Other findings" last); findings keep their order
inside a group. A page shows the first :data:`VISIBLE` findings of each group and folds the rest
into a ``<details>`` block.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from typing import Any

VISIBLE = 3  # findings shown per group before the rest is folded away
TECHNIQUES, INPUTS, GENERAL = "By technique", "By input", "Other findings"
_LEAD = re.compile(r"^(?:technique\s+)?([A-Za-z0-9_.+-]+)(?:\s*\([^)]*\))?\s*(:|,|under\b|vs\b)")
_WORD = re.compile(r"[\w′'’-]+", re.UNICODE)
_INPUT_KEYS = ("environments", "skies", "scenes", "materials", "furnace")


def input_names(e: Mapping[str, Any]) -> set[str]:
    """Names of the inputs an experiment's JSON keys its data by (environments, skies, scenes, materials),
    and the inputs its technique metrics are keyed by."""
    names: set[str] = set()
    for key in _INPUT_KEYS:
        v = e.get(key)
        if isinstance(v, Mapping):
            names |= {str(k) for k in v}
        elif isinstance(v, list):
            names |= {str(k) for k in v if isinstance(k, str)}
    for t in (e.get("techniques") or {}).values():
        metrics = (t or {}).get("metrics") if isinstance(t, Mapping) else None
        if isinstance(metrics, Mapping):
            names |= {str(k) for k, v in metrics.items() if isinstance(v, Mapping) and "value" not in v}
    return names


def _topic(text: str) -> tuple[str, str] | None:
    words = _WORD.findall(text)[:2]
    if len(words) < 2:
        return None
    return " ".join(w.lower() for w in words), " ".join(words)


def group_findings(findings: Iterable[str], techniques: Iterable[str] = (),
                   inputs: Iterable[str] = ()) -> list[dict[str, Any]]:
    """[{"title", "findings": [...], "visible": [...], "folded": [...]}, ...] by the module's rules."""
    items = [str(f) for f in findings]
    techs, ins = set(techniques), set(inputs)
    keys: list[tuple[str, str]] = []  # (group key, heading)
    topics: dict[str, int] = {}
    for f in items:
        t = _topic(f)
        if t:
            topics[t[0]] = topics.get(t[0], 0) + 1
    for f in items:
        m = _LEAD.match(f)
        name = m.group(1) if m else ""
        t = _topic(f)
        if name in techs or f.startswith("technique "):
            keys.append((TECHNIQUES, TECHNIQUES))
        elif name in ins and m and m.group(2) in (":", ","):
            keys.append((INPUTS, INPUTS))
        elif t and topics[t[0]] > 1:
            keys.append((t[0], t[1][:1].upper() + t[1][1:]))
        else:
            keys.append((GENERAL, GENERAL))
    groups: dict[str, dict[str, Any]] = {}
    for (key, heading), f in zip(keys, items, strict=True):
        groups.setdefault(key, {"title": heading, "findings": []})["findings"].append(f)
    out = [g for k, g in groups.items() if k != GENERAL] + ([groups[GENERAL]] if GENERAL in groups else [])
    for g in out:
        g["visible"], g["folded"] = g["findings"][:VISIBLE], g["findings"][VISIBLE:]
    return out
