"""One ``run``/``all`` of the command line: the experiments in a staging folder (:func:`run_in`: the environments
checked first, then :func:`~validate.run.schedule.run_experiments`), results.json's ``meta``, then the commit
(:mod:`validate.run.output`) with signals held until it is done, and the claims printed."""

from __future__ import annotations

import argparse
import datetime as _dt
import functools
import signal
import sys
import time
from pathlib import Path

from ..errors import ValidateError
from ..gl import runtime
from . import interrupt
from .output import check_output_folder, commit, output_folder, previous_seconds
from .plugins import load_plugin, load_plugins


def run_report(args: argparse.Namespace, names: list[str] | None) -> int:
    from .. import backend
    from ..atomic import refuse_input_overwrite
    from ..experiments import discover
    from ..report.html import load_results
    from ..scenes.probes import default_probes_dir

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
        from ..report.compare import load

        baseline = load(args.baseline)[1]  # read now: it may be the results.json this run replaces
    check_output_folder(out)
    previous = load_results(out) if names is not None else {}
    with output_folder(out) as (staging, state):
        results, held = run_in(args, exps, todo, staging, out, previous, baseline, be, t0, state)
    failed = print_claims(results)
    not_run = [(n, x) for n in (todo if names is not None else list(results["experiments"]))
               for x in results["experiments"].get(n, {}).get("not_run") or []]
    if "changes" in results:
        from ..report.compare import Comparison, Row

        comparison = Comparison(str(args.baseline), [Row(**r) for r in results["changes"]["rows"]])
        print(f"\nchanges: {comparison.summary()}")
    print(f"\nwrote {out / 'index.html'} and {out / 'results.json'} in {time.perf_counter() - t0:.1f} s")
    if held:
        name = signal.Signals(held[0]).name
        print(f"validate: {name} arrived while the report was being written; it is complete", file=sys.stderr)
        return 128 + held[0]
    if failed:
        print(f"{failed} claim(s) failed" + ("" if args.strict else " (use --strict to exit non-zero)"))
    if not_run:  # nothing judged is not a pass: say what, once more at the end, and fail under --strict
        for n, x in not_run:
            fix = f" — `{x['fix']}`" if x.get("fix") else ""
            print(f"{n}: {x['what']} not run: {x['why']}{fix}")
        print(f"{len(not_run)} piece(s) not run" + ("" if args.strict else " (use --strict to exit non-zero)"))
    return 1 if (failed or not_run) and args.strict else 0


def run_in(args: argparse.Namespace, exps: dict, todo: list[str], staging: Path, out: Path, previous: dict,
            baseline: dict | None, be: object, t0: float, state: dict[str, bool]) -> tuple[dict, list[int]]:
    """The experiments, in the staging folder, then the commit: (results, signals held meanwhile)."""
    from ..experiments import Context, ExperimentResult
    from ..experiments.base import Background
    from ..scenes.probes import default_probes_dir
    from .schedule import run_experiments

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
            nothing = "; NOT everything judged" if res.not_run else ""
            print(f"  {n}: {res.wall_time_s:.1f} s, {sum(c.passed for c in res.claims)}/{len(res.claims)} "
                  f"claims pass{nothing}", flush=True)
            for miss in res.not_run:
                print(f"  {n}: {miss.line()}", flush=True)

        done = {n: res.to_json() for n, res in run_experiments(ctx, exps, todo, started, finished,
                                                                seconds=previous_seconds(out)).items()}
        experiments = dict(previous.get("experiments", {}))
        experiments.update(done)
        experiments = {k: experiments[k] for k in list(exps) + [k for k in experiments if k not in exps]
                       if k in experiments}
        results = {"meta": {"backend": be.describe(), "variant": be.variant, "versions": versions(),  # type: ignore[attr-defined]
                            "generated": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                            "command": "python -m validate " + " ".join(sys.argv[1:]), "quick": args.quick,
                            "wall_time_s": round(time.perf_counter() - t0, 2),
                            "skipped_inputs": [list(s) for s in skipped],
                            "environments": environments_meta(envs), "gl": gl_meta()},
                   "experiments": experiments}
        if baseline is not None:
            from ..report.compare import compare

            results["changes"] = {**compare(baseline, results).to_json(), "baseline": str(args.baseline)}
        # figures, then the pages and results.json: one transaction; signals wait until it is done
        with interrupt.deferred() as held:
            commit(out, staging, done, results)
            state["committed"] = True
    finally:
        if starting is not None:
            starting.join()  # a cluster still starting (an input was refused meanwhile) is closed below
        ctx.close()
        runtime.close_all()
    return results, held


def environments_meta(envs: list) -> dict[str, dict]:
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


def gl_meta() -> dict:
    """``meta.gl``: GL_RENDERER/GL_VERSION of each runtime started in this run, and why GLSL techniques
    of a runtime are not registered when they are not."""
    from ..local_models.glsl_technique import STATUS

    out: dict = {"runtimes": runtime.meta()}
    out["glsl_techniques"] = {k: ("registered" if not why else f"not registered: {why}") for k, why in STATUS.items()}
    return out


def versions() -> dict:
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    return {"mitsuba": mi.__version__, "drjit": dr.__version__, "numpy": np.__version__,
            "python": sys.version.split()[0]}


def print_claims(results: dict) -> int:
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
