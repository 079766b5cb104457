#!/usr/bin/env bash
# Every guard CI runs, in order of speed; the first failure stops the run with a non-zero exit.
#   ruff (style and bugs), mypy (every package; strict on */core), import-linter (docs/architecture.md's dependency
#   rules), vulture (dead code, pyproject.toml [tool.vulture]), then the test suite. Extra arguments are
#   passed to pytest (e.g. -k amcl, -m "not slow").
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}
export ROS_AUTOMATIC_DISCOVERY_RANGE=${ROS_AUTOMATIC_DISCOVERY_RANGE:-LOCALHOST}

step() { printf '\n== %s\n' "$*"; }

step "ruff"
"$VENV/bin/ruff" check .
step "mypy"
"$VENV/bin/mypy" sim2d nav_stack smacc_py ros_tools navsuite_tools navsuite_data navsuite_testing
step "import-linter"
"$VENV/bin/lint-imports"
step "vulture (dead code)"
"$VENV/bin/vulture"
step "pytest"
# The simulator runs in lockstep with the stack at --rtf max, so whole-stack tests take sim time,
# not wall time, and no failed test is re-run: one that fails is a defect to find.
# The suite runs on three pytest-xdist workers (each its own ROS_DOMAIN_ID): a whole-stack test waits
# on messages more than it computes, so three keep two cores busier than two do (about 7.5 minutes
# instead of 9.5; 13 in one process). NAVSUITE_TEST_WORKERS=0 runs it in this process (for debugging).
# --dist worksteal: a worker that runs out of tests takes some from another's queue, so no worker ends
# the run alone on a queue of whole-stack tests (the same suite back to back on 2 cores: 479 s against
# 548 s with xdist's default hand-out, and 676 s with the slow tests sorted first).
"$VENV/bin/python" -m pytest -n "${NAVSUITE_TEST_WORKERS:-3}" --dist worksteal "$@"
