"""Every experiment is a package with one anatomy (issue 19).

Each package under ``validate/experiments/`` satisfies :class:`validate.experiments.base.ExperimentModule`
(NAME, TITLE, DESCRIPTION, ORDER, QUICK, FULL, compute, claims, findings, sections, run), exports exactly
that in ``__all__``, has the same stage modules (``settings``, ``compute``, ``claims``, ``report``), keeps
``QUICK`` and ``FULL`` as two instances of one frozen dataclass, and registers a ``run`` that only wires the
stages. Static and import-only: no experiment is run here (fast).
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import inspect
import pkgutil
from pathlib import Path

import pytest

import validate.experiments as experiments
from validate.experiments.base import EXPERIMENT_INTERFACE, EXPERIMENTS, ExperimentModule

PACKAGE_DIR = Path(experiments.__file__).parent
NAMES = sorted(m.name for m in pkgutil.iter_modules([str(PACKAGE_DIR)]) if m.ispkg)
STAGES = ("__init__", "settings", "compute", "claims", "report")
# A thin ``run``: choose QUICK/FULL, compute, then hand the stages' outputs to ExperimentResult. The longest
# today is 9 lines; 25 leaves room for a longer argument list, not for logic.
RUN_MAX_LINES = 25
# The brief's function-length rule for experiments/ (the before-stop hook's AST scan): no function over 60 lines.
FUNCTION_MAX_LINES = 60
# Names a thin run may call: the stage functions, the report's payload helpers, the result type.
RUN_CALLS = {"compute", "claims", "findings", "sections", "ExperimentResult", "data", "techniques", "summary",
             "settings_json", "to_json"}


def test_every_experiment_is_a_package() -> None:
    assert set(NAMES) >= {"arealights", "brdfs", "engines", "hemisphere", "ibl", "lights", "multiscatter", "sh9",
                          "shadows", "uberlight"}
    flat = [m.name for m in pkgutil.iter_modules([str(PACKAGE_DIR)]) if not m.ispkg]
    # shared by the experiments, not experiments (a run's scheduling and lanes are validate/run/)
    assert sorted(flat) == ["base", "formatting", "inputs", "techniques"]


@pytest.mark.parametrize("name", NAMES)
def test_package_satisfies_the_protocol_and_exports_exactly_it(name: str) -> None:
    mod = importlib.import_module(f"validate.experiments.{name}")
    assert isinstance(mod, ExperimentModule)
    assert sorted(mod.__all__) == sorted(EXPERIMENT_INTERFACE)
    assert mod.NAME == name and isinstance(mod.TITLE, str) and isinstance(mod.DESCRIPTION, str)
    assert isinstance(mod.ORDER, int)
    for fn, arity in (("compute", 2), ("claims", 1), ("findings", 1), ("sections", 2), ("run", 1)):
        assert callable(getattr(mod, fn)) and len(inspect.signature(getattr(mod, fn)).parameters) == arity, fn
    reg = EXPERIMENTS[name]
    assert (reg.title, reg.description, reg.order) == (mod.TITLE, mod.DESCRIPTION, mod.ORDER)


@pytest.mark.parametrize("name", NAMES)
def test_same_stage_modules_in_every_package(name: str) -> None:
    files = {p.stem for p in (PACKAGE_DIR / name).glob("*.py")}
    assert set(STAGES) <= files, sorted(set(STAGES) - files)


@pytest.mark.parametrize("name", NAMES)
def test_quick_and_full_are_two_instances_of_one_frozen_dataclass(name: str) -> None:
    s = importlib.import_module(f"validate.experiments.{name}.settings")
    assert dataclasses.is_dataclass(s.QUICK) and type(s.QUICK) is type(s.FULL) is s.Settings
    assert s.Settings.__dataclass_params__.frozen
    assert s.QUICK != s.FULL
    mod = importlib.import_module(f"validate.experiments.{name}")
    assert (mod.QUICK, mod.FULL) == (s.QUICK, s.FULL)


def _run_node(name: str) -> ast.FunctionDef:
    tree = ast.parse((PACKAGE_DIR / name / "__init__.py").read_text())
    (run,) = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "run"]
    return run


@pytest.mark.parametrize("name", NAMES)
def test_run_only_wires_the_stages(name: str) -> None:
    run = _run_node(name)
    assert run.end_lineno - run.lineno + 1 <= RUN_MAX_LINES
    body = [n for stmt in run.body for n in ast.walk(stmt)]  # the decorator (register_experiment) aside
    assert not [n for n in body if isinstance(n, (ast.For, ast.While, ast.If, ast.comprehension))]
    called = {n.func.id if isinstance(n.func, ast.Name) else n.func.attr
              for n in body if isinstance(n, ast.Call) and isinstance(n.func, (ast.Name, ast.Attribute))}
    assert called <= RUN_CALLS, sorted(called - RUN_CALLS)
    tree = ast.parse((PACKAGE_DIR / name / "__init__.py").read_text())
    defs = [n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))]
    assert defs == ["run"]  # the interface, nothing else


def test_no_function_in_experiments_is_over_the_limit() -> None:
    long = []
    for path in PACKAGE_DIR.rglob("*.py"):
        for n in ast.walk(ast.parse(path.read_text())):
            size = n.end_lineno - n.lineno + 1 if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) else 0
            if size > FUNCTION_MAX_LINES:
                long.append(f"{path.relative_to(PACKAGE_DIR)}:{n.lineno} {n.name} ({n.end_lineno - n.lineno + 1})")
    assert not long, long


def _body_key(fn: ast.FunctionDef) -> str:
    """The function's arguments and body without its docstring: equal keys mean the same code under two names."""
    body = fn.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:]
    return ast.dump(fn.args) + ast.dump(ast.Module(body=body, type_ignores=[]))


def test_no_helper_is_defined_twice_in_experiments() -> None:
    """Number formatting lives in experiments/formatting.py only, and no module-level function of the
    experiments layer repeats another's code (every package's thin ``run`` and report payload functions aside: the
    same wiring, or one call of a shared helper)."""
    per_package = {"run", "summary", "data", "techniques", "settings_json"}
    fmt = {"pm", "_pm", "pct", "_pct", "pct_fixed", "percent", "_percent", "pm_entry"}
    by_body: dict[str, list[str]] = {}
    for path in PACKAGE_DIR.rglob("*.py"):
        where = str(path.relative_to(PACKAGE_DIR))
        for n in ast.parse(path.read_text()).body:
            if not isinstance(n, ast.FunctionDef):
                continue
            assert n.name not in fmt or where == "formatting.py", f"{where}: {n.name} (use experiments/formatting.py)"
            if n.name not in per_package:
                by_body.setdefault(_body_key(n), []).append(f"{where}:{n.name}")
    twice = [v for v in by_body.values() if len(v) > 1]
    assert not twice, twice
