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
# No re-runs: the simulator runs in lockstep with the stack, so a test's outcome does not depend on
# how loaded the machine is, and a test that fails is a defect to find, not bad luck.
"$VENV/bin/python" -m pytest "$@"
