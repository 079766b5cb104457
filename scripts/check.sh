#!/usr/bin/env bash
# Every guard CI runs, in order of speed; the first failure stops the run with a non-zero exit.
#   ruff (style and bugs), mypy (strict on */core), import-linter (ARCHITECTURE.md dependency
#   rules), then the test suite. Extra arguments are passed to pytest (e.g. -k amcl, -m "not slow").
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}
export ROS_AUTOMATIC_DISCOVERY_RANGE=${ROS_AUTOMATIC_DISCOVERY_RANGE:-LOCALHOST}

step() { printf '\n== %s\n' "$*"; }

step "ruff"
"$VENV/bin/ruff" check .
step "mypy"
"$VENV/bin/mypy" sim2d nav_stack smacc_py
step "import-linter"
"$VENV/bin/lint-imports"
step "pytest"
# Tests that run the simulator and the stack depend on timing, and two cores shared by a dozen Python
# nodes sometimes lag. A failed test is re-run at most twice; each re-run shows as R in the output, and a
# feature that is really broken still fails. The summary ends with why each re-run attempt failed
# (tests/conftest.py).
"$VENV/bin/python" -m pytest --reruns 2 --reruns-delay 2 "$@"
