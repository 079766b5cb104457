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
# The simulator runs in lockstep with the stack at --rtf max, so whole-stack tests take sim time,
# not wall time. NAVSUITE_TEST_WORKERS=2 runs the suite on two pytest-xdist workers (each its own
# ROS_DOMAIN_ID, about 6 instead of 9 to 11 minutes); not the default yet because two workers
# still expose load dependence the lockstep does not cover (cross-process delivery and discovery
# measured in sim time: see the issue 17 note). Until that is gone a failed test is re-run at most
# twice, each re-run showing as R: a test that needs one is still a defect to find.
"$VENV/bin/python" -m pytest -n "${NAVSUITE_TEST_WORKERS:-0}" --reruns 2 --reruns-delay 2 "$@"
