"""Registered techniques inside an experiment: their JSON entries and their declared-threshold claims.

An experiment of a family measures every technique of ``family.techniques()`` with the same metrics
and hands the numbers here, so that built-ins and plug-ins get the same report rows, the same
``results.json`` entries (``experiments.<experiment>.techniques.<technique>``) and, for each threshold a
technique declares, the claim ``<experiment>.technique.<technique>.<metric>``. Every metric is a
:class:`~validate.stats.Measured` (value ± uncertainty, unit), written by :func:`technique_entry`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..errors import ValidateError
from ..local_models.registry import Technique
from ..metrics.irradiance_error import ErrorStats
from ..stats import Measured, is_measured, measured_json, measured_leaves
from .base import Claim


def stats_json(stats: Mapping[str, ErrorStats]) -> dict[str, dict[str, float]]:
    """Every metric's :class:`~validate.metrics.irradiance_error.ErrorStats` as its JSON dict."""
    return {k: v.to_json() for k, v in stats.items()}


def technique_scope(tech: Technique, names: list[str]) -> list[str]:
    """The environments a technique's declared thresholds are judged on: those it names with
    ``environments=(...)`` at registration (the ones present in this run), else every one run."""
    wanted = tech.meta.get("environments")
    return list(names) if not wanted else [n for n in names if n in set(wanted)]


def technique_entry(tech: Technique, metrics: Mapping[str, Any], **extra: Any) -> dict[str, Any]:
    """The JSON entry of one technique: family, description, where it comes from, its metrics.

    ``metrics``: a tree of mappings whose leaves are :class:`~validate.stats.Measured` (``{"flux.max": M}``
    or ``{env: {metric: {stat: M}}}``) or their JSON, written here by :meth:`Measured.to_json`; any other
    leaf is an error."""
    written = measured_json(_parsed(metrics))
    paths = {p for p, _ in measured_leaves(written)}
    loose = [p for p in _leaf_paths(written, "") if p not in paths]
    if loose:
        raise ValidateError(f"technique '{tech.name}': metric(s) {', '.join(loose[:5])} not a Measured value")
    return {"family": tech.family, "description": tech.description, "builtin": tech.builtin,
            "module": getattr(tech.fn, "__module__", ""), "thresholds": dict(tech.thresholds),
            "metrics": written, **extra}


def _parsed(tree: Any) -> Any:
    """Measured JSON leaves back to :class:`Measured` (so that :meth:`Measured.to_json` writes each one)."""
    if is_measured(tree):
        return Measured.from_json(tree)
    if isinstance(tree, Mapping):
        return {k: _parsed(v) for k, v in tree.items()}
    return tree


def _leaf_paths(tree: Any, prefix: str) -> list[str]:
    if not isinstance(tree, Mapping) or "value" in tree:
        return [prefix]
    return [p for k, v in tree.items() for p in _leaf_paths(v, f"{prefix}/{k}" if prefix else str(k))]


def error_stats_measured(stats: Mapping[str, Any], unit: str = "%") -> dict[str, Measured]:
    """An :class:`~validate.metrics.irradiance_error.ErrorStats` JSON dict ({mean, max, rms, mean_uncertainty,
    max_uncertainty}) as one :class:`Measured` per statistic ({mean, max, rms}; rms carries no uncertainty)."""
    return {st: Measured(float(stats[st]), float(stats.get(f"{st}_uncertainty", 0.0)), unit=unit, stat=st)
            for st in ("mean", "max", "rms") if st in stats}


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


@dataclass(frozen=True)
class Stat:
    """A metric over one environment (or the worst over several): mean and max, each ± uncertainty."""

    mean: float
    max: float
    mean_uncertainty: float = 0.0
    max_uncertainty: float = 0.0

    @classmethod
    def from_json(cls, d: Mapping[str, Any]) -> Stat:
        return cls(float(d["mean"]), float(d["max"]), float(d.get("mean_uncertainty", 0.0)),
                   float(d.get("max_uncertainty", 0.0)))

    @staticmethod
    def worst(stats: list[Stat]) -> Stat:
        """Worst case over environments: the largest mean and the largest max, with their uncertainties."""
        m = max(stats, key=lambda s: s.mean)
        x = max(stats, key=lambda s: s.max)
        return Stat(m.mean, x.max, m.mean_uncertainty, x.max_uncertainty)


class CheckResult:
    """What :mod:`validate.testing` returns: per environment and metric a :class:`Stat`.

    ``r.<metric>`` is the worst case over the environments checked (``r.flux_luminance.max``);
    ``r[env].<metric>`` or ``r.environments[env][metric]`` one environment's value."""

    def __init__(self, technique: str, family: str, environments: Mapping[str, Mapping[str, Stat]]):
        self.technique, self.family = technique, family
        self.environments = {k: dict(v) for k, v in environments.items()}

    @property
    def metrics(self) -> list[str]:
        names: list[str] = []
        for v in self.environments.values():
            names += [k for k in v if k not in names]
        return names

    def __getattr__(self, metric: str) -> Stat:
        if metric.startswith("_") or metric in ("technique", "family", "environments"):
            raise AttributeError(metric)
        found = [v[metric] for v in self.environments.values() if metric in v]
        if not found:
            raise AttributeError(f"no metric {metric!r}; measured: {', '.join(self.metrics)}")
        return Stat.worst(found)

    def __getitem__(self, env: str) -> _EnvView:
        return _EnvView(env, self.environments[env])

    def __repr__(self) -> str:
        rows = [f"{e}.{m}: mean {s.mean:.4g} ± {s.mean_uncertainty:.2g}, max {s.max:.4g} ± {s.max_uncertainty:.2g}"
                for e, v in self.environments.items() for m, s in v.items()]
        return f"CheckResult({self.technique!r}, {self.family}:\n  " + "\n  ".join(rows) + ")"


class _EnvView:
    def __init__(self, env: str, metrics: Mapping[str, Stat]):
        self._env, self._metrics = env, metrics

    def __getattr__(self, metric: str) -> Stat:
        try:
            return self._metrics[metric]
        except KeyError:
            raise AttributeError(f"{self._env}: no metric {metric!r}; measured: {', '.join(self._metrics)}") from None
