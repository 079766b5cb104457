"""The console of a command that runs a stack under ros_tools.launch (navsuite-demo, sm-battery-patrol).

Why: a mission's story is a handful of lines (transitions, a summary), while the stack prints
hundreds. By default the stack's lines are kept, not shown: errors appear live, and when the run
fails the last warnings and errors are printed with where the full logs are (the launcher writes
each process's log to ``<log_dir>/<process>.log``). ``verbose`` streams every line as it comes.
On a terminal a live line (``live``) shows the run's progress under the printed lines.
"""

from __future__ import annotations

import threading
from collections import deque
from pathlib import Path

from ros_tools.launch import show_problems
from ros_tools.status_line import StatusLine

LIVE_MARKERS = ("[ERROR]", "[FATAL]")  # shown as they come even on a calm console
KEPT_LINES = 200  # the stack's last lines, shown when it does not come up
KEPT_PROBLEMS = 20  # the stack's last warnings and errors, shown when the run fails


class StackConsole:
    """Serialised printing of the command's own lines (``say``) and the stack's (``stack``)."""

    def __init__(self, verbose: bool, name: str, status: StatusLine | None = None) -> None:
        """``name`` prefixes the console's own notes (``[demo] ...``); ``status`` is the live line
        (drawn on a terminal only; its stream should be stdout, where the lines go)."""
        self.verbose = verbose
        self.name = name
        self.status = status
        self._lock = threading.Lock()
        self.kept: deque[str] = deque(maxlen=KEPT_LINES)
        self.problems: deque[str] = deque(maxlen=KEPT_PROBLEMS)

    def say(self, line: str) -> None:
        """Print one line of the command's own (under the live line, which is redrawn later)."""
        with self._lock:
            if self.status is not None:
                self.status.clear()
            print(line, flush=True)

    def live(self, text: str) -> None:
        """Redraw the live line with ``text`` (rate-limited; nothing when not on a terminal)."""
        if self.status is not None:
            with self._lock:
                self.status.update(text)

    def stack(self, line: str) -> None:
        """Take one line of the stack's output (the Launcher's ``output``)."""
        if self.verbose:
            self.say(line)
            return
        with self._lock:
            self.kept.append(line)
            if show_problems(line):
                self.problems.append(line)
        if any(marker in line for marker in LIVE_MARKERS):
            self.say(line)

    def show_kept(self, count: int = 40) -> None:
        """Print the stack's last ``count`` lines (after it failed to come up), unless already shown."""
        if not self.verbose:
            for line in list(self.kept)[-count:]:
                self.say(line)

    def show_problems(self, log_dir: Path | None) -> None:
        """Print the kept warnings and errors and where the full logs are (after a failed run)."""
        if self.verbose:
            return
        with self._lock:
            problems = list(self.problems)
        where = f"; full logs: {log_dir}/<process>.log, the process named in brackets" if log_dir else ""
        if problems:
            self.say(f"[{self.name}] the stack's last {len(problems)} warnings and errors{where}:")
            for line in problems:
                self.say(line)
        elif where:
            self.say(f"[{self.name}] no warnings or errors from the stack{where}")
