"""The shared runner's process shape (ros_tools.runtime.runner), seen from outside a real process:
a ``finished`` check ends it with its code, SIGINT/SIGTERM end it promptly with the hook run while
the context is up, and rclpy's own signal handler is never installed (the one that shut a context
down under a process that then spun on for an hour after SIGTERM).

The child is tests/helpers/runner_probe.py; each fact is one line it prints.
"""

from __future__ import annotations

import signal
import subprocess
import time

import pytest

from navsuite_testing.ros import start_python, stop_process, wait_until
from tests.helpers.runner_probe import INTERRUPTED
from tests.helpers.streaming_cli import StreamingCli

pytestmark = pytest.mark.ros

START_WAIT = 60.0  # s for the child to import rclpy and build its node (a loaded 2-core machine)
STOP_WAIT = 1.0  # s from the signal to the hook: what the brief asks of the runner
EXIT_WAIT = 10.0  # s more for the interpreter to exit after its teardown
FLAG_HANDLER = "StopOnSignal._on_signal"


class Child(StreamingCli):
    """The probe as a child process, its output lines collected by StreamingCli's reader thread."""

    def __init__(self, *args: str) -> None:
        super().__init__(start_python("tests.helpers.runner_probe", args))

    def line(self, prefix: str) -> str | None:
        return next((line for line in self.lines if line.startswith(prefix)), None)

    def wait_line(self, prefix: str, timeout: float) -> None:
        self.wait_for(lambda _: self.line(prefix) is not None, timeout, f"the probe's '{prefix}' line")

    def finish(self) -> int:
        if self.proc.poll() is None:
            stop_process(self.proc)
        self._reader.join(timeout=5.0)
        return self.proc.wait()


@pytest.mark.parametrize("code", [0, 3, 7])
def test_a_finished_check_ends_the_process_with_its_code_after_the_hook(code: int) -> None:
    child = Child("finish", str(code))
    try:
        child.proc.wait(timeout=START_WAIT)
    except subprocess.TimeoutExpired:
        pytest.fail("the finished check did not end the process:\n" + "\n".join(child.lines))
    finally:
        child.finish()
    assert child.proc.returncode == code, "\n".join(child.lines)
    assert child.line("hook") == "hook context_ok=True", "\n".join(child.lines)


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_ends_the_run_promptly_with_the_hook_run_and_its_exit_code(sig: signal.Signals) -> None:
    child = Child("serve")
    try:
        child.wait_line("ready", START_WAIT)
        assert child.proc.poll() is None, "\n".join(child.lines)
        child.proc.send_signal(sig)
        sent = time.monotonic()
        # A deadline on the runner's response (a flag checked every SPIN_SLICE s), not a timing
        # measurement: the hook must run, with the context still up, within STOP_WAIT of the signal.
        wait_until(lambda: child.line("hook") is not None or child.proc.poll() is not None,
                   STOP_WAIT - (time.monotonic() - sent), "the hook after the signal")
        child.proc.wait(timeout=EXIT_WAIT)
    finally:
        child.finish()
    assert child.line("hook") == "hook context_ok=True", "\n".join(child.lines)
    assert child.proc.returncode == INTERRUPTED, "\n".join(child.lines)
    assert not any("Traceback" in line for line in child.lines), "\n".join(child.lines)


def test_the_run_installs_only_the_flag_handler_and_puts_the_old_ones_back() -> None:
    child = Child("finish", "0")
    try:
        child.proc.wait(timeout=START_WAIT)
    finally:
        child.finish()
    # Inside the run: the runner's flag for both signals, rclpy's handler off. After: Python's own.
    assert child.line("ready") == (f"ready sigterm={FLAG_HANDLER} sigint={FLAG_HANDLER} "
                                   "rclpy_handlers=False"), "\n".join(child.lines)
    assert child.line("after") == "after sigterm=SIG_DFL sigint=default_int_handler", "\n".join(child.lines)


def test_ros_process_for_a_library_leaves_the_signals_to_its_caller_and_shuts_its_context() -> None:
    from rclpy.context import Context

    from ros_tools.runtime.runner import ros_process

    before = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    with ros_process([], context=Context(), handle_signals=False) as process:
        assert process.context.ok() and process.ok()
        assert {sig: signal.getsignal(sig) for sig in before} == before
        context = process.context
    assert not context.ok()


def test_ros_process_keeps_dds_on_this_machine_unless_the_user_chose(monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 49: no import sets DDS defaults; the runner does, before rclpy starts, where unset."""
    import os

    from rclpy.context import Context

    from ros_tools.runtime.runner import ros_process

    monkeypatch.delenv("ROS_AUTOMATIC_DISCOVERY_RANGE", raising=False)
    with ros_process([], context=Context(), handle_signals=False):
        assert os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "LOCALHOST"
    monkeypatch.setenv("ROS_AUTOMATIC_DISCOVERY_RANGE", "OFF")  # the user's choice stays (OFF: no traffic)
    with ros_process([], context=Context(), handle_signals=False):
        assert os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "OFF"


def test_a_signal_sets_the_flag_and_asks_the_caller_to_stop_without_raising() -> None:
    import os

    from ros_tools.runtime.runner import StopOnSignal

    asked: list[bool] = []
    before = signal.getsignal(signal.SIGTERM)
    stop = StopOnSignal(on_stop=lambda: asked.append(True))
    try:
        os.kill(os.getpid(), signal.SIGTERM)  # handled in this (main) thread at the next bytecode
        wait_until(lambda: stop.requested, 5.0, "the stop flag")
    finally:
        stop.restore()
    assert asked == [True]
    assert signal.getsignal(signal.SIGTERM) == before
