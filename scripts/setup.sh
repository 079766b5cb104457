#!/usr/bin/env bash
# One-time (and idempotent) setup behind `make demo` and `make test`:
#   1. check the system prerequisites and say what to install when one is missing;
#   2. create .venv and install the project with its dev and interface-build groups, and for
#      --with-browser (`make test`) its cluster extra (only when pyproject.toml changed since the
#      last install, or the extra is missing);
#   3. build the ROS interface packages under interfaces/ into .venv, or restore them
#      from the cache (~/.cache/navsuite/interfaces/<hash>) when interfaces/ is unchanged;
#   4. compile the numba kernels into their __pycache__ (scripts/compile_kernels.py), and the
#      project's Python bytecode (compileall).
# A second run with nothing changed takes a few seconds and rebuilds nothing.
set -euo pipefail
cd "$(dirname "$0")/.."

VENV=${VENV:-.venv}
PYTHON=${PYTHON:-python3}
WITH_BROWSER=0
[ "${1:-}" = "--with-browser" ] && WITH_BROWSER=1

missing=()
need() {  # need <command> <debian package> <why>
  command -v "$1" >/dev/null 2>&1 || missing+=("  - '$1' not found: install the Debian/Ubuntu package '$2' ($3)")
}
need "$PYTHON" python3 "runs everything"
need cmake cmake "builds the ROS interface packages"
need cc gcc "compiles the interface type support"
need c++ g++ "compiles the interface type support"
need make make "drives the build"
need git git "versioning"
if command -v "$PYTHON" >/dev/null 2>&1; then
  if ! "$PYTHON" -c 'import sys; sys.exit(not ((3, 10) <= sys.version_info[:2] <= (3, 13)))'; then
    missing+=("  - $PYTHON is $("$PYTHON" -V 2>&1); ROS 2 Jazzy wheels exist for Python 3.10 to 3.13: set PYTHON=python3.11 (or similar)")
  elif ! "$PYTHON" -c 'import venv, ensurepip' >/dev/null 2>&1; then
    missing+=("  - $PYTHON has no venv/ensurepip module: install the package 'python3-venv'")
  elif ! "$PYTHON" -c 'import sysconfig, os, sys; sys.exit(not os.path.exists(os.path.join(sysconfig.get_paths()["include"], "Python.h")))'; then
    missing+=("  - Python headers (Python.h) are missing: install the package 'python3-dev'")
  fi
fi
if command -v cmake >/dev/null 2>&1; then
  cmake_version=$(cmake --version | head -n1 | grep -oE '[0-9]+\.[0-9]+' | head -n1)
  if [ "$(printf '%s\n3.22\n' "$cmake_version" | sort -V | head -n1)" != "3.22" ]; then
    missing+=("  - cmake $cmake_version is too old: version 3.22 or newer is needed")
  fi
fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: the system is missing what the build needs:" >&2
  printf '%s\n' "${missing[@]}" >&2
  echo "setup: for example: sudo apt-get install python3-venv python3-dev cmake gcc g++ make git" >&2
  exit 2
fi

if [ ! -x "$VENV/bin/python" ]; then
  echo "setup: creating $VENV with $("$PYTHON" -V 2>&1)"
  "$PYTHON" -m venv "$VENV"
fi

# `make test` (--with-browser) also installs the cluster extra: Ray, for the scenario farm's Ray test.
# The stamp names the extras, so a later `make test` after `make demo` adds Ray, and `make demo`
# after `make test` installs nothing.
extras=""
[ "$WITH_BROWSER" = 1 ] && extras="[cluster]"
deps_key="$(cat pyproject.toml | sha256sum | cut -c1-16)$extras"
deps_stamp="$VENV/.navsuite-deps"
installed=$(cat "$deps_stamp" 2>/dev/null || true)
if [ "$installed" != "$deps_key" ] && [ "$installed" != "$deps_key[cluster]" ]; then
  echo "setup: installing Python dependencies into $VENV (ROS 2 Jazzy wheels, numpy, pymunk, dev tools${extras:+, Ray})"
  "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --upgrade "pip>=25.1"
  "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check \
      --editable ".$extras" --group dev --group interfaces 2>&1 | { grep -v "is ignored: it is neither a file nor a directory" || true; }
  echo "$deps_key" > "$deps_stamp"
fi

"$VENV/bin/python" scripts/build_interfaces.py --venv "$VENV"

# numba's machine code for the planners and the costmap, compiled now rather than inside a stack.
"$VENV/bin/python" scripts/compile_kernels.py

# The project's own bytecode. Where PYTHONDONTWRITEBYTECODE is set (as on this machine) Python
# never caches it, and every process of a stack compiled its modules from source again: 0.7 s of CPU
# per stack start (4.4 s against 3.7 s for nav-bringup to "Nav2 is ready", 2026-11-28). Python checks
# each file against its source, so an edited module is compiled afresh until the next setup.
"$VENV/bin/python" -m compileall -q -j 0 nav_stack sim2d smacc_py ros_tools navsuite_tools navsuite_data tests bench >/dev/null

# The viewer's browser test drives the system's Chromium (never a downloaded browser).
if [ "$WITH_BROWSER" = 1 ] && ! command -v chromium >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "setup: installing Debian's chromium for the viewer's browser test"
    apt-get update -qq >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  else
    echo "setup: note: 'chromium' is not installed, so the viewer's browser test will be skipped" \
         "(sudo apt-get install chromium)"
  fi
fi
