"""Every experiment is a package with one anatomy (issues 19, 33).

Each package under ``validate/experiments/`` satisfies :class:`validate.experiments.base.ExperimentModule`
(NAME, TITLE, DESCRIPTION, ORDER, QUICK, FULL, compute, claims, findings, sections, plus the optional hooks of
``base.HOOKS``), exports exactly that in ``__all__``, has the same stage modules (``settings``, ``compute``,
``claims``, ``report``), keeps ``QUICK`` and ``FULL`` as two instances of one frozen dataclass, and only declares:
its ``__init__`` defines no function (the one generic ``base.run`` wires every experiment) and is registered by
``discover()`` with no edit elsewhere, its page and README row present. Sub-experiments (``PARTS``) are sub-packages
satisfying :class:`~validate.experiments.base.PartModule` with the same stage modules. Static and import-only: no
experiment is run here (fast).
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
from validate.experiments import discover
from validate.experiments.base import (
    EXPERIMENT_INTERFACE,
    HOOKS,
    PART_INTERFACE,
    ExperimentModule,
    PartModule,
    settings_json,
)

PACKAGE_DIR = Path(experiments.__file__).parent
REPO = PACKAGE_DIR.parents[1]
NAMES = sorted(m.name for m in pkgutil.iter_modules([str(PACKAGE_DIR)]) if m.ispkg)
STAGES = ("__init__", "settings", "compute", "claims", "report")
PART_STAGES = ("__init__", "compute", "claims", "report")
# An __init__ declares: a docstring, imports, NAME/TITLE/DESCRIPTION/ORDER/PARTS and __all__ — a few lines of code.
DECLARED = {"NAME", "TITLE", "DESCRIPTION", "ORDER", "PARTS", "__all__"}
INIT_MAX_CODE_LINES = 25
# The brief's function-length rule for experiments/ (the before-stop hook's AST scan): no function over 60 lines.
FUNCTION_MAX_LINES = 60


def test_every_experiment_is_a_package() -> None:
    assert set(NAMES) >= {"arealights", "brdfs", "engines", "hemisphere", "ibl", "lights", "multiscatter", "sh9",
                          "shadows", "uberlight", "renders", "listings", "worstcase"}
    flat = [m.name for m in pkgutil.iter_modules([str(PACKAGE_DIR)]) if not m.ispkg]
    # shared by the experiments, not experiments (a run's scheduling and lanes are validate/run/)
    assert sorted(flat) == ["base", "formatting", "inputs", "techniques"]


def test_every_package_is_discovered_and_registered() -> None:
    assert set(discover()) >= set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_package_satisfies_the_protocol_and_exports_exactly_it(name: str) -> None:
    mod = importlib.import_module(f"validate.experiments.{name}")
    assert isinstance(mod, ExperimentModule)
    hooks = set(mod.__all__) - set(EXPERIMENT_INTERFACE)
    assert set(EXPERIMENT_INTERFACE) <= set(mod.__all__) and hooks <= set(HOOKS), sorted(hooks - set(HOOKS))
    assert not {h for h in HOOKS if hasattr(mod, h)} - hooks  # a hook the package has is exported
    assert mod.NAME == name and isinstance(mod.TITLE, str) and isinstance(mod.DESCRIPTION, str)
    assert isinstance(mod.ORDER, int)
    arity = {"compute": 2, "claims": 1, "findings": 1, "sections": 2, "summary": 1, "data": 1, "techniques": 1,
             "reported_settings": 3}
    for fn in set(arity) & set(mod.__all__):
        assert callable(getattr(mod, fn)) and len(inspect.signature(getattr(mod, fn)).parameters) == arity[fn], fn
    reg = discover()[name]
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


@pytest.mark.parametrize("name", NAMES)
def test_init_only_declares(name: str) -> None:
    tree = ast.parse((PACKAGE_DIR / name / "__init__.py").read_text())
    body = [n for n in tree.body if not (isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant))]
    assert all(isinstance(n, (ast.ImportFrom, ast.Import, ast.Assign)) for n in body), name  # no def, no logic
    assigned = {t.id for n in body if isinstance(n, ast.Assign) for t in n.targets if isinstance(t, ast.Name)}
    assert assigned <= DECLARED, sorted(assigned - DECLARED)
    code = sum(n.end_lineno - n.lineno + 1 for n in body)
    assert code <= INIT_MAX_CODE_LINES, code


@pytest.mark.parametrize("name", NAMES)
def test_every_experiment_has_its_page_and_readme_row(name: str) -> None:
    assert (REPO / "docs" / "experiments" / f"{name}.md").is_file()
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    assert f"| `{name}` |" in readme and f"(docs/experiments/{name}.md)" in readme, name


PARTS = [(name, part) for name in NAMES for part in getattr(importlib.import_module(f"validate.experiments.{name}"),
                                                            "PARTS", ())]


def test_the_sub_experiments_are_parts() -> None:
    assert {p.__name__.removeprefix("validate.experiments.") for _, p in PARTS} == {
        "arealights.specular", "renders.shadows", "renders.cdf", "ibl.khronos", "renders.khronos",
        "renders.loaders"}


@pytest.mark.parametrize(("name", "part"), PARTS, ids=[p.__name__ for _, p in PARTS])
def test_part_is_a_sub_package_with_the_stages(name: str, part: object) -> None:
    assert isinstance(part, PartModule)
    assert part.__name__.startswith(f"validate.experiments.{name}.")
    assert set(PART_INTERFACE) <= set(part.__all__)
    files = {p.stem for p in Path(part.__file__).parent.glob("*.py")}
    assert set(PART_STAGES) <= files, sorted(set(PART_STAGES) - files)


def test_settings_json_is_one_conversion_for_every_shape() -> None:
    @dataclasses.dataclass(frozen=True)
    class Inner:
        xs: tuple[float, ...] = (1.0, 2.0)

    @dataclasses.dataclass(frozen=True)
    class Outer:
        a: int
        pairs: tuple[tuple[int, int], ...]
        inner: Inner = Inner()
        hidden: str = "x"

    s = Outer(1, ((1, 2), (3, 4)))
    assert settings_json(s) == {"a": 1, "pairs": [[1, 2], [3, 4]], "inner": {"xs": [1.0, 2.0]}, "hidden": "x"}
    assert settings_json(s, omit=("hidden", "inner"), extra=[1]) == {"a": 1, "pairs": [[1, 2], [3, 4]], "extra": [1]}
    assert settings_json({"k": (1,), "d": {"t": (2, 3)}}) == {"k": [1], "d": {"t": [2, 3]}}


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
    experiments layer repeats another's code (every package's report payload hooks aside: one call of a shared
    helper)."""
    per_package = {"summary", "data", "techniques", "reported_settings"}
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
