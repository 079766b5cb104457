"""Fake processes for the launcher's tests: short Python commands that count their own starts.

Each life appends one line to a counter file, prints ``life <n> ready`` and then does what its
life number asks (exit with a code, or stay up), so a test can tell a respawned process from the
first one without timing anything.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

_BODY = """
import os, sys, time
path = sys.argv[1]
with open(path, "a") as f:
    f.write(str(os.getpid()) + "\\n")
life = len(open(path).read().split())
print(f"life {{life}} ready env={{os.environ.get('FAKE_TAG', '')}}", flush=True)
codes = {codes!r}
if life <= len(codes):
    sys.exit(codes[life - 1])
time.sleep(60)
"""


def dying(counter: Path, exit_codes: Sequence[int]) -> list[str]:
    """A command whose n-th life exits with ``exit_codes[n-1]`` after its ready line; later lives stay
    up (60 s). Every life appends its pid to ``counter``."""
    return [sys.executable, "-u", "-c", _BODY.format(codes=list(exit_codes)), str(counter)]


def lives(counter: Path) -> int:
    """How many times the command was started."""
    return len(counter.read_text().split()) if counter.exists() else 0
