"""The farm's live console: one row per scenario (queued, running, passed, FAILED with its criterion).

On a terminal the table is redrawn in place at most every ``period`` s (wall), so a 20-scenario run
is one calm screen rather than a scroll of process output; elsewhere (CI logs, pipes) each change of
a scenario's state is one line. Rows are formatted by ``row_text`` (pure, tested without a terminal).
"""

from __future__ import annotations

import shutil
import threading
import time
from dataclasses import dataclass
from typing import TextIO

from navsuite_tools.scenarios.verdict import Outcome, Verdict

STATES = ("queued", "running", "passed", "FAILED")


@dataclass
class Row:
    """A scenario's line: its state, when it started (monotonic s) and, once done, what it gave."""

    name: str
    state: str = "queued"
    started: float | None = None
    outcome: Outcome | None = None
    verdict: Verdict | None = None


def row_text(row: Row, width: int, now: float) -> str:
    """``name  state  wall  note``: the note is the first failing criterion, or the sim time taken (and
    the smallest clearance, when the run measured it)."""
    wall = ""
    if row.outcome is not None:
        wall = f"{row.outcome.wall_time:5.1f} s"
    elif row.started is not None:
        wall = f"{now - row.started:5.1f} s"
    note = ""
    if row.verdict is not None and not row.verdict.passed:
        note = row.verdict.failures[0]
    elif row.outcome is not None and row.outcome.sim_time is not None:
        note = f"sim {row.outcome.sim_time:.1f} s"
        if row.outcome.min_clearance is not None:
            note += f", clearance {row.outcome.min_clearance:.3f} m"
    return f"{row.name:<{width}}  {row.state:<7}  {wall:>7}  {note}".rstrip()


class LiveTable:
    """Thread-safe: the executor's threads report, a redraw happens on ``tick`` or on each change."""

    def __init__(self, names: list[str], out: TextIO, period: float = 0.5) -> None:
        self.rows = {name: Row(name) for name in names}
        self._out, self._period = out, period
        self._tty = out.isatty()
        self._width = max((len(name) for name in names), default=4)
        self._drawn = 0
        self._last_draw = 0.0
        self._lock = threading.Lock()

    def start(self, name: str) -> None:
        with self._lock:
            row = self.rows[name]
            row.state, row.started = "running", time.monotonic()
            self._changed(row)

    def finish(self, name: str, outcome: Outcome, verdict: Verdict) -> None:
        with self._lock:
            row = self.rows[name]
            row.state = "passed" if verdict.passed else "FAILED"
            row.outcome, row.verdict = outcome, verdict
            self._changed(row)

    def tick(self) -> None:
        """Redraw the running rows' clocks (terminal only)."""
        with self._lock:
            if self._tty and time.monotonic() - self._last_draw >= self._period:
                self._draw()

    def counts(self) -> dict[str, int]:
        with self._lock:
            return {state: sum(row.state == state for row in self.rows.values()) for state in STATES}

    def _changed(self, row: Row) -> None:
        if self._tty:
            self._draw()
            return
        done = sum(r.state in ("passed", "FAILED") for r in self.rows.values())
        prefix = f"[{done:>{len(str(len(self.rows)))}}/{len(self.rows)}]"
        self._out.write(f"{prefix} {row_text(row, self._width, time.monotonic())}\n")
        self._out.flush()

    def _draw(self) -> None:
        now = time.monotonic()
        columns = shutil.get_terminal_size().columns - 1  # a wrapped line would break the redraw
        lines = [row_text(row, self._width, now)[:columns] for row in self.rows.values()]
        done = {state: sum(r.state == state for r in self.rows.values()) for state in STATES}
        lines.append(f"-- {done['passed']} passed, {done['FAILED']} failed, {done['running']} running, "
                     f"{done['queued']} queued")
        up = f"\033[{self._drawn}F" if self._drawn else ""
        self._out.write(up + "".join(f"\033[2K{line}\n" for line in lines))
        self._out.flush()
        self._drawn = len(lines)
        self._last_draw = now
