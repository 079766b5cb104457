"""The in-process half of ``navsuite-demo``: run SmNav2Test1 on its own rclpy context and report.

Kept apart from demo.py so the command-line and process handling stay readable; the mission result
is decided here from the transition log: success means the transition into StFinalState carries a
SUCCESS-family tag.
"""

from __future__ import annotations

import argparse
import threading
import time
from collections.abc import Callable
from typing import Any

from smacc_py.core import SmaccObserver, SmaccStateMachineBase, TransitionRecord

EXIT_SUCCESS, EXIT_ABORT, EXIT_TIMEOUT, EXIT_STACK, EXIT_INTERRUPTED = 0, 1, 2, 3, 130
FINAL_STATE = "StFinalState"


class MissionObserver(SmaccObserver):
    """Prints each transition and sets ``finished`` once the machine entered the final state."""

    def __init__(self, say: Callable[[str], None]) -> None:
        from smacc_py.ros.transition_printer import format_transition

        self.say, self.format = say, format_transition
        self.finished = threading.Event()
        self.records: list[TransitionRecord] = []

    def on_transition(self, sm: SmaccStateMachineBase, record: TransitionRecord) -> None:
        self.records.append(record)
        self.say(f"[demo] {self.format(record)}")
        if record.leaf.__name__ == FINAL_STATE:
            self.finished.set()


def summary(
    records: list[TransitionRecord], initial: str, sim_s: float, wall_s: float, result: str,
    mission_wall_s: float | None = None,
) -> list[str]:
    """The closing lines: states visited, durations, the real-time factor reached, result.

    ``wall_s`` counts from the command's start (bringup included); the real-time factor is the
    mission's sim time over the mission's own wall time (``mission_wall_s``, from the machine's start).
    """
    visited = [initial, *[r.leaf.__name__ for r in records]]
    rtf = f"; real-time factor {sim_s / mission_wall_s:.1f}" if mission_wall_s else ""
    return [
        "[demo] ---------------- summary ----------------",
        f"[demo] states visited: {' -> '.join(visited)}",
        f"[demo] transitions: {len(records)}; sim time {sim_s:.1f} s; wall time {wall_s:.1f} s{rtf}",
        f"[demo] result: {result}",
    ]


def run_mission(
    options: argparse.Namespace,
    launcher: Any,
    say: Callable[[str], None],
    interrupted: threading.Event,
    wall_start: float,
    live: Callable[[str], None] | None = None,
) -> int:
    """Run the machine until StFinalState, a timeout, Ctrl-C or the stack's death; returns the exit code.

    ``live`` gets the mission's status line (smacc_py.ros.mission_status) every 0.1 s (wall).
    """
    import rclpy
    from rclpy.context import Context
    from rclpy.parameter import Parameter

    from smacc_py.ros.mission_status import MissionStatus
    from smacc_py.ros.runtime import SmaccRuntime
    from smacc_py.state_machines.sm_nav2_test_1 import SmNav2Test1

    args = ["--ros-args", "--params-file", str(options.params_file)] if options.params_file else []
    context = Context()
    rclpy.init(args=args, context=context)
    overrides = [Parameter("use_sim_time", value=True)]
    for name in ("waypoint1", "waypoint2"):
        if getattr(options, name) is not None:
            overrides.append(Parameter(name.replace("waypoint", "waypoint_"), value=getattr(options, name)))
    runtime = None
    try:
        runtime = SmaccRuntime(SmNav2Test1, context=context, parameter_overrides=overrides)
        observer = MissionObserver(say)
        runtime.sm.add_observer(observer)
        status = MissionStatus()
        runtime.sm.add_observer(status)
        assert isinstance(runtime.sm, SmNav2Test1)
        config = runtime.sm.config
        say(
            f"[demo] mission: initial pose {config.initial_pose}, waypoint_1 {config.waypoint_1}, "
            f"waypoint_2 {config.waypoint_2}"
        )
        runtime.spin_in_background()
        runtime.start()
        mission_start = time.monotonic()
        deadline = mission_start + options.timeout
        timed_out = threading.Event()

        def until() -> bool:
            if live is not None and runtime is not None and runtime.started_at_s is not None:
                sim_s = runtime.sm.now() - runtime.started_at_s
                live(status.line(runtime.sm.current_state_names(), sim_s, time.monotonic() - mission_start))
            if observer.finished.is_set() or interrupted.is_set():
                return True
            if time.monotonic() > deadline:
                timed_out.set()
                return True
            return False

        stack_code = launcher.wait(until)
        records = list(observer.records)
        started = runtime.started_at_s
        sim_s = runtime.sm.now() - started if started is not None else 0.0
        wall_s = time.monotonic() - wall_start
        mission_wall_s = time.monotonic() - mission_start
        if observer.finished.is_set():
            last = records[-1]
            ok = last.tag.family() == "SUCCESS"
            code = EXIT_SUCCESS if ok else EXIT_ABORT
            result = "SUCCESS: mission complete" if ok else f"ABORT: {_why(last)}"
        elif interrupted.is_set():
            code, result = EXIT_INTERRUPTED, "interrupted"
        elif timed_out.is_set():
            code, result = (
                EXIT_TIMEOUT,
                f"TIMEOUT after {options.timeout:.0f} s wall in {runtime.sm.current_state_names()}",
            )
        else:
            code, result = EXIT_STACK, f"the stack stopped (exit code {stack_code}) before the mission ended"
        for line in summary(records, "StAllSensorsGo", sim_s, wall_s, result, mission_wall_s):
            say(line)
        return code
    finally:
        if runtime is not None:
            runtime.shutdown()
        if context.ok():
            rclpy.shutdown(context=context)


def _why(record: TransitionRecord) -> str:
    from smacc_py.ros.transition_printer import event_reason

    reason = event_reason(record.event)
    where = f"{record.source.__name__} -> {record.leaf.__name__} on {type(record.event).get_event_label()}"
    return f"{where} ({reason})" if reason else where
