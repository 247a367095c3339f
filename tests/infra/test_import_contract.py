"""The layers of ../shared/ARCHITECTURE.md hold: ``lint-imports`` (PyPI import-linter) keeps every contract of
``[tool.importlinter]`` in pyproject.toml (imports run down; a model never imports the reference, the reference
never imports a model). One subprocess, ~1 s: grimp parses the package's sources, nothing is imported. Then, on
grimp's graph (call-time imports included): every module of validate/ is in a layer, and no two modules import
each other through any chain (a circle)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
CONTRACT_IDS = ("layers", "models-vs-reference")


def _lint_imports() -> str:
    exe = shutil.which("lint-imports", path=str(Path(sys.executable).parent)) or shutil.which("lint-imports")
    if exe is None:
        pytest.fail("lint-imports not found: pip install import-linter (it is in the test extras of pyproject.toml)")
    return exe


def test_import_contracts_are_kept() -> None:
    proc = subprocess.run([_lint_imports(), "--no-cache"], cwd=REPO, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert f"Contracts: {len(CONTRACT_IDS)} kept, 0 broken." in proc.stdout


@pytest.mark.parametrize("contract", CONTRACT_IDS)
def test_each_contract_is_configured(contract: str) -> None:
    """Both contracts exist (a deleted contract would otherwise pass silently)."""
    tomllib = pytest.importorskip("tomllib")  # Python ≥ 3.11

    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["importlinter"]
    assert contract in {c["id"] for c in config["contracts"]}


# ---- every module in a layer, and no circle anywhere (call-time imports included) ------------------------------

@pytest.fixture(scope="module")
def graph():
    """The import graph of validate/ as grimp (import-linter's parser) reads it from the sources: every import
    statement, a function's own (call-time) imports included. Nothing is imported."""
    grimp = pytest.importorskip("grimp")
    sys.path.insert(0, str(REPO))
    try:
        return grimp.build_graph("validate", cache_dir=None)
    finally:
        sys.path.remove(str(REPO))


def _layers() -> list[str]:
    """The modules named in the ``layers`` contract (``a : b`` and ``a | b`` are siblings in one layer)."""
    tomllib = pytest.importorskip("tomllib")  # Python ≥ 3.11

    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["importlinter"]
    (layers,) = [c["layers"] for c in config["contracts"] if c["id"] == "layers"]
    return [name.strip() for layer in layers for name in layer.replace("|", ":").split(":")]


def outside_layers(modules: set[str], layers: list[str], imports: dict[str, set[str]]) -> list[str]:
    """Modules in no layer: neither a layer nor inside one. A package split over several layers (``validate``,
    ``validate.report``) is in none itself, so its ``__init__`` may import nothing of validate (a docstring, or
    names loaded on demand) — else its imports would escape the contract."""
    def inside(m: str) -> bool:
        return any(m == name or m.startswith(name + ".") for name in layers)

    def split_package(m: str) -> bool:
        return any(name.startswith(m + ".") for name in layers) and not imports.get(m)

    return sorted(m for m in modules if not inside(m) and not split_package(m))


def import_circles(imports: dict[str, set[str]]) -> list[set[str]]:
    """The strongly connected components of more than one module (each holds at least one circle), Tarjan's
    algorithm without recursion. A package's ``__init__`` is a module like any other: it importing its own
    submodules is an edge, and only a submodule importing the package (or something that does) back closes a
    circle — a real one (that submodule would see a half-initialised package)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[set[str]] = []
    for root in sorted(imports):
        if root in index:
            continue
        work = [(root, iter(sorted(imports.get(root, ()))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(imports.get(w, ())))))
                elif w in on_stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = set()
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    comp.add(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    out.append(comp)
    return out


def _imports(graph) -> dict[str, set[str]]:
    return {m: set(graph.find_modules_directly_imported_by(m)) for m in graph.modules}


def test_every_module_is_in_a_layer(graph) -> None:
    imports = _imports(graph)
    assert outside_layers(set(graph.modules), _layers(), imports) == []


def test_a_module_outside_the_layers_is_named() -> None:
    layers = ["validate.cli", "validate.report.html", "validate.errors"]
    imports = {"validate.report": set(), "validate.report.html": {"validate.errors"}}
    mods = {"validate", "validate.cli", "validate.report", "validate.report.html", "validate.errors", "validate.new"}
    assert outside_layers(mods, layers, imports) == ["validate.new"]
    imports["validate.report"] = {"validate.report.html"}  # an __init__ that imports escapes the contract
    assert outside_layers(mods, layers, imports) == ["validate.new", "validate.report"]


def test_the_graph_holds_call_time_imports(graph) -> None:
    """The cycle test below sees imports made inside functions: ``main`` imports the bench when it runs."""
    details = graph.get_import_details(importer="validate.cli.commands", imported="validate.bench")
    assert details and all(d["line_contents"].startswith("from ..bench") for d in details)
    source = (REPO / "validate" / "cli" / "commands.py").read_text().splitlines()
    assert all(source[d["line_number"] - 1].startswith("    ") for d in details)  # inside a function


def test_no_import_circle(graph) -> None:
    circles = import_circles(_imports(graph))
    assert circles == [], "import circles (call-time imports included): " + "; ".join(
        " ↔ ".join(sorted(c)) for c in circles)


def test_the_circle_finder_catches_a_circle() -> None:
    imports = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": set(), "p": {"p.x"}, "p.x": {"d"}}
    assert import_circles(imports) == [{"a", "b", "c"}]
    imports["p.x"] = {"p"}  # a submodule importing its package back: a real circle
    assert {"p", "p.x"} in import_circles(imports)
