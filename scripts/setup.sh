#!/usr/bin/env bash
# One-time set-up of a fresh Debian machine (Python >= 3.10, run as root or with sudo for apt):
#   * creates .venv and installs the suite with its test extras (editable);
#   * then `python -m validate setup`: drjit's LLVM backend (it needs libLLVM >= 16; with Debian's default
#     libLLVM 14/15 drjit refuses or aborts, so the probe runs in a child and libllvm19 comes from apt),
#     the GL runtime, a Vulkan device (mesa-vulkan-drivers: lavapipe, for the glTF-IBL-Sampler), Chromium,
#     Node.js, the npm engines and Blender (bpy in its own python3.11 venv, ~1 GB).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}

SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi

if [ ! -x .venv/bin/python ]; then
    if ! "$PY" -m venv .venv 2>/dev/null; then
        # Debian's system Python ships venv/ensurepip separately
        echo "setup: python venv unavailable; installing python3-venv through apt"
        rm -rf .venv
        $SUDO apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq python3-venv >/dev/null
        "$PY" -m venv .venv
    fi
fi
# The Python packages: installed once per pyproject.toml (a stamp holds its hash), so a second `make report` or
# `make test` does not spend half a minute re-resolving them; a changed pyproject.toml or a new .venv reinstalls.
py_stamp=.venv/.validate-setup
py_want=$(sha256sum pyproject.toml | cut -d' ' -f1)
if [ "$(cat "$py_stamp" 2>/dev/null)" != "$py_want" ] || ! .venv/bin/python -c "import validate" 2>/dev/null; then
    .venv/bin/python -m pip install --quiet --upgrade pip
    .venv/bin/python -m pip install --quiet -e '.[test]'
    echo "$py_want" > "$py_stamp"
fi

# Everything else — drjit's LLVM backend (libllvm19 from apt when the probe fails), Mesa's EGL/llvmpipe, Debian's
# chromium, nodejs/npm and the pinned npm engines (into the per-user folder, ~/.local/share/validate) — is
# `python -m validate setup`, the same command a user of the installed wheel runs (validate/setup/install.py).
# A piece that cannot be installed is a warning: the experiments and tests that need it say so and skip.
.venv/bin/python -m validate setup
