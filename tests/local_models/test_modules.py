"""Every module of every technique family imports by name, and the family layout holds.

Layout (validate/local_models/__init__.py): one folder per family, one file per technique, the family's shared
code in modules that register nothing; every family is defined in ``local_models/families.py``. Checked here:

* each module of each family folder imports by its dotted name (parametrised over the folders, found on disk,
  so a new file is tested without being listed), and whatever it registers belongs to that folder's family;
* a technique module never imports another technique module (shared code lives in a module of the family
  that registers nothing; read from the sources' import statements, absolute and relative);
* ``define_family`` is called in ``families.py`` only, and every family it defines has its folder.
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import pkgutil
from pathlib import Path

import pytest

import validate.local_models as lm
from validate.local_models import families

ROOT = Path(lm.__file__).parent
FOLDERS = tuple(families.__all__)


def _modules() -> list[str]:
    """Dotted names of every module and sub-package inside the family folders (from the file system)."""
    names: list[str] = []
    for fam in FOLDERS:
        prefix = f"validate.local_models.{fam}."
        for info in pkgutil.walk_packages([str(ROOT / fam)], prefix):
            names.append(info.name)
    return sorted(names)


MODULES = _modules()


def _registered_by() -> dict[str, set[str]]:
    """module name → names of the techniques whose function it defines (all families)."""
    out: dict[str, set[str]] = {}
    for fam in lm.FAMILIES.values():
        for tech in fam.techniques().values():  # every technique, those judged by some experiments only included
            if "glsl" in tech.meta and tech.builtin and tech.meta["glsl"].endswith(".glsl"):
                continue  # a GLSL built-in: a .glsl file, checked by test_glsl_builtins_live_in_their_family
            out.setdefault(tech.fn.__module__, set()).add(tech.name)
    return out


def test_glsl_builtins_live_in_their_family_folder() -> None:
    glsl = [t for fam in lm.FAMILIES.values() for t in fam if str(t.meta.get("glsl", "")).endswith(".glsl")]
    for tech in glsl:
        path = Path(tech.meta["glsl"])
        if tech.builtin:
            assert path.parent.name == tech.family, f"{tech.name}: {path} is not in local_models/{tech.family}/"


def _imported_modules(name: str) -> set[str]:
    """Absolute names of the validate.local_models modules ``name`` imports (module level or in functions)."""
    mod = importlib.import_module(name)
    path = Path(mod.__file__)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            base = importlib.util.resolve_name("." * node.level + (node.module or ""), package) if node.level \
                else (node.module or "")
            found.add(base)
            found.update(f"{base}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
    return {m for m in found if m.startswith("validate.local_models.") and m in MODULES}


def test_the_walk_finds_every_family_folder_and_the_techniques_the_issue_named() -> None:
    assert {m.split(".")[2] for m in MODULES} == set(FOLDERS)
    for name in ("validate.local_models.light.classic_lights", "validate.local_models.light.light_grid",
                 "validate.local_models.irradiance.engines"):
        assert name in MODULES


@pytest.mark.parametrize("name", MODULES)
def test_module_imports_by_name(name: str) -> None:
    mod = importlib.import_module(name)
    assert mod.__name__ == name
    folder = name.split(".")[2]
    techniques = _registered_by().get(name, set())
    for tech in techniques:
        assert lm.family(folder)[tech].fn.__module__ == name, f"{tech} registered by {name} outside its family"


def test_every_technique_module_registers_and_every_family_has_techniques() -> None:
    owners = _registered_by()
    builtin = {m for m in owners if m.startswith("validate.local_models.")}
    assert builtin <= set(MODULES), f"techniques defined outside the family folders: {sorted(builtin - set(MODULES))}"
    for fam in FOLDERS:
        assert any(m.split(".")[2] == fam for m in builtin), f"family {fam} has no built-in technique module"


@pytest.mark.parametrize("name", sorted(m for m in MODULES if m in _registered_by()))
def test_a_technique_never_imports_a_sibling_technique(name: str) -> None:
    techniques = set(_registered_by())
    imported = _imported_modules(name) & techniques - {name}
    assert not imported, f"{name} imports technique module(s) {sorted(imported)}; move shared code to the family"


def test_define_family_is_called_in_families_py_only() -> None:
    callers = []
    for path in sorted(ROOT.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            called = getattr(node.func, "id", getattr(node.func, "attr", "")) if isinstance(node, ast.Call) else ""
            if called == "define_family":
                callers.append(path.relative_to(ROOT).as_posix())
    assert set(callers) == {"families.py"}, callers
    assert list(lm.FAMILIES)[:len(FOLDERS)] == list(FOLDERS)


@pytest.mark.parametrize("folder", FOLDERS)
def test_each_family_package_stands_for_its_family(folder: str) -> None:
    package = importlib.import_module(f"validate.local_models.{folder}")
    fam = lm.family(folder)
    assert getattr(lm, folder) is package
    assert package.family is fam and package.register == fam.register
    assert [t.name for t in package] == [t.name for t in fam] and len(package) == len(fam) > 0
    first = next(iter(fam))
    assert first.name in package and package[first.name] is first
