"""Experiments: one package per experiment, discovered automatically (drop a package in this folder whose
``__init__`` exposes the :class:`~.base.ExperimentModule` interface and registers its ``run`` with
:func:`register_experiment`).

Every package has the same stages: ``settings.py`` (``QUICK``, ``FULL``) → ``compute.py`` (``compute(ctx, s)``,
numbers only) → ``claims.py`` (``claims(m)``) → ``report.py`` (``findings(m)``, ``sections(m, ctx)``), plus
``check.py`` where :mod:`validate.testing` needs one. Modules of this folder (:mod:`.base`, :mod:`.formatting`,
:mod:`.techniques`, :mod:`.inputs`, :mod:`.schedule`) are shared by the experiments and are not experiments."""

from __future__ import annotations

import importlib
import pkgutil

from ..errors import ValidateError
from .base import (
    EXPERIMENTS,
    Claim,
    Context,
    Experiment,
    ExperimentModule,
    ExperimentResult,
    Figure,
    Section,
    Table,
    register_experiment,
)

__all__ = ["EXPERIMENTS", "Claim", "Context", "Experiment", "ExperimentModule", "ExperimentResult", "Figure",
           "Section", "Table", "register_experiment", "discover", "run_experiment"]


def discover() -> dict[str, Experiment]:
    """Import every experiment package of this folder so their experiments register; sorted by order."""
    for mod in pkgutil.iter_modules(__path__):
        if mod.ispkg:
            importlib.import_module(f"{__name__}.{mod.name}")
    return dict(sorted(EXPERIMENTS.items(), key=lambda kv: (kv[1].order, kv[0])))


def run_experiment(name: str, ctx: Context) -> ExperimentResult:
    exps = discover()
    if name not in exps:
        raise ValidateError(f"unknown experiment {name!r}; available: {', '.join(exps)}")
    return exps[name].run(ctx)
