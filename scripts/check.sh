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
# The simulator runs in lockstep with the stack, so outcomes no longer depend on load. One known
# defect remains: a client that has just discovered an action server can lose its first goal
# request (Fast DDS matches the two sides at different moments); clients now resend, and until that
# is shown to be enough over repeated CI runs a failed test is re-run at most twice, each re-run
# showing as R. A test that needs a re-run is still a defect to find.
"$VENV/bin/python" -m pytest --reruns 2 --reruns-delay 2 "$@"
