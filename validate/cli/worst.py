"""``python -m validate worst TECHNIQUE``: the worst-case search for one technique, its probe and its figure."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import ValidateError
from ..experiments.worstcase.errors import METRICS
from ..experiments.worstcase.lighting import write_probe
from ..experiments.worstcase.search import SearchSettings, search


def add_parser(sub: argparse._SubParsersAction) -> None:
    w = sub.add_parser("worst", help="search the worst lighting for one irradiance technique; write it as a probe")
    w.add_argument("technique", help="an irradiance technique (see `list`)")
    w.add_argument("--budget", type=int, default=SearchSettings.budget, metavar="N",
                   help=f"evaluations in all (default {SearchSettings.budget})")
    w.add_argument("--restarts", type=int, default=SearchSettings.restarts, metavar="R",
                   help=f"random starts (default {SearchSettings.restarts})")
    w.add_argument("--seed", type=int, default=SearchSettings.seed, metavar="S")
    w.add_argument("--height", type=int, default=SearchSettings.height, metavar="H",
                   help=f"rows of the searched lat-long maps (default {SearchSettings.height}; ≥ 16: a loadable probe)")
    w.add_argument("--metric", default="flux_luminance.max", choices=[m for m in METRICS if m.endswith(".max")])
    w.add_argument("--out", type=Path, default=Path("reports"), metavar="DIR", help="where the probe goes")
    w.add_argument("--plugin", action="append", default=[], metavar="FILE|MODULE",
                   help="import a plug-in first (repeatable)")


def run_worst(args: argparse.Namespace) -> int:
    from .. import backend
    from ..local_models import irradiance

    if args.budget < 1 or args.restarts < 1 or args.height < 16:
        raise ValidateError(f"worst {args.technique}: --budget and --restarts must be ≥ 1 and --height ≥ 16 "
                            f"(got {args.budget}, {args.restarts}, {args.height})")
    be = backend.init()
    print(f"backend: {be.describe()}")
    tech = irradiance[args.technique]
    s = SearchSettings(height=args.height, budget=args.budget, restarts=args.restarts, seed=args.seed)
    r = search(tech.name, s, args.metric)
    path = args.out / f"worst_{tech.name}_{args.metric.replace('.', '_')}.exr"
    write_probe(path, r.radiance)
    pct = lambda x: f"{100 * x:.4g} %"  # noqa: E731
    print(f"{tech.name}: {r.method}, {r.evaluations} evaluations, {r.wall_s:.1f} s")
    print(f"worst {args.metric} = {pct(r.value)} ± {pct(r.uncertainty)} (± = |e(2H) − e(H)|, the truth's quadrature "
          f"at H = {s.height} and {2 * s.height}; e(2H) = {pct(r.value_2x)})")
    print(f"restarts: {', '.join(pct(v) for v in r.restart_values)} (spread "
          f"{pct(max(r.restart_values) - min(r.restart_values))}); random search, same budget: {pct(r.random_value)}")
    print(f"worst lighting: {r.lighting}")
    for metric, limit in tech.thresholds.items():
        env = tech.meta.get("environments")
        where = f" (declared for {', '.join(env)} only)" if env else ""
        if r.value + r.uncertainty < limit:
            verdict = "holds"
        elif r.value - r.uncertainty >= limit:
            verdict = "exceeded" if env else "BROKEN"
        else:
            verdict = "not shown to hold (the limit is within the uncertainty)"
        print(f"declared {metric} < {pct(limit)}{where}: {verdict} on the worst lighting found")
    print(f"wrote {path} (load it with --probe {path})")
    return 0
