"""smacc_py.state_machines.stack_run: how every mission command starts the stack, waits and ends.

The stack here is a shell command standing in for nav-bringup (``--bringup``); no rclpy is involved.
"""

from __future__ import annotations

import argparse
import signal
import sys
from pathlib import Path

import pytest

from ros_tools.console import StackConsole
from smacc_py.state_machines.stack_run import (
    EXIT_ABORT,
    EXIT_INTERRUPTED,
    EXIT_STACK,
    EXIT_SUCCESS,
    EXIT_TIMEOUT,
    MissionEnd,
    StackSession,
    add_console_arguments,
    bringup_command,
    parse_rtf,
    run_against_stack,
    wait_for_end,
)


def options(tmp_path: Path, bringup: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rtf", type=parse_rtf, default="max")
    parser.add_argument("--ready-timeout", type=float, default=20.0)
    parser.add_argument("--bringup")
    add_console_arguments(parser)
    return parser.parse_args(["--bringup", bringup, "--log-dir", str(tmp_path)])


def test_a_stack_that_dies_before_ready_exits_3_without_running_the_mission(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    handler = signal.getsignal(signal.SIGINT)
    ran: list[StackSession] = []
    code = run_against_stack(options(tmp_path, "/bin/sh -c 'echo boom; exit 4'"), StackConsole(False, "demo"),
                             "SmTest", lambda session: ran.append(session) or EXIT_SUCCESS)
    out = capsys.readouterr().out
    assert code == EXIT_STACK and not ran
    assert out.splitlines()[0] == "[demo] starting the stack: /bin/sh -c echo boom; exit 4 --rtf max"
    assert (f"[demo] FAILED: the stack did not come up: nav exited with code 4 before it was ready "
            f"(logs: {tmp_path}/)") in out
    assert (tmp_path / "nav.log").exists()
    assert signal.getsignal(signal.SIGINT) is handler


def test_once_ready_the_mission_runs_and_its_code_is_the_exit_status(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    stack = f"{sys.executable} -c \"print('Nav2 is ready', flush=True); import time; time.sleep(30)\""

    def mission(session: StackSession) -> int:
        end = wait_for_end(session, lambda: True, deadline=float("inf"))
        assert end == MissionEnd(finished=True, interrupted=False, timed_out=False, stack_code=0)
        return EXIT_SUCCESS

    code = run_against_stack(options(tmp_path, stack), StackConsole(False, "patrol"), "SmTest", mission,
                             ready_note="the stack is ready; its logs: {log_dir}/<process>.log")
    assert code == EXIT_SUCCESS
    assert f"[patrol] the stack is ready; its logs: {tmp_path}/<process>.log" in capsys.readouterr().out


class _Launcher:
    """Polls ``until`` like ros_tools.launch.Launcher.wait; ``dies_after`` polls the stack exits with 5."""

    def __init__(self, dies_after: int = 1000) -> None:
        self.dies_after = dies_after

    def wait(self, until, poll: float = 0.1) -> int:  # type: ignore[no-untyped-def]
        for _ in range(self.dies_after):
            if until():
                return 0
        return 5


def session(launcher: _Launcher) -> StackSession:
    import threading

    return StackSession(StackConsole(False, "demo"), launcher, Path("logs"), threading.Event(), 0.0)  # type: ignore[arg-type]


def test_wait_for_end_tells_a_timeout_from_a_dead_stack_and_ticks_every_poll() -> None:
    ticks: list[int] = []
    end = wait_for_end(session(_Launcher()), lambda: False, deadline=0.0, tick=lambda: ticks.append(1))
    assert end.timed_out and not end.finished and ticks == [1]
    end = wait_for_end(session(_Launcher(dies_after=3)), lambda: False, deadline=float("inf"))
    assert not end.timed_out and end.stack_code == 5


@pytest.mark.parametrize(("end", "expected"), [
    (MissionEnd(True, True, True, 5), (EXIT_ABORT, "ABORT")),
    (MissionEnd(False, True, True, 5), (EXIT_INTERRUPTED, "interrupted")),
    (MissionEnd(False, False, True, 0), (EXIT_TIMEOUT, "TIMEOUT after 600 s wall in ['StA']")),
    (MissionEnd(False, False, False, 5),
     (EXIT_STACK, "the stack stopped (exit code 5) before the dance ended")),
])
def test_the_verdict_prefers_the_mission_then_ctrl_c_then_the_deadline(end, expected) -> None:  # type: ignore[no-untyped-def]
    assert end.verdict(lambda: (EXIT_ABORT, "ABORT"), 600.0, ["StA"], "dance") == expected


def test_bringup_command_passes_the_participant_and_console_only_to_nav_bringup() -> None:
    custom = bringup_command("5", "fake-stack --x", "SmTest", "tb4", ["--verbose"])
    assert custom == ["fake-stack", "--x", "--robot", "tb4", "--rtf", "5"]
    real = bringup_command("max", None, "SmTest", None, ["--log-dir", "logs"])
    assert real[-5:] == ["max", "--participant", "SmTest", "--log-dir", "logs"]
    with pytest.raises(argparse.ArgumentTypeError):
        parse_rtf("0")
