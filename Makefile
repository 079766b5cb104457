# The two commands of the README:
#   make demo   set up (if needed) and run the main job
#   make test   set up (if needed) and run every guard: ruff, mypy, import-linter, pytest
# Setup (scripts/setup.sh) is idempotent: a second run installs and builds nothing.

SHELL := /bin/bash
VENV ?= .venv
PY := $(VENV)/bin/python
# DDS stays on this machine unless the user chose a discovery range (README: across machines).
export ROS_AUTOMATIC_DISCOVERY_RANGE ?= LOCALHOST

.PHONY: demo test setup check pytest clean-interfaces-cache

setup:
	@bash scripts/setup.sh

demo: setup
	@$(VENV)/bin/navsuite-demo

test:
	@bash scripts/setup.sh --with-browser
	@bash scripts/check.sh

clean-interfaces-cache:
	rm -rf "$${NAVSUITE_CACHE:-$${XDG_CACHE_HOME:-$$HOME/.cache}/navsuite}/interfaces" $(VENV)/.navsuite-interfaces
