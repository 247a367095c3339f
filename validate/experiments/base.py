"""What an experiment is and what it returns.

An experiment sweeps something, compares local models with the reference, and returns an
:class:`ExperimentResult`: claims (bound-based pass/fail), findings in words, report sections
(text, figures, tables) and a JSON-able ``data`` dict. The report is rendered from the JSON alone,
so ``run NAME`` can update one experiment and re-render the page without losing the others.

Claims pass only when the *bound* clears the threshold: for ``comparison="<"`` the claim passes iff
measured + uncertainty < threshold; for ``">"`` iff measured − uncertainty > threshold.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, TypeVar

T = TypeVar("T")


@dataclass
class Power:
    """The same claim evaluated under a perturbation of the size a real bug would have.

    ``fails`` must be True for the claim to mean anything: had the technique (or the reference) been
    wrong by that much, the claim would have caught it.
    """

    perturbation: str
    measured: float
    fails: bool
    uncertainty: float = 0.0

    def to_json(self) -> dict[str, Any]:
        return {"perturbation": self.perturbation, "measured": _finite(self.measured),
                "uncertainty": _finite(self.uncertainty), "fails": bool(self.fails)}


def _finite(x: float) -> float | None:
    x = float(x)
    return x if x == x and abs(x) != float("inf") else None


@dataclass
class Claim:
    id: str
    description: str
    metric: str
    threshold: float
    measured: float
    uncertainty: float
    comparison: str = "<"  # "<": measured + uncertainty < threshold; ">": measured − uncertainty > threshold
    unit: str = ""  # "%" means values are fractions displayed as percent
    source: str = ""  # where the threshold comes from: paper + equation/table, theorem, or a measured margin
    power: Power | None = None

    def holds(self, measured: float, uncertainty: float) -> bool:
        """Does the bound clear the threshold for these values? (NaN never holds.)"""
        if self.comparison == "<":
            return bool(measured + uncertainty < self.threshold)
        return bool(measured - uncertainty > self.threshold)

    @property
    def passed(self) -> bool:
        return self.holds(self.measured, self.uncertainty)

    def with_power(self, perturbation: str, measured: float, uncertainty: float | None = None) -> Claim:
        """Attach the power check: the claim re-evaluated on ``measured`` (± ``uncertainty``, default the
        claim's own) obtained under ``perturbation``; it *fails* when the perturbed bound misses."""
        unc = self.uncertainty if uncertainty is None else float(uncertainty)
        self.power = Power(perturbation, float(measured), not self.holds(float(measured), unc), unc)
        return self

    def to_json(self) -> dict[str, Any]:
        d = asdict(self)
        d["measured"], d["uncertainty"] = _finite(self.measured), _finite(self.uncertainty)
        d["passed"] = self.passed
        d["power"] = self.power.to_json() if self.power is not None else None
        return d


@dataclass
class Figure:
    path: str  # relative to the report folder, e.g. "figures/sh9/grace_probe_error.png"
    caption: str
    width: int | None = None  # display width in px (None: natural)


@dataclass
class Table:
    headers: list[str]
    rows: list[list[Any]]
    caption: str = ""


@dataclass
class Section:
    title: str
    paragraphs: list[str] = field(default_factory=list)  # plain text (escaped in HTML)
    figures: list[Figure] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)
    gallery: list[list[Figure]] = field(default_factory=list)  # rows of images shown side by side


@dataclass
class ExperimentResult:
    name: str
    title: str
    summary: str
    claims: list[Claim] = field(default_factory=list)
    findings: list[str] = field(default_factory=list)
    sections: list[Section] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)
    wall_time_s: float = 0.0
    settings: dict[str, Any] = field(default_factory=dict)
    # per registered technique: {technique: {"family": ..., "description": ..., "metrics": {...}}}
    techniques: dict[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "title": self.title,
            "summary": self.summary,
            "claims": [c.to_json() for c in self.claims],
            "findings": list(self.findings),
            "wall_time_s": self.wall_time_s,
            "settings": self.settings,
            "report": {"sections": [asdict(s) for s in self.sections]},
            "techniques": self.techniques,
        }
        out.update(self.data)
        return out


@dataclass
class Context:
    """Everything an experiment may use: where to write, how hard to try, which inputs."""

    out_dir: Path
    quick: bool = False
    probes_dir: Path | None = None
    probe_files: list[Path] = field(default_factory=list)
    layout: str = "auto"
    clamp_negative: bool = False
    show_progress: bool = True
    seed: int = 1234
    log: Callable[[str], None] = print
    _env_cache: dict[str, Any] = field(default_factory=dict)

    def figure_dir(self, experiment: str) -> Path:
        d = self.out_dir / "figures" / experiment
        d.mkdir(parents=True, exist_ok=True)
        return d

    def figure_path(self, experiment: str, filename: str) -> tuple[Path, str]:
        """(absolute path to write, path relative to the report folder)."""
        p = self.figure_dir(experiment) / filename
        return p, p.relative_to(self.out_dir).as_posix()

    def progress(self, items: Iterable[T], desc: str, total: int | None = None) -> Iterator[T]:
        from tqdm import tqdm

        yield from tqdm(items, desc=desc, total=total, disable=not self.show_progress, leave=False,
                        dynamic_ncols=True)

    def map(self, fn: Callable[[Any], T], items: Iterable[Any], desc: str) -> list[T]:
        """``[fn(x) for x in items]`` with a progress bar. Experiments express per-environment work
        through this one call so that it can run as independent tasks (serial here; see scale-out)."""
        items = list(items)
        return [fn(x) for x in self.progress(items, desc, total=len(items))]

    def environments(self) -> tuple[list[Any], list[tuple[str, str]]]:
        """Built-in environments plus every probe found (probes dir and explicit files).

        Returns (environments, skipped) where skipped lists (file, one-line reason) for probe files in
        a scanned directory that failed validation. Explicitly named files raise instead.
        """
        if "envs" not in self._env_cache:
            from ..scenes import probes, procedural

            envs = list(procedural.builtin_environments(self.quick))
            only = set(probes.read_aliases()) if self.quick else None  # quick: the paper's probes only
            found, skipped = probes.load_probes(self.probes_dir, self.probe_files, self.layout,
                                                self.clamp_negative, log=self.log, only_stems=only)
            self._env_cache["envs"] = (envs + found, skipped)
        return self._env_cache["envs"]


@dataclass(frozen=True)
class Experiment:
    name: str
    title: str
    description: str
    run: Callable[[Context], ExperimentResult]
    order: int = 100


EXPERIMENTS: dict[str, Experiment] = {}


def register_experiment(name: str, title: str, description: str, order: int = 100
                        ) -> Callable[[Callable[[Context], ExperimentResult]], Callable[[Context], ExperimentResult]]:
    def deco(fn: Callable[[Context], ExperimentResult]) -> Callable[[Context], ExperimentResult]:
        def timed(ctx: Context) -> ExperimentResult:
            t0 = time.perf_counter()
            res = fn(ctx)
            res.wall_time_s = round(time.perf_counter() - t0, 2)
            return res
        EXPERIMENTS[name] = Experiment(name, title, description, timed, order)
        return fn
    return deco
