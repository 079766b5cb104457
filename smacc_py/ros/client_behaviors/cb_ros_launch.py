"""``CbRosLaunch``: run a process for the lifetime of a state (SMACC2's CbRosLaunch / CbRosLaunch2).

On entry the command starts with ``subprocess.Popen`` (never waited for); the runtime's polling
notices when it ends: exit status 0 posts ``EvCbSuccess[CbRosLaunch, Or](returncode=0)``, any other
status ``EvCbFailure`` with ``returncode`` and ``reason``; a command that cannot start fails at once.
On state exit a process still running is stopped: SIGINT to its process group (what Ctrl-C sends,
which ``ros2 launch`` turns into an orderly shutdown of everything it started), then SIGKILL after
``stop_timeout_s`` wall seconds. That wait runs in a daemon thread, so the exit does not block.

``ros2_launch_command(package, launch_file, **arguments)`` builds the usual ``ros2 launch`` line;
any other command works as well.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import subprocess
import threading
from collections.abc import Mapping, Sequence

from smacc_py.ros.client_behaviors.cb_outcome_base import CbOutcomeBase
from smacc_py.ros.components.checks import check_duration

_log = logging.getLogger("smacc_py")

DEFAULT_STOP_TIMEOUT_S = 5.0  # wall s between SIGINT and SIGKILL on state exit


def ros2_launch_command(package: str, launch_file: str, **arguments: str) -> list[str]:
    """``["ros2", "launch", package, launch_file, "name:=value", ...]``."""
    return ["ros2", "launch", package, launch_file, *(f"{k}:={v}" for k, v in arguments.items())]


def _stop(process: subprocess.Popen[bytes], timeout_s: float) -> None:
    """SIGINT the process group, SIGKILL it if still alive after ``timeout_s``, reap the process."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(process.pid, signal.SIGINT)
    try:
        process.wait(timeout_s)
    except subprocess.TimeoutExpired:
        _log.warning("CbRosLaunch: pid %d ignored SIGINT for %.1f s; killing it", process.pid, timeout_s)
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGKILL)
        process.wait()


class CbRosLaunch(CbOutcomeBase):
    """Runs ``command`` (argv list) while its state is active; ``env`` adds variables to ours."""

    def __init__(self, command: Sequence[str], *, cwd: str | None = None,
                 env: Mapping[str, str] | None = None,
                 stop_timeout_s: float = DEFAULT_STOP_TIMEOUT_S) -> None:
        if isinstance(command, str) or not command or not all(isinstance(a, str) for a in command):
            raise TypeError(f"CbRosLaunch: command must be a non-empty list of strings (argv), got "
                            f"{command!r}")
        self.command = list(command)
        self.cwd, self.env = cwd, dict(env or {})
        self.stop_timeout_s = check_duration("CbRosLaunch", "stop_timeout_s", stop_timeout_s)
        self.process: subprocess.Popen[bytes] | None = None
        self._stopper: threading.Thread | None = None

    def start(self) -> None:
        try:
            self.process = subprocess.Popen(self.command, cwd=self.cwd, env={**os.environ, **self.env},
                                            stdin=subprocess.DEVNULL, start_new_session=True)
        except OSError as exc:
            self.finish(False, returncode=None, reason=f"CbRosLaunch: cannot start {self.command}: {exc}")

    def poll(self) -> None:
        code = None if self.process is None else self.process.poll()
        if code is None:
            return
        if code == 0:
            self.finish(True, returncode=0)
        else:
            self.finish(False, returncode=code,
                        reason=f"CbRosLaunch: {self.command} exited with status {code}")

    def stop(self) -> None:
        process = self.process
        if process is not None and process.poll() is None:
            self._stopper = threading.Thread(target=_stop, args=(process, self.stop_timeout_s),
                                             name="CbRosLaunch.stop", daemon=True)
            self._stopper.start()
