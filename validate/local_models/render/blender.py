"""The Blender engines' common harness: scene files in, Blender's own images out, from a child process.

Blender (``bpy`` 5.0.1, :data:`validate.setup.paths.BLENDER_BPY`) lives in a virtual environment of its own
(:func:`validate.setup.paths.blender_venv`, ``python -m validate setup --blender``): its wheel needs CPython 3.11
and numpy < 2, so it never shares the suite's interpreter. :func:`render_batch` writes one JSON of jobs, runs
``blender_worker.py`` (shipped beside this module) under that interpreter — one process for a whole batch, so
Blender starts once — and reads back the float32 OpenEXR frames and what the importer made of each light.
EEVEE needs an OpenGL context: headless it gets one through EGL on Mesa with ``EGL_PLATFORM=surfaceless`` (it
prints ``EGL_BAD_MATCH`` lines and renders correctly).

An engine is a :class:`BlenderEngine` declared in its own module (``blender_cycles``, ``blender_eevee``): Blender's
render engine, the precision of its output (what a reader adds to the uncertainty), the scene kinds it renders as the
suite's truth describes them, and its known defects.

The glTF importer's light conversion (``export_import_convert_lighting_mode``, io_scene_gltf2
``blender/imp/light.py``, ``PBR_WATTS_TO_LUMENS = 683``) — read back from Blender by the worker, and measured in
pixels by the ``blender`` experiment:

======  =====================================  ======================================
mode    directional (lux → sun W/m²)           point, spot (cd → W)
======  =====================================  ======================================
SPEC    E/683                                  I·4π/683
COMPAT  E                                      I·4π
RAW     E                                      I
======  =====================================  ======================================

Blender's point or spot of power P emits P/(4π) W/sr, so COMPAT is the mode whose radiance is the suite's (1 cd read
as 1 W/sr), SPEC is 683 × darker (1 W = 683 lm) and RAW's point and spot lights are 4π × darker.
"""

from __future__ import annotations

import functools
import json
import os
import subprocess
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...setup import paths
from .engine import Engine, Unavailable

WORKER = Path(__file__).resolve().parent / "blender_worker.py"
LIGHTING_MODES = ("SPEC", "COMPAT", "RAW")
TRUTH_MODE = "COMPAT"  # the importer's mode whose radiance is the suite's (module docstring)
BATCH_TIMEOUT_S = 900.0
FIX = "python -m validate setup --blender"


@dataclass(frozen=True)
class BlenderEngine(Engine):
    """One Blender render engine as the suite drives it (the fields of :class:`.engine.Engine`, plus bpy's name)."""

    engine: str = "CYCLES"  # bpy's RenderSettings.engine

    def version(self) -> str | None:
        return installed_version()

    def unavailable(self) -> Unavailable | None:
        ver, why = available()
        return None if ver else Unavailable("Blender (bpy)", why, FIX)


@dataclass(frozen=True)
class Job:
    """One scene for Blender: ``frames`` stills of ``samples`` each, frame k seeded ``seeds[k]``."""

    glb: str
    out: str  # frames go to <out>_<k>.exr
    engine: str  # bpy engine (BlenderEngine.engine)
    resolution: int
    samples: int
    seeds: tuple[int, ...]
    lighting_mode: str = TRUTH_MODE
    world: tuple[float, float, float] | None = None  # a constant world radiance (the furnace), else black
    punctual: bool = True  # point/spot radius 0 and sun angle 0 (KHR lights are punctual)
    scene: dict[str, Any] | None = None  # a bpy-built scene's description (blender_worker.build); glb is then ""
    extras: dict[str, Any] | None = None  # added to an imported scene (blender_worker._extras): boxes, light radius


@dataclass
class JobResult:
    frames: np.ndarray  # (F, R, R, 4) float32 RGBA, row 0 = top, alpha = coverage
    lights: list[dict[str, Any]]  # what the importer made of each light (before the worker made them punctual)
    frame_s: list[float]
    setup_s: float


@dataclass
class Batch:
    version: str
    import_s: float  # ``import bpy`` in the child
    wall_s: float  # the whole child process, start to exit
    results: list[JobResult]


def installed_version() -> str | None:
    """bpy's version in the Blender venv from its package metadata (no process started), or None."""
    for d in sorted((paths.blender_venv() / "lib").glob("python3*/site-packages/bpy-*.dist-info")):
        return d.name.removeprefix("bpy-").removesuffix(".dist-info")
    return None


@functools.lru_cache(maxsize=1)
def available() -> tuple[str | None, str]:
    """(Blender's version, "") when the venv's interpreter imports bpy, else (None, why)."""
    py = paths.blender_python()
    if not py.is_file():
        return None, f"no Blender venv at {paths.blender_venv()}"
    try:
        r = subprocess.run([str(py), "-c", "import bpy; print(bpy.app.version_string)"], capture_output=True,
                           text=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return None, f"{py}: {exc}"
    if r.returncode != 0:
        return None, ((r.stderr.strip().splitlines() or [f"exit status {r.returncode}"])[-1])[:200]
    return (r.stdout.strip().splitlines() or ["?"])[-1], ""


def read_exr_rgba(path: str | Path) -> np.ndarray:
    """(H, W, 4) float32 RGBA of Blender's OpenEXR (row 0 = top); one line naming the file on failure."""
    import OpenEXR

    try:
        with OpenEXR.File(str(path), separate_channels=True) as f:
            ch = {k: np.asarray(v.pixels, np.float32) for k, v in f.channels().items()}
        return np.stack([ch[c] for c in "RGBA"], axis=-1)
    except Exception as exc:  # OpenEXR's errors, a missing channel
        first = (str(exc).strip().splitlines() or [type(exc).__name__])[-1]
        raise ValidateError(f"{path}: cannot read Blender's OpenEXR ({first[:160]})") from None


def render_batch(jobs: list[Job], workdir: Path, timeout: float = BATCH_TIMEOUT_S) -> Batch:
    """Run ``jobs`` in one Blender process (module docstring); raises ValidateError with Blender's reason."""
    py = paths.blender_python()
    if not py.is_file():
        raise ValidateError(f"Blender not installed ({paths.blender_venv()} missing): {FIX}")
    workdir.mkdir(parents=True, exist_ok=True)
    jobs_file, result_file = workdir / "jobs.json", workdir / "result.json"
    jobs_file.write_text(json.dumps({"jobs": [asdict(j) for j in jobs]}))
    env = {**os.environ, "EGL_PLATFORM": "surfaceless"}
    t0 = time.perf_counter()
    try:
        r = subprocess.run([str(py), str(WORKER), str(jobs_file), str(result_file)], capture_output=True, text=True,
                           timeout=timeout, env=env, cwd=workdir)
    except subprocess.TimeoutExpired:
        raise ValidateError(f"Blender: a batch of {len(jobs)} scenes ran past {timeout:g} s") from None
    wall = time.perf_counter() - t0
    if r.returncode != 0 or not result_file.is_file():
        lines = [x for x in (r.stderr + r.stdout).strip().splitlines() if "EGL Error" not in x]
        raise ValidateError(f"Blender worker failed (exit {r.returncode}): {(lines or ['no output'])[-1][:200]}")
    doc = json.loads(result_file.read_text())
    results = []
    for job, res in zip(jobs, doc["jobs"], strict=True):
        if "error" in res:
            raise ValidateError(f"Blender: {Path(job.glb or job.out).name}: {res['error']}")
        frames = np.stack([read_exr_rgba(f) for f in res["files"]])
        results.append(JobResult(frames, res["lights"], list(res["frame_s"]), float(res["setup_s"])))
    return Batch(str(doc["version"]), float(doc["import_s"]), wall, results)


def half_exact(x: np.ndarray) -> bool:
    """Every value of ``x`` is a binary16 number (a float file holding a half-float render)."""
    x = np.asarray(x, np.float32)
    return bool(np.array_equal(x.astype(np.float16).astype(np.float32), x))


__all__ = ["BlenderEngine", "Job", "JobResult", "Batch", "LIGHTING_MODES", "TRUTH_MODE", "available",
           "installed_version", "render_batch", "read_exr_rgba", "half_exact"]
