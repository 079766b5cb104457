"""A lockstep participant waits for a sim-time timer due at its tick, but not for ever.

The report of tick T waits until the process's timers due at or before T have run
(ros_tools/runtime/timers.py, earliest_due_ns), so the simulator never steps past a cycle still to
come. The participant makes those calls itself on /clock (timers.run_overdue), so a wake-up the
executor misses neither stops the world nor kills the timer (CI run 6: nav2 stopped reporting and a
patrol hung; CI 2026-11-29: a state machine's control loop stopped for seconds of sim time). A call
whose node clock lags is never made ahead of that clock; after OWED_GRACE wall seconds the tick
counts as done without it.
"""

from __future__ import annotations

from typing import Any

import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.time import Time
from rosgraph_msgs.msg import Clock

from ros_tools.runtime import lockstep, timers
from ros_tools.runtime.lockstep import OWED_GRACE, LockstepParticipant

pytestmark = pytest.mark.ros
MS = 1_000_000


def _clock(ns: int) -> Clock:
    msg = Clock()
    msg.clock.sec, msg.clock.nanosec = divmod(ns, 1_000_000_000)
    return msg


def test_the_participant_makes_the_due_calls_and_waits_only_for_a_lagging_node_clock(
        ros_context: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    node = Node("owed_probe", context=ros_context)
    participant = LockstepParticipant(node, "owed_probe")
    reports: list[int] = []
    monkeypatch.setattr(participant, "_report", lambda ns: (reports.append(ns),
                                                            setattr(participant, "_last_report_ns", ns)))
    due = [100 * MS]
    monkeypatch.setattr(lockstep.timers, "earliest_due_ns", lambda _context=None: due[0])
    lagging = [True]  # whether the timer's node clock is behind the participant's /clock
    made: list[int] = []

    def run_overdue(clock_ns: int, _context: Any = None) -> list[str]:  # rcl's view: due by its own clock?
        if lagging[0] or due[0] > clock_ns:
            return []
        made.append(due[0])
        due[0] += 100 * MS
        return ["cycle"]

    monkeypatch.setattr(lockstep.timers, "run_overdue", run_overdue)
    wall = [50.0]
    monkeypatch.setattr(lockstep.time, "monotonic", lambda: wall[0])
    try:
        participant._on_clock(_clock(120 * MS))
        assert reports == [100 * MS - 1]              # up to the call its lagging node owes, not past it
        wall[0] += OWED_GRACE / 2
        participant._on_clock(_clock(120 * MS))       # the simulator's repeated /clock while it waits
        assert reports[-1] == 100 * MS - 1
        lagging[0] = False                             # the node's /clock came: the call is due by its clock
        participant._report_withheld()
        assert made == [100 * MS] and reports[-1] == 120 * MS
        participant._on_clock(_clock(210 * MS))       # due and its clock is there: made at once, no wait
        assert made == [100 * MS, 200 * MS] and reports[-1] == 210 * MS
        lagging[0] = True                              # a node clock that stays behind
        participant._on_clock(_clock(320 * MS))
        assert reports[-1] == 300 * MS - 1
        wall[0] += OWED_GRACE + 0.01
        participant._on_clock(_clock(320 * MS))
        assert made == [100 * MS, 200 * MS]           # never made ahead of its own clock
        assert reports[-1] == 320 * MS                 # and the world goes on
    finally:
        participant.destroy()
        node.destroy_node()


def test_a_sim_time_timer_is_called_by_its_clock_and_owes_nothing_after(ros_context: Any) -> None:
    """No executor spins here: the clock's move to the due slot makes the call, so run_overdue (the
    participant's rescue for an executor-driven timer) finds nothing left to make."""
    sim_time = [Parameter("use_sim_time", value=True)]
    node = Node("overdue_probe", context=ros_context, parameter_overrides=sim_time)
    clock = node.get_clock()
    calls: list[int] = []

    def cycle() -> None:
        calls.append(clock.now().nanoseconds)

    clock.set_ros_time_override(Time(nanoseconds=10 * MS, clock_type=clock.clock_type))
    timer = timers.create_periodic_timer(node, 0.1, cycle)
    try:
        assert timers.earliest_due_ns(ros_context) == 110 * MS
        clock.set_ros_time_override(Time(nanoseconds=60 * MS, clock_type=clock.clock_type))
        assert calls == []                                            # not due before 110 ms
        clock.set_ros_time_override(Time(nanoseconds=110 * MS, clock_type=clock.clock_type))
        assert calls == [110 * MS]
        assert timers.earliest_due_ns(ros_context) == 210 * MS      # one period on, as rcl moves it
        assert timers.run_overdue(110 * MS, ros_context) == []       # made once
        timer.cancel()
        clock.set_ros_time_override(Time(nanoseconds=400 * MS, clock_type=clock.clock_type))
        assert calls == [110 * MS]                                    # a canceled timer is not called
        assert timers.earliest_due_ns(ros_context) is None           # and owes nothing
    finally:
        node.destroy_node()
