"""Experiments: one module per experiment, discovered automatically (drop a module in this folder
that calls :func:`register_experiment`)."""

from __future__ import annotations

import importlib
import pkgutil

from .base import EXPERIMENTS, Claim, Context, Experiment, ExperimentResult, Figure, Section, Table, register_experiment

__all__ = ["EXPERIMENTS", "Claim", "Context", "Experiment", "ExperimentResult", "Figure", "Section", "Table",
           "register_experiment", "discover", "run_experiment"]


def discover() -> dict[str, Experiment]:
    """Import every module in this package so their experiments register; sorted by order."""
    for mod in pkgutil.iter_modules(__path__):
        if mod.name not in ("base",):
            importlib.import_module(f"{__name__}.{mod.name}")
    return dict(sorted(EXPERIMENTS.items(), key=lambda kv: (kv[1].order, kv[0])))


def run_experiment(name: str, ctx: Context) -> ExperimentResult:
    from ..errors import ValidateError

    exps = discover()
    if name not in exps:
        raise ValidateError(f"unknown experiment {name!r}; available: {', '.join(exps)}")
    return exps[name].run(ctx)
