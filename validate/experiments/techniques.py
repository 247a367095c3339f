"""Registered techniques inside an experiment: their JSON entries and their declared-threshold claims.

An experiment of a family measures every technique of ``family.techniques()`` with the same metrics
and hands the numbers here, so that built-ins and plug-ins get the same report rows, the same
``results.json`` entries (``experiments.<experiment>.techniques.<technique>``) and, for each threshold a
technique declares, the claim ``<experiment>.technique.<technique>.<metric>``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..errors import ValidateError
from ..local_models.registry import Technique
from .base import Claim


@dataclass(frozen=True)
class Measured:
    """One metric of one technique: value ± uncertainty, and the same metric under the experiment's
    standard perturbation (the power check of any claim made on it)."""

    value: float
    uncertainty: float
    perturbed: float | None = None
    perturbation: str = ""


def technique_entry(tech: Technique, metrics: Mapping[str, Any], **extra: Any) -> dict[str, Any]:
    """The JSON entry of one technique: family, description, where it comes from, its metrics."""
    return {"family": tech.family, "description": tech.description, "builtin": tech.builtin,
            "module": getattr(tech.fn, "__module__", ""), "thresholds": dict(tech.thresholds),
            "metrics": dict(metrics), **extra}


def technique_claims(experiment: str, tech: Technique, measured: Mapping[str, Measured], unit: str = "%",
                     scope: str = "") -> list[Claim]:
    """One claim per threshold ``tech`` declares, judged on ``measured[metric]`` (upper bounds).

    A threshold on a metric this experiment does not measure is a one-line error naming the technique.
    ``scope`` says over what the value was taken (e.g. "worst over 5 environments")."""
    claims = []
    for metric, limit in tech.thresholds.items():
        if metric not in measured:
            raise ValidateError(f"technique '{tech.name}' ({tech.family}): threshold on {metric!r}, which experiment "
                                f"{experiment} does not measure; it measures: {', '.join(sorted(measured))}")
        m = measured[metric]
        c = Claim(f"{experiment}.technique.{tech.name}.{metric}",
                  f"{tech.name}: {metric} < {limit:g}" + (f" ({scope})" if scope else ""), metric, float(limit),
                  m.value, m.uncertainty, unit=unit,
                  source=tech.source or f"threshold declared by the technique's author ({tech.fn.__module__})")
        if m.perturbed is not None:
            c.with_power(m.perturbation, m.perturbed)
        claims.append(c)
    return claims
