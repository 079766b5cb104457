"""A child process whose output lines are collected, as they come, by a reader thread.

Why a thread: a streaming command (``ros2py topic echo``, a Foxglove bridge, a probe that waits for a
signal) never ends by itself, so ``communicate()`` cannot be used to read it; a test waits for the
line it needs while the child keeps running. Shared by the CLI tests' ``stream_cli`` fixture
(tests/integration/conftest.py) and the runner's process tests (test_runner.py).
"""

from __future__ import annotations

import signal
import subprocess
import threading
from collections.abc import Callable
from dataclasses import dataclass, field

from navsuite_testing.ros import wait_until


@dataclass
class StreamingCli:
    """A running streaming verb (echo, hz, pub) whose output lines are collected as they come."""

    proc: subprocess.Popen[str]
    lines: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line.rstrip("\n"))

    def wait_for(self, predicate: Callable[[list[str]], bool], timeout: float, what: str) -> None:
        wait_until(lambda: predicate(self.lines) or self.proc.poll() is not None, timeout, what)
        assert predicate(self.lines), f"{what}; the CLI exited early:\n" + "\n".join(self.lines)

    def interrupt(self, timeout: float = 10.0) -> int:
        """Send SIGINT (Ctrl-C) and return the exit code."""
        self.proc.send_signal(signal.SIGINT)
        code = self.proc.wait(timeout=timeout)
        self._reader.join(timeout=timeout)
        return code
