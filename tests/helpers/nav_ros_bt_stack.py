"""Run ``nav-bringup`` in a child process for system tests and talk to it from a client node.

The simulator runs in lockstep at SYSTEM_RTF (``max`` unless NAV_SYSTEM_TEST_RTF says otherwise).
"""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from typing import Any

from navsuite_testing.ros import REPO, SYSTEM_RTF, wait_until

READY = "Nav2 is ready"


class Bringup:
    """A running ``python -m nav_stack.ros.bringup.nav_bringup`` whose output is collected line by line."""

    def __init__(self, *args: str) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "nav_stack.ros.bringup.nav_bringup", "--rtf", SYSTEM_RTF, *args], cwd=REPO,
            env=dict(os.environ), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
            start_new_session=True)
        self.lines: list[str] = []
        self._reader = threading.Thread(target=self._pump, daemon=True)
        self._reader.start()

    def _pump(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line.rstrip("\n"))

    def output(self, last: int = 60) -> str:
        return "\n".join(self.lines[-last:])

    def wait_for_line(self, text: str, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while not any(text in line for line in self.lines):
            if self.proc.poll() is not None:
                code = self.proc.returncode
                raise AssertionError(f"nav-bringup exited ({code}) before '{text}':\n{self.output()}")
            if time.monotonic() > deadline:
                raise AssertionError(f"no '{text}' after {timeout:.0f} s:\n{self.output()}")
            time.sleep(0.1)

    def stop(self, timeout: float = 30.0) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
        self._reader.join(timeout=5.0)
        return self.proc.returncode


def yaw_of(q: Any) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def wait(predicate: Callable[[], bool], timeout: float, what: str) -> None:
    """Poll ``predicate()`` until true; fail after ``timeout`` s (navsuite_testing.ros.wait_until)."""
    wait_until(predicate, timeout, what, step=0.05)
