#!/usr/bin/env bash
# One-time set-up of a fresh Debian machine (Python >= 3.10, run as root or with sudo for apt):
#   * creates .venv and installs the suite with its test extras;
#   * makes sure drjit's LLVM backend works: it needs libLLVM >= 16, and with Debian's default
#     libLLVM 14/15 drjit aborts the whole process ("LLVM ERROR: Cannot select ... fminimum").
#     The probe runs in a subprocess; if it fails, libllvm19 is installed through apt.
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

probe_llvm() {
    .venv/bin/python - <<'PY' >/dev/null 2>&1
import drjit as dr
x = dr.llvm.Float([1.0, 2.0, 3.0])
assert list(dr.sum(dr.minimum(x, 2.0))) == [5.0]
PY
}

if probe_llvm; then
    echo "setup: drjit LLVM backend works"
else
    echo "setup: drjit LLVM backend unavailable; installing libllvm19 through apt"
    if command -v apt-get >/dev/null 2>&1; then
        $SUDO apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq libllvm19 >/dev/null
    fi
    if probe_llvm; then
        echo "setup: drjit LLVM backend works (libllvm19)"
    else
        echo "setup: WARNING: drjit LLVM backend still unavailable; the suite falls back to scalar_rgb (slow)." >&2
        echo "       Set DRJIT_LIBLLVM_PATH to a libLLVM >= 16 to use the vectorised backend." >&2
    fi
fi

# Headless Chromium (Debian's package; nothing downloads a browser) for the report's page test.
if ! command -v chromium >/dev/null 2>&1 && command -v apt-get >/dev/null 2>&1; then
    echo "setup: installing chromium through apt (headless test of the HTML report)"
    { $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq chromium >/dev/null; } \
        || echo "setup: WARNING: chromium unavailable; the report page test will be skipped" >&2
fi

# Shipping engines under test (the `engines` experiment): Node.js and the pinned npm packages
# (package.json / package-lock.json: three, @babylonjs/core). Without them that experiment is skipped
# with the reason and everything else runs; so any failure here is a warning, never an abort.
if ! command -v node >/dev/null 2>&1 && command -v apt-get >/dev/null 2>&1; then
    echo "setup: installing Debian's nodejs and npm through apt (engines experiment)"
    { $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq nodejs npm >/dev/null; } \
        || echo "setup: WARNING: nodejs/npm unavailable; the engines experiment will be skipped" >&2
fi
if [ -f package.json ] && command -v node >/dev/null 2>&1 && node --version >/dev/null 2>&1; then
    # once per package-lock.json (a stamp inside node_modules holds its hash): `npm ci` deletes and rewrites
    # node_modules on every call
    npm_want=$(cat package.json package-lock.json 2>/dev/null | sha256sum | cut -d' ' -f1)
    if [ -d node_modules ] && [ "$(cat node_modules/.validate-setup 2>/dev/null)" = "$npm_want" ]; then
        echo "setup: npm packages installed (three, @babylonjs/core)"
    elif command -v npm >/dev/null 2>&1; then
        npm ci --silent --no-audit --no-fund >/dev/null 2>&1 \
            && echo "$npm_want" > node_modules/.validate-setup \
            && echo "setup: npm packages installed (three, @babylonjs/core)" \
            || echo "setup: WARNING: npm ci failed; the engines experiment will be skipped" >&2
    else
        echo "setup: WARNING: npm not found; the engines experiment will be skipped" >&2
    fi
fi

# GL runtimes for GLSL techniques (validate.gl): Mesa's llvmpipe through EGL (surfaceless, no GPU, no
# display) and headless Chromium's WebGL2 (the chromium package above; playwright drives it through
# executable_path, so nothing downloads a browser). Without them the GLSL techniques are not registered,
# `python -m validate list` says why, and the GL tests skip: every failure here is a warning.
probe_gl() {
    .venv/bin/python - <<'PY' 2>&1
from validate.gl import runtime
ok, why = runtime.available("llvmpipe")
print(why)
raise SystemExit(0 if ok else 1)
PY
}
if gl_msg=$(probe_gl); then
    echo "setup: GL runtime works: $gl_msg"
else
    echo "setup: GL runtime unavailable ($gl_msg); installing Mesa's EGL/llvmpipe through apt"
    if command -v apt-get >/dev/null 2>&1; then
        { $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq \
            libegl1 libegl-mesa0 libgl1-mesa-dri libgl1 >/dev/null; } \
            || echo "setup: WARNING: apt could not install the Mesa GL packages" >&2
    fi
    if gl_msg=$(probe_gl); then
        echo "setup: GL runtime works: $gl_msg"
    else
        echo "setup: WARNING: no GL runtime ($gl_msg); GLSL techniques will not be registered" >&2
    fi
fi
