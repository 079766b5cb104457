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
# The simulator runs in lockstep with the stack, so a test's outcome does not depend on how loaded
# the machine is: the suite runs in two worker processes (pytest-xdist, each worker its own
# ROS_DOMAIN_ID), and a failure is never re-run. Arguments after the script's name go to pytest; a
# later -n overrides this one (-n 0 runs everything in this process).
"$VENV/bin/python" -m pytest -n "${NAVSUITE_TEST_WORKERS:-2}" --dist worksteal "$@"
