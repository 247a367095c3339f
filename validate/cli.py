"""Command line: ``python -m validate {list, run NAME, all, bench}``.

Outputs go to ``--out`` (default ``reports/``): ``index.html``, ``results.json``, ``figures/``.
Work is staged in a temporary folder inside ``--out`` and moved into place only when every
experiment succeeded, so a failure leaves the previous report untouched. ``run NAME`` updates that
experiment's entry in an existing ``results.json`` and re-renders the page; other entries are kept.

Exit status: 0 success; 1 a claim failed and ``--strict`` was given; 2 bad input or a failed task
(one-line error, nothing written); 130 / 143 interrupted by SIGINT / SIGTERM (one line; the previous
report is untouched, and every reference finished before the signal is in the cache for the rerun).

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

from .errors import ValidateError


class Interrupted(BaseException):
    """Raised in the main thread by SIGINT or SIGTERM (a BaseException, like KeyboardInterrupt, so that
    no `except Exception` on the way swallows it)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


_DEFERRED: list[int] | None = None  # while the finished report is being moved into place


def _on_signal(signum: int, frame: object) -> None:
    if _DEFERRED is not None:
        _DEFERRED.append(signum)
        return
    raise Interrupted(signum)


def _install_signal_handlers() -> dict[int, object]:
    """SIGTERM behaves like SIGINT: unwind (the staging folder is removed), exit with one line.
    Returns the previous handlers (``main`` restores them: it may be called as a library function)."""
    import threading

    previous: dict[int, object] = {}
    if threading.current_thread() is threading.main_thread():
        for sig in (signal.SIGINT, signal.SIGTERM):
            previous[sig] = signal.signal(sig, _on_signal)
    return previous


@contextlib.contextmanager
def _signals_deferred() -> Iterator[list[int]]:
    """Hold SIGINT/SIGTERM while the finished outputs are renamed into place, so that the report is
    either the previous one or the new one, never a mix."""
    global _DEFERRED
    _DEFERRED = []
    try:
        yield _DEFERRED
    finally:
        _DEFERRED = None

EPILOG = """examples:
  python -m validate list
  python -m validate all --probes ../shared/probes     # full report in reports/index.html
  python -m validate all --quick                       # coarse settings, the paper's probes only
  python -m validate all --quick --workers 2           # the same on a local Dask cluster
  python -m validate run sh9 --probe my_probe.exr      # one experiment, one extra probe
  python -m validate all --plugin my_technique.py      # your technique in every experiment of its family
  python -m validate list --plugin my_technique.py     # families, their contracts, registered techniques
  python -m validate bench                             # speed and memory, side by side -> bench.json
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
                        help="clamp negative texels to 0 instead of rejecting the file")
    common.add_argument("--quick", action="store_true",
                        help="coarser settings: fewer environments, smaller images, fewer samples")
    common.add_argument("--strict", action="store_true", help="exit with status 1 when any claim fails")
    common.add_argument("--plugin", action="append", default=[], metavar="FILE|MODULE",
                        help="import a Python file or module that registers techniques (repeatable)")
    common.add_argument("--no-progress", action="store_true", help="no progress bars")
    common.add_argument("--workers", type=_positive_int, default=1, metavar="N",
                        help="run per-environment tasks on a local Dask cluster of N processes (default 1: "
                             "in-process)")
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
    r = sub.add_parser("run", parents=[common], help="run one experiment and update the report")
    r.add_argument("name", help="experiment name (see `list`)")
    sub.add_parser("all", parents=[common], help="run every experiment and write the report")
    from .experiments.worstcase.command import add_parser as add_worst_parser

    add_worst_parser(sub)
    b = sub.add_parser("bench", help="benchmarks: drjit local models vs numpy, reference cost")
    b.add_argument("--out", type=Path, default=Path("reports"), metavar="DIR")
    b.add_argument("--sizes", default="1024,2048,4096,8192", metavar="H,H,...",
                   help="map heights (rows; width 2H) measured in child processes (default: 1k to 8k)")
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
        for t in fam:
            tag = "" if t.builtin else " [plug-in]"
            thr = "; thresholds " + ", ".join(f"{k} < {v:g}" for k, v in t.thresholds.items()) if t.thresholds else ""
            print(f"  {t.name:24s} {t.description}{tag}{thr}")
    return 0


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


def _run(args: argparse.Namespace, names: list[str] | None) -> int:
    from . import backend
    from .atomic import refuse_input_overwrite
    from .experiments import Context, discover
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
    previous = load_results(out) if names is not None else {}

    out.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".staging-", dir=out))
    ctx = Context(out_dir=staging, quick=args.quick, probes_dir=probes_dir, probe_files=list(args.probe),
                  layout=args.layout, clamp_negative=args.clamp_negative,
                  show_progress=not args.no_progress and sys.stderr.isatty(),
                  workers=args.workers, scheduler=args.scheduler,
                  worker_setup=functools.partial(load_plugins, tuple(args.plugin)) if args.plugin else None)
    try:
        envs, skipped = ctx.environments()  # validate every input before any work
        print(f"environments: {len(envs)} ({len(skipped)} skipped)")
        if ctx.distributed:
            client = ctx.client()
            where = args.scheduler or f"local Dask cluster, {args.workers} processes"
            print(f"workers: {len(client.scheduler_info()['workers'])} ({where})", flush=True)
        done = {}
        for n in todo:
            print(f"running {n} ...", flush=True)
            res = exps[n].run(ctx)
            done[n] = res.to_json()
            print(f"  {n}: {res.wall_time_s:.1f} s, {sum(c.passed for c in res.claims)}/{len(res.claims)} "
                  "claims pass")
        experiments = dict(previous.get("experiments", {}))
        experiments.update(done)
        experiments = {k: experiments[k] for k in list(exps) + [k for k in experiments if k not in exps]
                       if k in experiments}
        results = {"meta": {"backend": be.describe(), "variant": be.variant, "versions": _versions(),
                            "generated": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                            "command": "python -m validate " + " ".join(sys.argv[1:]), "quick": args.quick,
                            "wall_time_s": round(time.perf_counter() - t0, 2),
                            "skipped_inputs": [list(s) for s in skipped]},
                   "experiments": experiments}
        # move figures into place, then the JSON and the page (each atomically); signals wait
        with _signals_deferred() as held:
            page = _commit(out, staging, done, results)
    finally:
        ctx.close()
        shutil.rmtree(staging, ignore_errors=True)
    failed = _print_claims(results)
    print(f"\nwrote {page} and {out / 'results.json'} in {time.perf_counter() - t0:.1f} s")
    if held:
        name = signal.Signals(held[0]).name
        print(f"validate: {name} arrived while the report was being written; it is complete", file=sys.stderr)
        return 128 + held[0]
    if failed:
        print(f"{failed} claim(s) failed" + ("" if args.strict else " (use --strict to exit non-zero)"))
    return 1 if failed and args.strict else 0


def _commit(out: Path, staging: Path, done: dict, results: dict) -> Path:
    """Rename each experiment's figures into ``out``, then write results.json and the page."""
    from .report.html import write_report, write_results_json

    for n in done:
        src, dst = staging / "figures" / n, out / "figures" / n
        if src.exists():
            old = None
            if dst.exists():
                old = dst.with_name(f".old-{n}-{os.getpid()}")
                dst.rename(old)
            dst.parent.mkdir(parents=True, exist_ok=True)
            src.rename(dst)
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
    write_results_json(out, results)
    return write_report(out, results)


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    previous_handlers = _install_signal_handlers()
    try:
        if args.command is None:
            parser.print_help()
            return 0
        if args.command == "list":
            return _cmd_list(args.plugin)
        if args.command == "run":
            return _run(args, [args.name])
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
            return run_bench(args.out, sizes)
    except ValidateError as exc:
        print(f"validate: error: {exc}", file=sys.stderr)
        return 2
    except Interrupted as exc:
        print(f"validate: interrupted by {exc}; the previous report is untouched (finished references are "
              "cached: rerun to resume)", file=sys.stderr)
        return 128 + exc.signum
    except KeyboardInterrupt:  # SIGINT before the handlers were installed
        print("validate: interrupted; the previous report is untouched", file=sys.stderr)
        return 130
    finally:
        for sig, handler in previous_handlers.items():
            signal.signal(sig, handler)  # type: ignore[arg-type]
    return 0
