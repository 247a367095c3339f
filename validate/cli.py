"""Command line: ``python -m validate {list, run NAME [NAME ...], all, compare OLD NEW, bench, docs}``.

Outputs go to ``--out`` (default ``reports/``): ``index.html``, ``results.json``, ``figures/``.
Work is staged in a temporary folder inside ``--out``; when every experiment succeeded, the new
results.json and pages are written there too, and only then is everything renamed into place as one
:class:`~validate.atomic.Transaction` (rolled back if any step fails). So a failure — bad input, a
failed task, a full disk at any point, a signal — leaves the previous report byte for byte, and a
fresh ``--out`` folder is removed again. ``run NAME ...`` updates those experiments' entries in an existing
``results.json`` and re-renders the page; other entries are kept.

``--baseline OLD.json`` (``all``/``run``) compares the new results with an earlier run
(:mod:`validate.compare`) and stores the rows as the top-level ``changes`` entry of results.json;
``compare OLD NEW`` prints the same comparison.

Exit status: 0 success; 1 a claim failed and ``--strict`` was given (``compare --strict``: a
regression); 2 bad input, a failed task or an output that cannot be written (one line
``validate: error: <path>: <problem>``, nothing written); 130 / 143 interrupted by SIGINT / SIGTERM
(one line within seconds in every phase, :mod:`validate.interrupt`; the previous report is
untouched, and every reference finished before the signal is in the cache for the rerun).

Scale-out: ``--workers N`` (N > 1) runs the per-environment tasks of every experiment on an embedded
``dask.distributed.LocalCluster`` of N processes; ``--scheduler ADDRESS`` on an existing Dask cluster
(its workers must see ``--out`` and the probes on a shared file system). ``--workers 1`` (default)
runs in-process. The numbers are the same in every mode.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as _dt
import functools
import importlib
import importlib.util
import os
import shutil
import signal
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

from . import interrupt
from .atomic import OutputError, output_error
from .errors import ValidateError
from .experiments.worstcase.command import add_parser as add_worst_parser
from .gl import runtime
from .interrupt import Interrupted  # re-exported: callers catch it here
from .report.docs import update_docs

EPILOG = """examples:
  python -m validate list
  python -m validate all --probes ../shared/probes     # full report in reports/index.html
  python -m validate all --quick                       # coarse settings, the paper's probes only
  python -m validate all --quick --workers 2           # the same on a local Dask cluster
  python -m validate run sh9 --probe my_probe.exr      # one experiment, one extra probe
  python -m validate all --plugin my_technique.py      # your technique in every experiment of its family
  python -m validate list --plugin my_technique.py     # families, their contracts, registered techniques
  python -m validate run brdfs --plugin my_brdf.glsl   # a GLSL technique (see docs/glsl.md)
  python -m validate bench                             # speed and memory, side by side -> bench.json
  python -m validate bench --only fits                 # the fits only: scipy vs drjit AD
  python -m validate bench --only render               # the engines: browser start, page load, frame times
  python -m validate all --quick --baseline old/results.json   # ... and what changed since then
  python -m validate compare old/results.json reports/results.json --strict   # CI: exit 1 on a regression
  python -m validate docs --results reports/results.json   # docs/ figures from that run (--check: exit 1 if stale)
  python -m validate worst sh9 --budget 400            # worst lighting found for sh9 -> reports/worst_sh9_*.exr

environment variables:
  VALIDATE_PROBES   default for --probes
  VALIDATE_VARIANT  force a Mitsuba variant (cuda_ad_rgb, llvm_ad_rgb, scalar_rgb)
  VALIDATE_CACHE    reference cache folder (default ~/.cache/validate; 'off' disables)
  VALIDATE_REFERENCE  folder of published tables (default: the package's own copy, validate/data)
  VALIDATE_NODE     the Node.js used by the engines experiment (a missing path turns the engines off)
"""


def _parser() -> argparse.ArgumentParser:
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--out", type=Path, default=Path("reports"), metavar="DIR",
                        help="output folder for index.html, results.json, figures/ (default: reports)")
    common.add_argument("--probes", type=Path, default=None, metavar="DIR",
                        help="add every .exr/.hdr/.pfm light probe in DIR (default: $VALIDATE_PROBES)")
    common.add_argument("--probe", type=Path, action="append", default=[], metavar="FILE",
                        help="add one probe file (repeatable); a bad file is an error")
    common.add_argument("--layout", choices=["auto", "latlong", "angular", "cross"], default="auto",
                        help="layout of --probe files (default: detect from aspect 2:1, 1:1, 3:4)")
    common.add_argument("--clamp-negative", action="store_true",
                        help="clamp every negative texel to 0 (without it only float noise is clamped: "
                             "|min| <= 0.05 x mean luminance on <= 0.5 %% of the texels; larger negatives "
                             "reject the file)")
    common.add_argument("--quick", action="store_true",
                        help="coarser settings: fewer environments, smaller images, fewer samples")
    common.add_argument("--strict", action="store_true", help="exit with status 1 when any claim fails")
    common.add_argument("--baseline", type=Path, default=None, metavar="OLD.json",
                        help="compare with an earlier results.json (or its folder): a 'changes' entry in "
                             "results.json and a summary line (see `compare`)")
    common.add_argument("--plugin", action="append", default=[], metavar="FILE|MODULE",
                        help="a Python file or module that registers techniques, or a .glsl technique file "
                             "(repeatable)")
    common.add_argument("--no-progress", action="store_true", help="no progress bars")
    common.add_argument("--workers", type=_positive_int, default=1, metavar="N",
                        help="run per-environment tasks on a local Dask cluster of N processes (default 1: "
                             "in-process); with N > 1 experiments run in two lanes, this process and a child")
    common.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="run the tasks on an existing Dask cluster (e.g. tcp://host:8786)")

    p = argparse.ArgumentParser(prog="python -m validate", epilog=EPILOG,
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                description="Measure real-time lighting approximations against Mitsuba 3 "
                                            "ground truth and write an HTML report.")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    lp = sub.add_parser("list", help="list experiments, built-in environments and every technique family")
    lp.add_argument("--plugin", action="append", default=[], metavar="FILE|MODULE",
                    help="import a plug-in first so that its techniques are listed (repeatable)")
    r = sub.add_parser("run", parents=[common], help="run some experiments and update the report in place")
    r.add_argument("name", nargs="+", help="experiment name(s) (see `list`), run in the order given")
    sub.add_parser("all", parents=[common], help="run every experiment and write the report")
    c = sub.add_parser("compare", help="what changed between two runs (claims, technique metrics, judgements)",
                       description="For every claim, technique metric and judgement in either results.json: the "
                                   "change and whether it exceeds the combined uncertainty sqrt(s_old^2 + s_new^2) "
                                   "(a value without one counts as 0). Prints a note per file written before the "
                                   "measured-value schema, the changed rows, the counts per experiment, then a "
                                   "summary line.")
    c.add_argument("old", type=Path, metavar="OLD.json", help="the earlier results.json (or its folder)")
    c.add_argument("new", type=Path, metavar="NEW.json", help="the later results.json (or its folder)")
    c.add_argument("--strict", action="store_true",
                   help="exit with status 1 on a regression: a claim that passed and now fails, or a technique "
                        "metric or judgement worse beyond its uncertainty (errors: larger is worse unless the value "
                        "says otherwise)")
    add_worst_parser(sub)
    b = sub.add_parser("bench", help="benchmarks: drjit local models vs numpy, reference cost")
    b.add_argument("--out", type=Path, default=Path("reports"), metavar="DIR")
    b.add_argument("--sizes", default="1024,2048,4096,8192", metavar="H,H,...",
                   help="map heights (rows; width 2H) measured in child processes (default: 1k to 8k)")
    b.add_argument("--only", default=None, metavar="SECTION,...",
                   help="run only these sections of kernels, gl, sizes, fits, render (default: all)")
    d = sub.add_parser("docs", help="rewrite the measured-figure blocks of docs/ from a results.json")
    d.add_argument("--results", type=Path, default=Path("reports") / "results.json", metavar="FILE",
                   help="results to render (default: reports/results.json)")
    d.add_argument("--docs", type=Path, default=Path("docs"), metavar="DIR", help="docs folder (default: docs)")
    d.add_argument("--check", action="store_true",
                   help="write nothing; exit 1 naming each file whose blocks differ from the results")
    return p


def _positive_int(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a positive integer")
    return n


def load_plugins(specs: tuple[str, ...]) -> None:
    """Import every plug-in (the setup each Dask worker runs once, see ``Context.worker_setup``)."""
    for spec in specs:
        load_plugin(spec)


def load_plugin(spec: str) -> None:
    path = Path(spec)
    if path.suffix == ".glsl":
        if not path.is_file():
            raise ValidateError(f"{spec}: plugin file not found")
        from .local_models.glsl_technique import load_glsl

        load_glsl(spec)  # compile/link errors: "<file>:<line>: <driver message>"
        return
    try:
        if path.suffix == ".py":
            if not path.is_file():
                raise ValidateError(f"{spec}: plugin file not found")
            mod_spec = importlib.util.spec_from_file_location(f"validate_plugin_{path.stem}", path)
            assert mod_spec and mod_spec.loader
            module = importlib.util.module_from_spec(mod_spec)
            mod_spec.loader.exec_module(module)
        else:
            importlib.import_module(spec)
    except ValidateError:
        raise
    except Exception as exc:
        raise ValidateError(f"{spec}: plugin failed to load ({type(exc).__name__}: {exc})") from None


def _cmd_list(plugins: list[str]) -> int:
    from .experiments import discover
    from .local_models import FAMILIES
    from .scenes.procedural import BUILTIN_NAMES

    exps = discover()
    for spec in plugins:
        load_plugin(spec)
    print("experiments:")
    for name, e in exps.items():
        print(f"  {name:12s} {e.title}")
    print("built-in environments:")
    for name in BUILTIN_NAMES:
        print(f"  {name}")
    for fam in FAMILIES.values():
        print(f"technique family {fam.name}: {fam.contract}")
        print(f"  computes in {fam.precision} (validate/local_models/precision.py): {fam.precision_reason}")
        if fam.glsl_contract:
            print(f"  GLSL entry point (docs/glsl.md): {fam.glsl_contract}")
        for t in fam:
            tag = _glsl_tag(t) + ("" if t.builtin else " [plug-in]")
            thr = "; thresholds " + ", ".join(f"{k} < {v:g}" for k, v in t.thresholds.items()) if t.thresholds else ""
            print(f"  {t.name:24s} {t.description}{tag}{thr}")
    from .local_models.glsl_technique import STATUS

    for kind, why in STATUS.items():
        print(f"GLSL techniques ({kind}): " + (f"not registered: {why}" if why else "registered"))
    return 0


def _cmd_docs(results: Path, docs: Path, check: bool) -> int:
    """``docs``: render the generated blocks of ``docs/*.md`` (see :mod:`validate.report.docs`)."""
    changed = update_docs(results, docs, check=check)
    for path in changed:
        print(f"{'stale' if check else 'updated'}: {path}")
    if check and changed:
        print(f"validate: {len(changed)} file(s) in {docs} differ from {results}; "
              f"run `python -m validate docs --results {results}`", file=sys.stderr)
        return 1
    print(f"{docs}: {'up to date with' if not changed else 'rendered from'} {results}")
    return 0


def _glsl_tag(t: object) -> str:
    """`` [GLSL llvmpipe; seed …]`` for a GLSL technique, else empty."""
    meta = getattr(t, "meta", {})
    if "glsl" not in meta:
        return ""
    seed = f"; seed {meta['seed']}" if meta.get("seed") else ""
    return f" [GLSL {meta.get('runtime', 'llvmpipe')}{seed}]"


def _gl_meta() -> dict:
    """``meta.gl``: GL_RENDERER/GL_VERSION of each runtime started in this run, and why GLSL techniques
    of a runtime are not registered when they are not."""
    from .local_models.glsl_technique import STATUS

    out: dict = {"runtimes": runtime.meta()}
    out["glsl_techniques"] = {k: ("registered" if not why else f"not registered: {why}") for k, why in STATUS.items()}
    return out


def _versions() -> dict:
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    return {"mitsuba": mi.__version__, "drjit": dr.__version__, "numpy": np.__version__,
            "python": sys.version.split()[0]}


def _print_claims(results: dict) -> int:
    failed = 0
    print()
    print(f"{'claim':44s} {'measured ± unc':>26s} {'threshold':>12s}  result")
    for exp in results["experiments"].values():
        for c in exp.get("claims", []):
            pct = c.get("unit") == "%"
            f = (lambda v, d=3: f"{100 * v:.{d}g} %") if pct else (lambda v, d=4: f"{v:.{d}g}")
            ok = "pass" if c["passed"] else "FAIL"
            failed += not c["passed"]
            print(f"{c['id'][:44]:44s} {f(c['measured']) + ' ± ' + f(c['uncertainty']):>26s} "
                  f"{c['comparison'] + ' ' + f(c['threshold'], 4):>12s}  {ok}")
    return failed


def _cmd_compare(old: Path, new: Path, strict: bool) -> int:
    from .compare import compare

    comparison = compare(old, new)
    for note in comparison.notes:
        print(note)
    table = comparison.table()
    if table:
        print(table)
    print(comparison.per_experiment())
    print(comparison.summary())
    return 1 if strict and comparison.regressions else 0


def _first_missing(path: Path) -> Path | None:
    """The topmost folder of ``path`` that does not exist yet (what a failed run must remove again)."""
    missing = None
    for p in [path, *path.parents]:
        if os.path.lexists(p):
            break
        missing = p
    return missing


def _check_output_folder(out: Path) -> None:
    """Refuse at once an ``--out`` that is, or lies under, something other than a folder."""
    for p in [out, *out.parents]:
        if os.path.lexists(p):
            if not p.is_dir():
                where = "" if p == out else f" ({p})"
                raise OutputError(f"{out}: cannot create the output folder: a file is in the way{where}")
            return


@contextlib.contextmanager
def _output_folder(out: Path) -> Iterator[tuple[Path, dict[str, bool]]]:
    """Create ``out`` and a staging folder in it; yield (staging, state). On the way out the staging
    folder is removed, and on failure a freshly created ``out`` too (unless ``state["committed"]``).
    OSErrors become one-line :class:`OutputError`; paths inside the staging folder are named as the
    outputs they were going to be."""
    _check_output_folder(out)
    fresh = _first_missing(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=".staging-", dir=out))
    except OSError as exc:
        if fresh is not None:
            shutil.rmtree(fresh, ignore_errors=True)
        raise output_error(out, exc, "cannot create the output folder") from None
    state = {"committed": False}

    def clean() -> None:
        shutil.rmtree(staging, ignore_errors=True)
        if fresh is not None and not state["committed"]:
            shutil.rmtree(fresh, ignore_errors=True)

    try:
        with interrupt.cleanup(clean):
            yield staging, state
    except OSError as exc:
        where = exc.filename if exc.filename is not None else out
        raise OutputError(str(output_error(where, exc)).replace(str(staging), str(out))) from None
    except ValidateError as exc:
        raise type(exc)(str(exc).replace(str(staging), str(out))) from None
    finally:
        if state["committed"]:
            shutil.rmtree(staging, ignore_errors=True)
        else:
            clean()


def _environments_meta(envs: list) -> dict[str, dict]:
    """``meta.environments``: every probe's source, layout, loader notes and negative-texel clamp."""
    out: dict[str, dict] = {}
    for e in envs:
        if getattr(e, "kind", "") != "probe":
            continue
        entry: dict = {"source": e.source.name if e.source else None, "layout": e.layout, "notes": list(e.notes)}
        if e.clamped_negative is not None:
            entry["clamped_negative"] = {"texels": int(e.clamped_negative[0]), "min": float(e.clamped_negative[1])}
        out[e.name] = entry
    return out


def _run(args: argparse.Namespace, names: list[str] | None) -> int:
    from . import backend
    from .atomic import refuse_input_overwrite
    from .experiments import discover
    from .report.html import load_results
    from .scenes.probes import default_probes_dir

    t0 = time.perf_counter()
    be = backend.init()
    print(f"backend: {be.describe()}")
    for spec in args.plugin:
        load_plugin(spec)
    exps = discover()
    todo = list(exps) if names is None else names
    for n in todo:
        if n not in exps:
            raise ValidateError(f"unknown experiment {n!r}; available: {', '.join(exps)}")
    probes_dir = args.probes or default_probes_dir()
    out: Path = args.out
    inputs = list(args.probe) + ([probes_dir] if probes_dir else [])
    refuse_input_overwrite(out, inputs)
    baseline = None
    if args.baseline is not None:
        from .compare import load

        baseline = load(args.baseline)[1]  # read now: it may be the results.json this run replaces
    _check_output_folder(out)
    previous = load_results(out) if names is not None else {}
    with _output_folder(out) as (staging, state):
        results, held = _run_in(args, exps, todo, staging, out, previous, baseline, be, t0, state)
    failed = _print_claims(results)
    if "changes" in results:
        from .compare import Comparison, Row

        comparison = Comparison(str(args.baseline), [Row(**r) for r in results["changes"]["rows"]])
        print(f"\nchanges: {comparison.summary()}")
    print(f"\nwrote {out / 'index.html'} and {out / 'results.json'} in {time.perf_counter() - t0:.1f} s")
    if held:
        name = signal.Signals(held[0]).name
        print(f"validate: {name} arrived while the report was being written; it is complete", file=sys.stderr)
        return 128 + held[0]
    if failed:
        print(f"{failed} claim(s) failed" + ("" if args.strict else " (use --strict to exit non-zero)"))
    return 1 if failed and args.strict else 0


def _run_in(args: argparse.Namespace, exps: dict, todo: list[str], staging: Path, out: Path, previous: dict,
            baseline: dict | None, be: object, t0: float, state: dict[str, bool]) -> tuple[dict, list[int]]:
    """The experiments, in the staging folder, then the commit: (results, signals held meanwhile)."""
    from .experiments import Context, ExperimentResult
    from .experiments.base import Background
    from .experiments.schedule import run_experiments
    from .scenes.probes import default_probes_dir

    ctx = Context(out_dir=staging, quick=args.quick, probes_dir=args.probes or default_probes_dir(),
                  probe_files=list(args.probe),
                  layout=args.layout, clamp_negative=args.clamp_negative,
                  show_progress=not args.no_progress and sys.stderr.isatty(),
                  workers=args.workers, scheduler=args.scheduler,
                  worker_setup=functools.partial(load_plugins, tuple(args.plugin)) if args.plugin else None)
    # the Dask workers start (their interpreters import on the other core) while this process reads and checks the
    # environments; no task is sent before every input is validated
    starting = Background(ctx.client, "validate-dask-start") if ctx.distributed else None
    try:
        envs, skipped = ctx.environments()  # validate every input before any work
        print(f"environments: {len(envs)} ({len(skipped)} skipped)")
        for e in envs:
            if e.clamped_negative is not None:
                print(f"  {e.name}: {e.notes[0]}")
        if starting is not None:
            client = starting.result()
            where = args.scheduler or f"local Dask cluster, {args.workers} processes"
            print(f"workers: {len(client.scheduler_info()['workers'])} ({where})", flush=True)
        def started(n: str, second_lane: bool) -> None:
            print(f"running {n} ..." + (" (second lane)" if second_lane else ""), flush=True)

        def finished(n: str, res: ExperimentResult) -> None:
            print(f"  {n}: {res.wall_time_s:.1f} s, {sum(c.passed for c in res.claims)}/{len(res.claims)} "
                  "claims pass", flush=True)

        done = {n: res.to_json() for n, res in run_experiments(ctx, exps, todo, started, finished,
                                                                seconds=_previous_seconds(out)).items()}
        experiments = dict(previous.get("experiments", {}))
        experiments.update(done)
        experiments = {k: experiments[k] for k in list(exps) + [k for k in experiments if k not in exps]
                       if k in experiments}
        results = {"meta": {"backend": be.describe(), "variant": be.variant, "versions": _versions(),  # type: ignore[attr-defined]
                            "generated": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                            "command": "python -m validate " + " ".join(sys.argv[1:]), "quick": args.quick,
                            "wall_time_s": round(time.perf_counter() - t0, 2),
                            "skipped_inputs": [list(s) for s in skipped],
                            "environments": _environments_meta(envs), "gl": _gl_meta()},
                   "experiments": experiments}
        if baseline is not None:
            from .compare import compare

            results["changes"] = {**compare(baseline, results).to_json(), "baseline": str(args.baseline)}
        # figures, then the pages and results.json: one transaction; signals wait until it is done
        with interrupt.deferred() as held:
            _commit(out, staging, done, results)
            state["committed"] = True
    finally:
        if starting is not None:
            starting.join()  # a cluster still starting (an input was refused meanwhile) is closed below
        ctx.close()
        runtime.close_all()
    return results, held


def _previous_seconds(out: Path) -> dict[str, float]:
    """Each experiment's wall time in the report already in ``out`` (none when there is none or it cannot be read:
    it only orders the two lanes' work, :func:`~validate.experiments.schedule.longest_first`)."""
    from .report.html import load_results

    try:
        exps = load_results(out).get("experiments", {})
    except ValidateError:
        return {}
    if not isinstance(exps, dict):
        return {}
    return {n: float(e["wall_time_s"]) for n, e in exps.items()
            if isinstance(e, dict) and isinstance(e.get("wall_time_s"), (int, float))}


def _commit(out: Path, staging: Path, done: dict, results: dict) -> Path:
    """Move each experiment's figures into ``out``, draw the summary figures and write results.json and
    every page into the staging folder, then rename them into place: one
    :class:`~validate.atomic.Transaction`, so a full disk or any other failure leaves the previous
    report exactly as it was."""
    from .atomic import Transaction, write_text
    from .report import html

    new = staging / "commit"
    with Transaction(staging / "replaced") as tx:
        summaries = _stage_summaries(out, staging, results)
        for n in done:
            src = staging / "figures" / n
            if src.exists():
                tx.move(src, out / "figures" / n)
        if summaries is not None:
            tx.move(summaries, out / html.SUMMARY_DIR)
        pages = html.render_pages(out, results)  # figure paths are checked against their final place
        html.write_results_json(new, results)
        for name, text in pages.items():
            write_text(new / name, text)
        for name in pages:
            if name != html.REPORT_FILE:
                tx.move(new / name, out / name)
        for stale in sorted(out.glob("exp-*.html")):
            if stale.name not in pages:
                tx.remove(stale)
        tx.move(new / html.RESULTS_FILE, out / html.RESULTS_FILE)
        tx.move(new / html.REPORT_FILE, out / html.REPORT_FILE)
    return out / html.REPORT_FILE


def _stage_summaries(out: Path, staging: Path, results: dict) -> Path | None:
    """The report's summary figures (``report.html.draw_summaries``) drawn in the staging folder: the
    current ones are hard-linked in first (no copy, no disk space), so only changed figures are drawn.
    Returns the staged folder (None where this version of the report draws none)."""
    from .report import html

    draw = getattr(html, "draw_summaries", None)
    if draw is None:
        return None
    staged, current = staging / html.SUMMARY_DIR, out / html.SUMMARY_DIR
    try:
        staged.mkdir(parents=True, exist_ok=True)
        for f in current.glob("*.png") if current.is_dir() else ():
            try:
                os.link(f, staged / f.name)
            except OSError:
                shutil.copy2(f, staged / f.name)  # another file system or no hard links: a copy
    except OSError as exc:
        raise output_error(getattr(exc, "filename", None) or staged, exc) from None
    draw(staging, results)
    return staged


def _failure(exc: BaseException) -> int:
    """The one line and exit status for what ended a command. Once a signal arrived, whatever it
    raised on its way out counts as the interruption: a native extension (Mitsuba's initialisation,
    a drjit callback) may wrap the signal's exception in its own (ImportError, RuntimeError)."""
    signum = interrupt.interrupted()
    if isinstance(exc, Interrupted) or signum is not None:
        signum = exc.signum if isinstance(exc, Interrupted) else signum
        assert signum is not None
        interrupt.announce(signum)
        return 128 + signum
    if isinstance(exc, KeyboardInterrupt):  # SIGINT before the handlers were installed
        print("validate: interrupted; the previous report is untouched", file=sys.stderr)
        return 130
    if isinstance(exc, ValidateError):
        print(f"validate: error: {exc}", file=sys.stderr)
        return 2
    if isinstance(exc, OSError):  # an output fault outside the run's folder (e.g. bench.json): still one line
        print(f"validate: error: {output_error(exc.filename or '(output)', exc)}", file=sys.stderr)
        return 2
    raise exc


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    undo = interrupt.install()
    try:
        if args.command is None:
            parser.print_help()
            return 0
        if args.command == "list":
            return _cmd_list(args.plugin)
        if args.command == "compare":
            return _cmd_compare(args.old, args.new, args.strict)
        if args.command == "run":
            return _run(args, list(dict.fromkeys(args.name)))
        if args.command == "all":
            return _run(args, None)
        if args.command == "worst":
            from .experiments.worstcase.command import run_worst

            for spec in args.plugin:
                load_plugin(spec)
            return run_worst(args)
        if args.command == "bench":
            from .bench import run_bench

            try:
                sizes = tuple(int(v) for v in args.sizes.split(",") if v.strip())
            except ValueError:
                raise ValidateError(f"--sizes {args.sizes}: expected heights like 1024,2048") from None
            from .bench import SECTIONS

            only = tuple(v.strip() for v in (args.only or ",".join(SECTIONS)).split(",") if v.strip())
            bad = [v for v in only if v not in SECTIONS]
            if bad or not only:
                raise ValidateError(f"--only {args.only}: unknown section {', '.join(bad) or '(none)'}; "
                                    f"expected some of {', '.join(SECTIONS)}")
            return run_bench(args.out, sizes, only)
        if args.command == "docs":
            return _cmd_docs(args.results, args.docs, args.check)
    except (Exception, Interrupted, KeyboardInterrupt) as exc:
        return _failure(exc)
    finally:
        undo()
    return 0
