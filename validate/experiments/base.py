"""What an experiment is and what it returns.

An experiment sweeps something, compares local models with the reference, and returns an
:class:`ExperimentResult`: claims (bound-based pass/fail), findings in words, report sections
(text, figures, tables) and a JSON-able ``data`` dict. The report is rendered from the JSON alone,
so ``run NAME`` can update one experiment and re-render the page without losing the others.

Claims pass only when the *bound* clears the threshold: for ``comparison="<"`` the claim passes iff
measured + uncertainty < threshold; for ``">"`` iff measured − uncertainty > threshold.
"""

from __future__ import annotations

import functools
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import asdict, dataclass, field, fields, is_dataclass
from pathlib import Path
from typing import Any, ClassVar, Generic, Protocol, TypeVar, runtime_checkable

from ..backend import init
from ..errors import ValidateError
from ..scenes import probes, procedural

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
        return {"perturbation": self.perturbation, "measured": finite_or_none(self.measured),
                "uncertainty": finite_or_none(self.uncertainty), "fails": bool(self.fails)}


def settings_json(obj: Any, omit: Iterable[str] = (), **extra: Any) -> Any:
    """Settings as JSON: a dataclass as a dict of its fields (less ``omit``, plus ``extra``), recursively, tuples and
    lists as lists, mappings with their values converted; anything else as it is. The one conversion every
    experiment's ``settings`` entry of ``results.json`` goes through (:func:`run`)."""
    if is_dataclass(obj) and not isinstance(obj, type):
        skip = set(omit)
        obj = {f.name: getattr(obj, f.name) for f in fields(obj) if f.name not in skip}
    elif isinstance(obj, Mapping):
        skip = set(omit)
        obj = {k: v for k, v in obj.items() if k not in skip}
    elif isinstance(obj, (tuple, list)):
        return [settings_json(v) for v in obj]
    else:
        return obj
    return {k: settings_json(v) for k, v in (obj | extra).items()}


def finite_or_none(x: float) -> float | None:
    """``x`` as a float, or None for NaN and ±inf (``results.json`` stays strict JSON)."""
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
        d["measured"], d["uncertainty"] = finite_or_none(self.measured), finite_or_none(self.uncertainty)
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


@dataclass(frozen=True)
class NotRun:
    """Something an experiment exists to judge that this run could not run (an engine, a browser, a GL runtime),
    with why and the command that installs it. A run that leaves one out says so on the command line, in
    ``results.json`` (``experiments.<name>.not_run``) and on the page; ``--strict`` exits 1 on it: nothing
    judged is not a pass."""

    what: str  # e.g. "three.js, Filament"
    why: str  # e.g. "npm engines not installed in ~/.local/share/validate/engines/node_modules"
    fix: str = ""  # e.g. "python -m validate setup --engines"

    def line(self) -> str:
        return f"{self.what} not run: {self.why}" + (f" — `{self.fix}`" if self.fix else "")

    def to_json(self) -> dict[str, str]:
        return {"what": self.what, "why": self.why, "fix": self.fix}


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
    not_run: list[NotRun] = field(default_factory=list)

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
            "not_run": [n.to_json() for n in self.not_run],
        }
        clash = set(self.data) & {"title", "summary", "claims", "findings", "wall_time_s", "settings", "report",
                                   "techniques", "not_run"}
        if clash:  # the report contract's keys are not the experiment's to overwrite
            raise ValueError(f"experiment {self.name}: data uses reserved key(s) {sorted(clash)}")
        out.update(self.data)
        return out


@dataclass
class Context:
    """Everything an experiment may use: where to write, how hard to try, which inputs, and where the
    per-environment tasks run.

    Scale-out: :meth:`map` runs ``fn`` over items in this process (``workers == 1``, no scheduler), on
    an embedded ``dask.distributed.LocalCluster`` of ``workers`` processes (one thread each), or on an
    existing Dask cluster (``scheduler`` = its address). Tasks are pure functions of their item and of
    the context (seeds come from ``seed`` and the item, never from the worker), so every mode returns
    the same numbers. Workers choose their Mitsuba variant with the same subprocess probe
    (:func:`validate.backend.init`, which reuses the parent's result through the environment), then
    run ``worker_setup`` (the CLI passes "load these plug-ins") once per process. Figures written by a
    task go to ``out_dir``, the run's staging folder, which workers must see: the local cluster shares
    the file system; a remote cluster needs ``--out`` on a shared one.
    """

    out_dir: Path
    quick: bool = False
    probes_dir: Path | None = None
    probe_files: list[Path] = field(default_factory=list)
    layout: str = "auto"
    clamp_negative: bool = False
    show_progress: bool = True
    seed: int = 1234
    log: Callable[[str], None] = print
    workers: int = 1
    scheduler: str | None = None
    worker_setup: Callable[[], None] | None = None  # picklable; run once per worker process
    _env_cache: dict[str, Any] = field(default_factory=dict)
    _client: Any = field(default=None, repr=False)
    _ready: ClassVar[set[str]] = set()  # worker_setup already run in this process (by repr)

    def __getstate__(self) -> dict[str, Any]:
        """Tasks capture the context: ship it without the loaded environments or the Dask client."""
        state = dict(self.__dict__)
        state["_env_cache"], state["_client"] = {}, None
        return state

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

    @property
    def distributed(self) -> bool:
        return self.scheduler is not None or self.workers > 1

    def map(self, fn: Callable[[Any], T], items: Iterable[Any], desc: str) -> list[T]:
        """``[fn(x) for x in items]`` with a progress bar counting finished tasks, in this process or
        as Dask tasks (see the class docstring); results keep the order of ``items``. A task that
        fails on a worker raises :class:`~validate.errors.ValidateError` naming ``desc`` and the item
        (its ``name``, e.g. the environment)."""
        items = list(items)
        if not self.distributed or not items:
            return [fn(x) for x in self.progress(items, desc, total=len(items))]
        from dask.distributed import as_completed

        client = self.client()
        try:
            [fn_future] = client.scatter([fn], broadcast=True, hash=False)
            item_futures = client.scatter(items, hash=False)
        except Exception as exc:  # e.g. an item or closure that cannot be pickled
            why = (str(exc).strip().splitlines() or [""])[0][:200]
            raise ValidateError(f"task {desc!r}: cannot ship the work to Dask workers "
                                f"({type(exc).__name__}: {why})") from None
        futures = [client.submit(Context._run_task, fn_future, it, self.worker_setup, pure=False)
                   for it in item_futures]
        index = {f.key: k for k, f in enumerate(futures)}
        try:
            for fut in self.progress(as_completed(futures), desc, total=len(futures)):
                if fut.status == "error":
                    raise self._task_error(desc, items[index[fut.key]], fut.exception())
            return [f.result() for f in futures]
        finally:
            client.cancel(futures + item_futures + [fn_future])

    @staticmethod
    def _run_task(fn: Callable[[Any], T], item: Any, setup: Callable[[], None] | None) -> T:
        """One task on a worker: choose the variant (probe), run the setup once, then ``fn(item)``."""
        init()
        if setup is not None and repr(setup) not in Context._ready:
            setup()
            Context._ready.add(repr(setup))
        return fn(item)

    @staticmethod
    def _task_error(desc: str, item: Any, exc: BaseException | None) -> Exception:
        def label(x: Any) -> str:
            if hasattr(x, "name"):
                return str(x.name)
            if isinstance(x, (tuple, list)) and any(hasattr(y, "name") for y in x):
                return ", ".join(str(y.name) for y in x if hasattr(y, "name"))
            return repr(x)[:60]

        text = str(exc).strip().splitlines()[0] if exc is not None and str(exc).strip() else ""
        if isinstance(exc, ValidateError):
            return ValidateError(f"{text} (task {desc!r}, environment {label(item)})")
        kind = type(exc).__name__ if exc is not None else "unknown error"
        return ValidateError(f"task {desc!r} failed on environment {label(item)}: {kind}: {text}"[:400])

    def client(self) -> Any:
        """The Dask client: connected to ``scheduler``, else to an embedded LocalCluster (started once)."""
        if self._client is None:
            import logging

            import dask
            from dask.distributed import Client, LocalCluster

            if self.scheduler is not None:
                try:
                    self._client = Client(self.scheduler, timeout="20s")
                except (OSError, TimeoutError) as exc:
                    raise ValidateError(f"--scheduler {self.scheduler}: cannot connect ({exc})") from None
            else:
                # Dask pins BLAS/OpenMP to one thread in its workers; a BLAS product then sums in
                # another order than in this process (measured: 1 ulp in the reference's float32
                # kernel product). Workers inherit this process's thread settings instead, so the
                # numbers are identical to the serial run's. Dask also sets MALLOC_TRIM_THRESHOLD_=65536
                # (return freed memory to the OS at once); that fixes glibc's mmap threshold at 128 KiB,
                # so every larger numpy temporary is a fresh mapping, page-faulted anew: measured on
                # `run multiscatter --workers 2`, 4.2 M minor faults and 17.9 s of system time against
                # 1.07 M and 6.0 s serially. Workers keep glibc's defaults, as this process does.
                environ = {k: v for k, v in dask.config.get("distributed.nanny.pre-spawn-environ", {}).items()
                           if not k.endswith("_NUM_THREADS") and k != "MALLOC_TRIM_THRESHOLD_"}
                # and no statistical profiler in the workers (a thread sampling every task's stack every 10 ms,
                # for a dashboard this run does not serve)
                with dask.config.set({"distributed.nanny.pre-spawn-environ": environ,
                                      "distributed.worker.profile.enabled": False}):
                    cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                           memory_limit=0, dashboard_address=None, silence_logs=logging.CRITICAL,
                                           # no dashboard, and its HTTP server (health routes) on a free port:
                                           # distributed's default 8787 warns on stderr when another cluster has it
                                           scheduler_kwargs={"dashboard_address": ":0"})
                self._client = Client(cluster)
        return self._client

    def close(self) -> None:
        """Disconnect from the cluster; an embedded LocalCluster is shut down."""
        client, self._client = self._client, None
        if client is None:
            return
        cluster = client.cluster if self.scheduler is None else None
        client.close()
        if cluster is not None:
            cluster.close()

    def environments(self) -> tuple[list[Any], list[tuple[str, str]]]:
        """Built-in environments plus every probe found (probes dir and explicit files).

        Returns (environments, skipped) where skipped lists (file, one-line reason) for probe files in
        a scanned directory that failed validation. Explicitly named files raise instead.
        """
        if "envs" not in self._env_cache:
            only = set(probes.read_aliases()) if self.quick else None  # quick: the paper's probes only
            # probes first: a bad probe file is refused before seconds of built-in maps are made
            found, skipped = probes.load_probes(self.probes_dir, self.probe_files, self.layout,
                                                self.clamp_negative, log=self.log, only_stems=only)
            envs = list(procedural.builtin_environments(self.quick))
            self._env_cache["envs"] = (envs + found, skipped)
        return self._env_cache["envs"]


class Background(threading.Thread, Generic[T]):
    """``fn()`` on a daemon thread of this process: :meth:`result` waits and returns its value or re-raises its
    exception in the caller's thread; :meth:`failed` is the exception once it has ended with one. Daemon: an
    interrupt unwinds the main thread (:mod:`validate.run.interrupt`) without waiting for it. Used for work that
    waits on other processes (Dask tasks, the browser) while this thread goes on."""

    def __init__(self, fn: Callable[[], T], name: str) -> None:
        super().__init__(name=name, daemon=True)
        self._fn = fn
        self._value: T | None = None
        self._error: BaseException | None = None
        self.start()

    def run(self) -> None:
        try:
            self._value = self._fn()
        except BaseException as exc:  # re-raised in the caller's thread by result()
            self._error = exc

    def failed(self) -> BaseException | None:
        return None if self.is_alive() else self._error

    def result(self) -> T:
        self.join()
        if self._error is not None:
            raise self._error
        return self._value  # type: ignore[return-value]


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


@runtime_checkable
class ExperimentModule(Protocol):
    """The interface every experiment package declares in its ``__init__`` (its ``__all__``: these names and the
    optional hooks below it defines, nothing else); :func:`run` does the wiring.

    The stages: ``settings.py`` (``QUICK``, ``FULL``: two instances of one frozen dataclass) → ``compute.py``
    (``compute(ctx, s) -> Measurements``, numbers only) → ``claims.py`` (``claims(m) -> list[Claim]``) →
    ``report.py`` (``findings(m) -> list[str]``, ``sections(m, ctx) -> list[Section]``). ``TITLE`` is the
    experiment's one title (the page heading, ``results.json``'s ``title``, ``validate list``).

    Optional hooks (:data:`HOOKS`, defaults in :func:`run`): ``summary(m) -> str`` (default ``DESCRIPTION``),
    ``data(m) -> dict`` (the experiment's own ``results.json`` keys; default none), ``techniques(m) -> dict``
    (``experiments.<name>.techniques``; default none), ``reported_settings(s, m, ctx)`` (what ``settings``
    reports, converted by :func:`settings_json`; default ``s``, the run's settings), ``not_run(m) -> list[NotRun]``
    (what the run could not judge here and why; default none) and ``PARTS`` (sub-experiments,
    :class:`PartModule`: sub-packages whose claims, findings, sections, data and techniques :func:`run` appends).
    """

    NAME: str
    TITLE: str
    DESCRIPTION: str
    ORDER: int
    QUICK: Any
    FULL: Any

    def compute(self, ctx: Context, s: Any) -> Any: ...

    def claims(self, m: Any) -> list[Claim]: ...

    def findings(self, m: Any) -> list[str]: ...

    def sections(self, m: Any, ctx: Context) -> list[Section]: ...


@runtime_checkable
class PartModule(Protocol):
    """A sub-experiment: a sub-package of an experiment with the same anatomy (``compute``, ``claims``, ``report``),
    listed in the parent's ``PARTS``. The parent's ``compute`` measures it (so its work may overlap the parent's)
    and keeps its measurements at ``KEY`` (a key of a dict of measurements, else an attribute); :func:`run` gives
    them to the part's stages and appends what they return to the parent's. Optional: ``data(pm) -> dict``,
    ``techniques(pm) -> dict`` (default none), and ``measure(ctx, s, m) -> pm``: a part that needs the parent's
    measurements and cannot be measured inside the parent's ``compute`` without an import circle (it imports
    :mod:`validate.judge`, which imports the parent) is measured by :func:`run` right after the parent."""

    KEY: str

    def claims(self, pm: Any) -> list[Claim]: ...

    def findings(self, pm: Any) -> list[str]: ...

    def sections(self, pm: Any, ctx: Context) -> list[Section]: ...


EXPERIMENT_INTERFACE = ("NAME", "TITLE", "DESCRIPTION", "ORDER", "QUICK", "FULL", "compute", "claims", "findings",
                        "sections")
HOOKS = ("summary", "data", "techniques", "reported_settings", "not_run", "PARTS")
PART_INTERFACE = ("KEY", "compute", "claims", "findings", "sections")


def part_measurements(m: Any, key: str) -> Any:
    """A part's measurements inside its parent's: ``m[key]`` for a dict, else ``m.key``."""
    return m[key] if isinstance(m, Mapping) else getattr(m, key)


def run(mod: Any, ctx: Context) -> ExperimentResult:
    """Run the experiment package ``mod`` (an :class:`ExperimentModule`): the settings of the run (``QUICK`` or
    ``FULL``), ``compute``, then every stage's output, its parts' appended, into one :class:`ExperimentResult`."""
    s = mod.QUICK if ctx.quick else mod.FULL
    m = mod.compute(ctx, s)
    parts = [(p, p.measure(ctx, s, m) if hasattr(p, "measure") else part_measurements(m, p.KEY))
             for p in getattr(mod, "PARTS", ())]
    claims = mod.claims(m) + [c for p, pm in parts for c in p.claims(pm)]
    findings = mod.findings(m) + [f for p, pm in parts for f in p.findings(pm)]
    sections = mod.sections(m, ctx) + [x for p, pm in parts for x in p.sections(pm, ctx)]
    data, techniques = _hook(mod, "data", m, {}), _hook(mod, "techniques", m, {})
    for p, pm in parts:
        data |= _hook(p, "data", pm, {})
        techniques |= _hook(p, "techniques", pm, {})
    not_run = [n for x, xm in [(mod, m), *parts] if hasattr(x, "not_run") for n in x.not_run(xm)]
    summary = mod.summary(m) if hasattr(mod, "summary") else mod.DESCRIPTION
    reported = mod.reported_settings(s, m, ctx) if hasattr(mod, "reported_settings") else s
    return ExperimentResult(mod.NAME, mod.TITLE, summary, claims, findings, sections, data,
                            settings=settings_json(reported), techniques=techniques, not_run=not_run)


def _hook(mod: Any, name: str, m: Any, default: dict[str, Any]) -> dict[str, Any]:
    return dict(getattr(mod, name)(m)) if hasattr(mod, name) else default


def missing_interface(mod: Any, names: Iterable[str] = EXPERIMENT_INTERFACE) -> list[str]:
    """The names of ``names`` that ``mod`` lacks."""
    return [n for n in names if not hasattr(mod, n)]


def register_module(mod: Any) -> Experiment:
    """Register the experiment package ``mod`` under its ``NAME``, run by :func:`run` (timed)."""
    missing = missing_interface(mod)
    if missing:
        raise ValidateError(f"experiment package {mod.__name__}: missing {', '.join(missing)} (see "
                            "validate.experiments.base.ExperimentModule)")
    register_experiment(mod.NAME, mod.TITLE, mod.DESCRIPTION, mod.ORDER)(functools.partial(run, mod))
    return EXPERIMENTS[mod.NAME]
