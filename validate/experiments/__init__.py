"""Experiments: one package per experiment, discovered automatically: a package in this folder whose ``__init__``
declares the :class:`~.base.ExperimentModule` interface is registered by :func:`discover` and run by the one
generic :func:`~.base.run` (no edit elsewhere).

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
    register_module,
)

__all__ = ["EXPERIMENTS", "Claim", "Context", "Experiment", "ExperimentModule", "ExperimentResult", "Figure",
           "Section", "Table", "register_experiment", "register_module", "discover", "run_experiment"]


def discover() -> dict[str, Experiment]:
    """Import and register every experiment package of this folder (and whatever else registered itself, e.g. a
    plug-in's :func:`register_experiment`); sorted by order."""
    for info in pkgutil.iter_modules(__path__):
        if info.ispkg:
            mod = importlib.import_module(f"{__name__}.{info.name}")
            if getattr(mod, "NAME", None) not in EXPERIMENTS:
                register_module(mod)
    return dict(sorted(EXPERIMENTS.items(), key=lambda kv: (kv[1].order, kv[0])))


def run_experiment(name: str, ctx: Context) -> ExperimentResult:
    exps = discover()
    if name not in exps:
        raise ValidateError(f"unknown experiment {name!r}; available: {', '.join(exps)}")
    return exps[name].run(ctx)
