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
from contextlib import AbstractContextManager
from typing import TYPE_CHECKING

from smacc_py.core import SmaccObserver, SmaccStateMachineBase, TransitionRecord
from smacc_py.state_machines.stack_run import (
    EXIT_ABORT,
    EXIT_SUCCESS,
    StackSession,
    machine_runtime,
    mission_sim_s,
    running,
    wait_for_end,
)

if TYPE_CHECKING:
    from smacc_py.ros.runtime import SmaccRuntime

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


def mission_runtime(options: argparse.Namespace) -> AbstractContextManager[SmaccRuntime]:
    """SmNav2Test1's runtime with the command's parameters file and waypoints (``machine_runtime``)."""
    from smacc_py.state_machines.sm_nav2_test_1 import SmNav2Test1

    waypoints = {name.replace("waypoint", "waypoint_"): getattr(options, name)
                 for name in ("waypoint1", "waypoint2") if getattr(options, name) is not None}
    return machine_runtime(SmNav2Test1, options.params_file, waypoints)


def run_mission(options: argparse.Namespace, session: StackSession, runtime: SmaccRuntime) -> int:
    """Run the machine until StFinalState, a timeout, Ctrl-C or the stack's death; returns the exit code.

    ``runtime`` (``mission_runtime``) is built but not started: the demo builds it before the stack,
    so DDS discovers the machine while the stack comes up; ``running`` starts it and shuts it down. On
    a terminal the console's live line shows the mission's status (smacc_py.ros.mission_status),
    redrawn every 0.1 s (wall).
    """
    from smacc_py.ros.mission_status import MissionStatus
    from smacc_py.state_machines.sm_nav2_test_1 import SmNav2Test1

    say = session.out.say
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
    with running(runtime):
        mission_start = time.monotonic()

        def live() -> None:
            if runtime.started_at_s is not None:
                line = status.line(runtime.sm.current_state_names(), mission_sim_s(runtime),
                                   time.monotonic() - mission_start)
                session.out.live(line)

        end = wait_for_end(session, observer.finished.is_set, mission_start + options.timeout, live)
        records = list(observer.records)

        def finished() -> tuple[int, str]:
            last = records[-1]
            ok = last.tag.family() == "SUCCESS"
            return (EXIT_SUCCESS, "SUCCESS: mission complete") if ok else (EXIT_ABORT, f"ABORT: {_why(last)}")

        code, result = end.verdict(finished, options.timeout, runtime.sm.current_state_names(), "mission")
        now, sim_s = time.monotonic(), mission_sim_s(runtime)
        wall_s, mission_wall_s = now - session.wall_start, now - mission_start
        for line in summary(records, "StAllSensorsGo", sim_s, wall_s, result, mission_wall_s):
            say(line)
        return code


def _why(record: TransitionRecord) -> str:
    from smacc_py.ros.transition_printer import event_reason

    reason = event_reason(record.event)
    where = f"{record.source.__name__} -> {record.leaf.__name__} on {type(record.event).get_event_label()}"
    return f"{where} ({reason})" if reason else where
