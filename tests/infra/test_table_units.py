"""Units on every column (issue 23): every column of every table an experiment's report builds names its unit.

A header ends with its unit in parentheses (:func:`validate.format.col`: "max |z| (–)", "β (°)") or is a column
of words (:data:`validate.format.LABEL_COLUMNS`); :func:`validate.format.missing_units` tells the two apart.

The tables are built from an experiment's measurements, which no committed file holds (``docs/results.json``
keeps claims and findings, not report sections), and a run costs minutes. So the headers are read where they
are written: every ``Table(headers, ...)`` call under ``validate/experiments/`` is found in the source and its
``headers`` expression is evaluated symbolically — list literals, ``+``, ``*`` unpacking, comprehensions
(their element expression stands for every column they produce), names bound in the enclosing function or
module, and f-strings, whose ``{…}`` parts are values and whose literal text must carry the unit. A header
that cannot be read this way (a variable list of names: ``["technique"] + skies``) fails: build it with
:func:`~validate.format.col`, whose unit is checked when it runs. Static: nothing is imported or run (fast).
``tests/experiments/test_hemisphere.py`` checks the tables of a real quick run the same way.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import pytest

import validate.experiments as experiments
from validate.errors import ValidateError
from validate.format import LABEL_COLUMNS, UNITS, col, header_unit, missing_units

ROOT = Path(experiments.__file__).parent
HOLE = "{…}"  # an f-string's formatted value: a number or a name, never the unit
UNKNOWN = object()  # a header the source does not spell out


@dataclass(frozen=True)
class Column:
    where: str  # file:line of the Table call
    header: object  # the header text (f-string values as HOLE), or UNKNOWN with the source in ``source``
    source: str

    @property
    def ok(self) -> bool:
        return isinstance(self.header, str) and header_unit(self.header) is not None


def _bindings(body: list[ast.AST]) -> dict[str, ast.expr]:
    """The value last assigned to each plain name among ``body`` (statements, or a function's nodes)."""
    names: dict[str, ast.expr] = {}
    for node in body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name):
            names[node.targets[0].id] = node.value
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and node.value is not None:
            names[node.target.id] = node.value
    return names


class _Headers:
    """Symbolic evaluation of one ``headers`` expression into :class:`Column` s."""

    def __init__(self, src: str, where: str, names: list[dict[str, ast.expr]]) -> None:
        self.src, self.where, self.names = src, where, names

    def columns(self, e: ast.expr, depth: int = 0) -> list[Column]:
        if depth > 8:
            return [self._unknown(e)]
        if isinstance(e, ast.List | ast.Tuple):
            out: list[Column] = []
            for x in e.elts:
                out += self.columns(x.value, depth + 1) if isinstance(x, ast.Starred) else [self.column(x)]
            return out
        if isinstance(e, ast.BinOp) and isinstance(e.op, ast.Add):
            return self.columns(e.left, depth + 1) + self.columns(e.right, depth + 1)
        if isinstance(e, ast.ListComp | ast.GeneratorExp):
            loop = next((g.iter for g in e.generators if isinstance(e.elt, ast.Name)
                         and isinstance(g.target, ast.Name) and g.target.id == e.elt.id), None)
            return self.columns(loop, depth + 1) if isinstance(loop, ast.List | ast.Tuple) else [self.column(e.elt)]
        if isinstance(e, ast.Call) and isinstance(e.func, ast.Name) and e.func.id in ("list", "tuple") and e.args:
            return self.columns(e.args[0], depth + 1)
        if isinstance(e, ast.Name):
            value = next((scope[e.id] for scope in self.names if e.id in scope), None)
            return self.columns(value, depth + 1) if value is not None else [self._unknown(e)]
        return [self._unknown(e)]

    def column(self, e: ast.expr, depth: int = 0) -> Column:
        if isinstance(e, ast.Name) and depth < 8:  # a header held in a module constant
            value = next((scope[e.id] for scope in self.names if e.id in scope), None)
            return self.column(value, depth + 1) if value is not None else self._unknown(e)
        if isinstance(e, ast.Constant) and isinstance(e.value, str):
            return Column(self.where, e.value, e.value)
        if isinstance(e, ast.JoinedStr):
            text = "".join(v.value if isinstance(v, ast.Constant) else HOLE for v in e.values)
            return Column(self.where, text, ast.get_source_segment(self.src, e) or text)
        if (isinstance(e, ast.Call) and getattr(e.func, "id", getattr(e.func, "attr", None)) == "col"
                and len(e.args) == 2 and isinstance(e.args[1], ast.Constant)):
            name = self.column(e.args[0]).header
            return Column(self.where, f"{name if isinstance(name, str) else HOLE} ({e.args[1].value})",
                          ast.get_source_segment(self.src, e) or "col(...)")
        return self._unknown(e)

    def _unknown(self, e: ast.expr) -> Column:
        return Column(self.where, UNKNOWN, ast.get_source_segment(self.src, e) or ast.dump(e))


def _is_table(node: ast.AST) -> bool:
    return isinstance(node, ast.Call) and getattr(node.func, "id", getattr(node.func, "attr", None)) == "Table"


def table_columns(path: Path, root: Path = ROOT) -> list[Column]:
    """Every column of every ``Table(...)`` call in one source file; a name in ``headers`` is looked up in the
    innermost enclosing function, then in the module."""
    src = path.read_text(encoding="utf-8")
    if "Table(" not in src:
        return []
    tree = ast.parse(src)
    module = _bindings(tree.body)
    functions = [f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef | ast.AsyncFunctionDef)]
    out = []
    for node in (n for n in ast.walk(tree) if _is_table(n)):
        headers = node.args[0] if node.args else next((k.value for k in node.keywords if k.arg == "headers"), None)
        if headers is None:
            continue
        around = [f for f in functions if f.lineno <= node.lineno <= (f.end_lineno or f.lineno)]
        names = [_bindings(list(ast.walk(max(around, key=lambda f: f.lineno)))), module] if around else [module]
        out += _Headers(src, f"{path.relative_to(root).as_posix()}:{node.lineno}", names).columns(headers)
    return out


def all_columns() -> list[Column]:
    return [c for p in sorted(ROOT.rglob("*.py")) for c in table_columns(p)]


def test_every_table_column_of_every_experiment_names_its_unit() -> None:
    columns = all_columns()
    assert len({c.where for c in columns}) >= 50  # the scan finds the tables (59 Table calls when written)
    bad = [f"{c.where}: {c.header if c.ok or isinstance(c.header, str) else c.source!r}" for c in columns if not c.ok]
    assert not bad, ("table columns without a unit (end the header with one of validate.format.UNITS in "
                     "parentheses via col(name, unit), or add a column of words to LABEL_COLUMNS):\n"
                     + "\n".join(bad))


def test_the_scan_reads_the_forms_the_reports_use(tmp_path: Path) -> None:
    """The symbolic reader against a report written in every form: it must find the bad columns, not just pass."""
    f = tmp_path / "report.py"
    f.write_text(
        "HEAD = ['environment', 'E (W/m²)']\n"
        "def s(m, names):\n"
        "    extra = [f'{n} max (%)' for n in names]\n"
        "    return [Table(['β (°)', 'max |z|', col('z', '–')] + extra, []), Table(HEAD, []),\n"
        "            Table(['technique'] + names, []), Table([*(f'W (F₀ = {x:g})' for x in m)], []),\n"
        "            Table([h for n in names for h in (f'{n} max (%)', f'{n} at')], [])]\n",
        encoding="utf-8")
    got = [(c.header if isinstance(c.header, str) else c.source, c.ok) for c in table_columns(f, tmp_path)]
    assert got == [("β (°)", True), ("max |z|", False), ("z (–)", True), ("{…} max (%)", True),
                   ("environment", True), ("E (W/m²)", True), ("technique", True), ("names", False),
                   ("W (F₀ = {…})", False), ("{…} max (%)", True), ("{…} at", False)]


@pytest.mark.parametrize(("header", "unit"), [
    ("β (°)", "°"), ("max |z| (–)", "–"), ("E (W/m²)", "W/m²"), ("technique", ""), ("max rel. diff", None),
    ("Mitsuba E (red) ± s.e.", None), ("(θ_v, θ_l, Δφ)", None), ("glPolygonOffset(factor, units)", None),
])
def test_header_unit_accepts_units_only(header: str, unit: str | None) -> None:
    assert header_unit(header) == unit


def test_col_writes_and_checks_the_unit() -> None:
    assert col("max |z|", "–") == "max |z| (–)" and header_unit(col("t", "s")) == "s"
    assert missing_units(["technique", col("E", "W/m²"), "error"]) == ["error"]
    assert all(header_unit(col("x", u)) == u for u in UNITS) and not LABEL_COLUMNS & UNITS
    for bad in ("", "red", "percent"):
        with pytest.raises(ValidateError, match="unit"):
            col("x", bad)
