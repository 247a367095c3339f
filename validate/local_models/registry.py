"""One registry mechanism for every technique family.

A *family* is a kind of local lighting model with one array contract (what the function receives,
what it returns). A *technique* is one registered function of a family. Built-in techniques register
exactly as plug-ins do, with the family's decorator::

    from validate.local_models import irradiance

    @irradiance.register("my_sh4", "SH up to l = 4",
                         thresholds={"flux_luminance.mean": 0.01, "flux_luminance.max": 0.05},
                         source="R&H 2001 §4: average < 1 %, max < 5 % of the total flux")
    def my_sh4(radiance, normals):
        ...
        return irradiance  # (N, 3)

Every experiment of the family iterates over ``family.techniques()`` and calls each through
:meth:`Family.call`, which checks the output contract (shape, finite values, non-negative or within
bounds where the family says the quantity is physical) and raises :class:`ValidateError` with one
line ``technique '<name>' (<family>): <problem>``.

A technique registered with ``experiments=("ibl",)`` is judged by those experiments only: iterating the family
(``for t in irradiance``, what every experiment of the family does) leaves it out, :meth:`Family.judged_by`
(``irradiance.judged_by("ibl")``) includes it, :meth:`Family.techniques` lists everything. It is for techniques
too costly to run wherever the family is used (an external tool per environment: the glTF-IBL-Sampler). Such a
technique may declare ``unavailable=<callable() -> str | None>`` (why it cannot run here, or None); the
experiments that judge it skip it with that reason.

``thresholds`` are the technique's own declared bounds, ``metric → upper limit`` with metric names
the experiment documents (e.g. ``flux_luminance.mean``); each becomes the claim
``<experiment>.technique.<name>.<metric>``. ``source`` cites where the limits come from.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys
import types
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ValidateError
from .precision import check_precision, family_precision

ShapeFn = Callable[..., tuple[int, ...]]


@dataclass(frozen=True)
class Technique:
    """One registered technique: ``fn`` follows its family's contract."""

    name: str
    family: str
    fn: Callable[..., Any]
    description: str
    thresholds: Mapping[str, float] = field(default_factory=dict)
    source: str = ""
    meta: Mapping[str, Any] = field(default_factory=dict)

    @property
    def builtin(self) -> bool:
        """Shipped with the suite (informational only: built-ins go through the same registry)."""
        return getattr(self.fn, "__module__", "").startswith("validate.")


@dataclass
class Family:
    """A technique family: its name, the documented contract and how outputs are checked.

    ``output_shape(*args, **kwargs)`` gives the expected output shape for the call's inputs.
    ``lower``/``upper`` bound every output value where the quantity is physical (``None``: no bound).
    ``precision`` is the drjit float dtype the family's techniques compute in ("float32" or "float64",
    :mod:`.precision`), active for the duration of every :meth:`call`; ``precision_reason`` says why.
    """

    name: str
    contract: str
    output_shape: ShapeFn
    lower: float | None = None
    upper: float | None = None
    bounds_reason: str = ""
    glsl_contract: str = ""  # the GLSL entry point and its uniforms, where the family has one (each family's glsl.py)
    precision: str = "float32"
    precision_reason: str = ""
    _techniques: dict[str, Technique] = field(default_factory=dict, repr=False)

    # -- registration -------------------------------------------------------------------------
    def register(self, name: str, description: str = "", *, thresholds: Mapping[str, float] | None = None,
                 source: str = "", **meta: Any) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
        """Decorator registering ``fn`` as technique ``name`` of this family (a duplicate is an error)."""
        if not isinstance(name, str) or not name or any(c.isspace() for c in name):
            raise ValidateError(f"technique name {name!r} ({self.name}): must be a non-empty word")
        for metric, limit in (thresholds or {}).items():
            if not isinstance(limit, (int, float)) or not np.isfinite(limit):
                raise ValidateError(f"technique '{name}' ({self.name}): threshold {metric!r} must be a finite number")

        def deco(fn: Callable[..., Any]) -> Callable[..., Any]:
            if name in self._techniques:
                raise ValidateError(f"technique '{name}' ({self.name}): already registered "
                                    f"(by {self._techniques[name].fn.__module__}); pick another name")
            if not callable(fn):
                raise ValidateError(f"technique '{name}' ({self.name}): not callable")
            doc = description or (fn.__doc__ or "").strip().split("\n")[0]
            self._techniques[name] = Technique(name, self.name, fn, doc, dict(thresholds or {}), source, meta)
            return fn
        return deco

    def add(self, name: str, fn: Callable[..., Any], description: str = "", **kwargs: Any) -> Technique:
        """Non-decorator form of :meth:`register`."""
        self.register(name, description, **kwargs)(fn)
        return self._techniques[name]

    def unregister(self, name: str) -> None:
        """Remove a technique (tests and interactive use)."""
        self._techniques.pop(name, None)

    # -- lookup -------------------------------------------------------------------------------
    def techniques(self) -> dict[str, Technique]:
        """Every registered technique, in registration order (built-ins first, then plug-ins)."""
        return dict(self._techniques)

    def __iter__(self) -> Iterator[Technique]:
        """The techniques every experiment of the family judges (those registered with ``experiments=(...)``
        left out: :meth:`judged_by`)."""
        return iter([t for t in self._techniques.values() if not t.meta.get("experiments")])

    def judged_by(self, experiment: str) -> list[Technique]:
        """The techniques experiment ``experiment`` judges: every one of :meth:`__iter__` plus those registered
        with ``experiments=(...)`` naming it, in registration order."""
        return [t for t in self._techniques.values()
                if not t.meta.get("experiments") or experiment in tuple(t.meta["experiments"])]

    def __contains__(self, name: object) -> bool:
        return name in self._techniques

    def __len__(self) -> int:
        return len(list(iter(self)))

    def __getitem__(self, name: str) -> Technique:
        try:
            return self._techniques[name]
        except KeyError:
            raise ValidateError(f"unknown {self.name} technique {name!r}; registered: "
                                f"{', '.join(self._techniques) or 'none'}") from None

    # -- calling ------------------------------------------------------------------------------
    def call(self, name: str | Technique, *args: Any, **kwargs: Any) -> np.ndarray:
        """Call a technique with the family's :attr:`precision` active (:func:`.precision.to_dr` converts to it)
        and check its output contract; returns a float64 array."""
        tech = name if isinstance(name, Technique) else self[name]
        try:
            with family_precision(self.precision):
                out = tech.fn(*args, **kwargs)
        except ValidateError:
            raise
        except Exception as exc:  # a plug-in's own bug: name it, one line
            raise ValidateError(f"technique '{tech.name}' ({self.name}): raised {type(exc).__name__}: {exc}") from None
        return self.check(tech.name, out, self.output_shape(*args, **kwargs))

    def check(self, name: str, out: Any, shape: tuple[int, ...]) -> np.ndarray:
        """The output contract: array of ``shape``, finite, within the family's physical bounds."""
        where = f"technique '{name}' ({self.name})"
        try:
            arr = np.asarray(out, dtype=np.float64)
        except Exception:
            raise ValidateError(f"{where}: returned {type(out).__name__}, not an array of numbers") from None
        if arr.shape != tuple(shape):
            raise ValidateError(f"{where}: returned shape {arr.shape}, expected {tuple(shape)}")
        bad = ~np.isfinite(arr)
        if bad.any():
            kinds = "NaN" if np.isnan(arr).any() else "Inf"
            raise ValidateError(f"{where}: returned {int(bad.sum())} non-finite value(s) ({kinds})")
        if self.lower is not None and (arr < self.lower).any():
            raise ValidateError(f"{where}: returned {int((arr < self.lower).sum())} value(s) below {self.lower:g} "
                                f"(min {arr.min():.4g}); {self.bounds_reason}")
        if self.upper is not None and (arr > self.upper).any():
            raise ValidateError(f"{where}: returned {int((arr > self.upper).sum())} value(s) above {self.upper:g} "
                                f"(max {arr.max():.4g}); {self.bounds_reason}")
        return arr


FAMILIES: dict[str, Family] = {}


def define_family(name: str, contract: str, output_shape: ShapeFn, *, lower: float | None = None,
                  upper: float | None = None, bounds_reason: str = "", precision: str = "float32",
                  precision_reason: str = "") -> Family:
    """Create and register a family (a duplicate family name is an error); ``precision`` is the dtype its
    techniques compute in (:mod:`.precision`), ``precision_reason`` why."""
    if name in FAMILIES:
        raise ValidateError(f"technique family {name!r} is already defined")
    check_precision(precision, f"technique family {name!r}")
    fam = Family(name, " ".join(contract.split()), output_shape, lower, upper, bounds_reason,
                 precision=precision, precision_reason=" ".join(precision_reason.split()))
    FAMILIES[name] = fam
    return fam


def family(name: str) -> Family:
    """The family called ``name`` (unknown → one-line error)."""
    try:
        return FAMILIES[name]
    except KeyError:
        raise ValidateError(f"unknown technique family {name!r}; defined: {', '.join(FAMILIES)}") from None


def find_technique(name: str) -> list[Technique]:
    """Every technique of that name across families."""
    return [f._techniques[name] for f in FAMILIES.values() if name in f._techniques]


class FamilyPackage(types.ModuleType):
    """The package of a family folder (``local_models/<family>/``) standing for its :class:`Family`.

    ``from validate.local_models import irradiance`` gives the package ``validate.local_models.irradiance``
    (its technique files are submodules), and the package answers as the family does: ``irradiance.register``,
    ``irradiance.call``, ``for t in irradiance``, ``"sh9" in irradiance``, ``irradiance["sh9"]``. Attributes the
    package itself lacks (not a submodule, not defined in its ``__init__``) are looked up on ``family``.
    """

    family: Family

    def __getattr__(self, name: str) -> Any:
        fam = self.__dict__.get("family")
        if fam is None or name.startswith("__"):
            raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}")
        return getattr(fam, name)

    def __iter__(self) -> Iterator[Technique]:
        return iter(self.family)

    def __len__(self) -> int:
        return len(self.family)

    def __contains__(self, name: object) -> bool:
        return name in self.family

    def __getitem__(self, name: str) -> Technique:
        return self.family[name]


def family_package(module_name: str, fam: Family, first: tuple[str, ...] = ()) -> None:
    """Make the family folder's package ``module_name`` stand for ``fam`` and import its techniques.

    Every module and sub-package of the folder is imported and registers its own techniques, so a new
    built-in is one new file. Import order is registration order (the order of tables and ``results.json``):
    the modules named in ``first``, then the rest alphabetically; names starting with ``_`` are skipped.
    Modules that register nothing (the family's shared code) are imported all the same, harmlessly.
    """
    package = sys.modules[module_name]
    package.family = fam  # type: ignore[attr-defined]
    package.__class__ = FamilyPackage
    found = sorted(m.name for m in pkgutil.iter_modules(package.__path__) if not m.name.startswith("_"))
    missing = [name for name in first if name not in found]
    if missing:
        raise ValidateError(f"technique family {fam.name!r}: listed module(s) {', '.join(missing)} not found")
    for name in [*first, *(n for n in found if n not in first)]:
        importlib.import_module(f"{module_name}.{name}")
