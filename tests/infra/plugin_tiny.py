"""A tiny experiment for the output-fault and signal tests (loaded with ``--plugin``), no reference.

``tiny_io`` writes ``TINY_FIGURES`` (default 3) incompressible 96×96 PNG figures (≈ 28 KB each),
one claim with its power check, and one technique metric. ``TINY_PHASE`` makes it block in one
place, after touching ``$TINY_MARK/<phase>`` (so a test can signal it there):

* ``python``: a pure-Python loop (60 s);
* ``render``: one long Mitsuba render in native code (a 256² path-traced sphere, 2¹⁶ spp);
* ``pipe``: a blocking read from a child process that ignores SIGINT and SIGTERM (how the Node
  workers are read), the child's pid in ``$TINY_MARK/child.pid``;
* ``subprocess``: ``subprocess.run`` of such a child.

``TINY_NOT_RUN=1`` reports a piece it could not run (``ExperimentResult.not_run``).
``TINY_ONLY_CONSTANT=1`` replaces the built-in environments by one small constant map (building
them all costs seconds a signal test does not need).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from validate.experiments.base import Claim, Context, ExperimentResult, Figure, NotRun, Section, register_experiment

NAME = "tiny_io"
STUBBORN_CHILD = ("import signal, sys, time; signal.signal(signal.SIGINT, signal.SIG_IGN); "
                  "signal.signal(signal.SIGTERM, signal.SIG_IGN); print('ready', flush=True); time.sleep(120)")


if os.environ.get("TINY_ONLY_CONSTANT"):
    from validate.scenes import procedural

    procedural.builtin_environments = lambda quick=False: [procedural.constant(16)]


def _mark(phase: str) -> None:
    mark = os.environ.get("TINY_MARK")
    if mark:
        Path(mark, phase).write_text(str(time.time()))


def _block(phase: str) -> None:
    if phase == "python":
        _mark(phase)
        end = time.monotonic() + 60
        while time.monotonic() < end:
            sum(range(1000))
    elif phase == "render":
        import mitsuba as mi

        scene = mi.load_dict({"type": "scene", "integrator": {"type": "path"}, "emitter": {"type": "constant"},
                              "sensor": {"type": "perspective", "film": {"type": "hdrfilm", "width": 256,
                                                                          "height": 256}},
                              "shape": {"type": "sphere"}})
        _mark(phase)
        np.asarray(mi.render(scene, spp=1 << 16))
    elif phase == "pipe":
        proc = subprocess.Popen([sys.executable, "-c", STUBBORN_CHILD], stdout=subprocess.PIPE)
        Path(os.environ["TINY_MARK"], "child.pid").write_text(str(proc.pid))
        assert proc.stdout is not None
        proc.stdout.readline()
        _mark(phase)
        proc.stdout.read()  # blocks until the child ends (it ignores the signals)
    elif phase == "subprocess":
        _mark(phase)
        subprocess.run([sys.executable, "-c", STUBBORN_CHILD], capture_output=True, check=False)


@register_experiment(NAME, "Tiny I/O experiment (tests only)", "writes a few figures; blocks on demand", order=999)
def run(ctx: Context) -> ExperimentResult:
    from validate.figures.plots import save_image

    phase = os.environ.get("TINY_PHASE", "")
    if phase:
        _block(phase)
    rng = np.random.default_rng(7)
    figures = []
    for k in range(int(os.environ.get("TINY_FIGURES", "3"))):
        path, rel = ctx.figure_path(NAME, f"noise_{k}.png")
        save_image(path, rng.random((96, 96, 3)).astype(np.float32) * 4.0)
        figures.append(Figure(rel, f"noise {k}"))
    value = float(os.environ.get("TINY_VALUE", "0.01"))
    claim = Claim(f"{NAME}.value", "the value is small", "value", 0.02, value, 0.001,
                  source="test fixture: a fixed threshold").with_power("value × 3", 3 * value)
    res = ExperimentResult(NAME, "Tiny I/O experiment", "test fixture", claims=[claim],
                           sections=[Section("Figures", ["noise"], figures=figures)])
    res.techniques = {"tiny": {"family": "irradiance", "description": "fixture",
                               "metrics": {"error.max": {"value": value, "uncertainty": 0.001}}}}
    if os.environ.get("TINY_NOT_RUN"):
        res.not_run = [NotRun("the tiny engine", "TINY_NOT_RUN is set", "unset TINY_NOT_RUN")]
    return res
