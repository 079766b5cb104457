"""A lockstep participant waits for a sim-time timer due at its tick, but not for ever.

The report of tick T waits until the process's timers due at or before T have run
(ros_tools/runtime/timers.py, earliest_due_ns), so the simulator never steps past a cycle still to
come. A timer whose wake-up the executor missed must not stop the world: after OWED_GRACE wall
seconds the tick counts as done (CI run 6: nav2 stopped reporting and a patrol hung).
"""

from __future__ import annotations

from typing import Any

import pytest
from rclpy.node import Node
from rosgraph_msgs.msg import Clock

from ros_tools.runtime import lockstep
from ros_tools.runtime.lockstep import OWED_GRACE, LockstepParticipant

pytestmark = pytest.mark.ros
MS = 1_000_000


def _clock(ns: int) -> Clock:
    msg = Clock()
    msg.clock.sec, msg.clock.nanosec = divmod(ns, 1_000_000_000)
    return msg


def test_a_tick_waits_for_its_due_timer_then_counts_as_done_after_the_grace(
        ros_context: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    node = Node("owed_probe", context=ros_context)
    participant = LockstepParticipant(node, "owed_probe")
    reports: list[int] = []
    monkeypatch.setattr(participant, "_report", lambda ns: (reports.append(ns),
                                                            setattr(participant, "_last_report_ns", ns)))
    due = [100 * MS]
    monkeypatch.setattr(lockstep.timers, "earliest_due_ns", lambda _context=None: due[0])
    wall = [50.0]
    monkeypatch.setattr(lockstep.time, "monotonic", lambda: wall[0])
    try:
        participant._on_clock(_clock(120 * MS))
        assert reports == [100 * MS - 1]              # up to the owed call, not past it
        wall[0] += OWED_GRACE / 2
        participant._on_clock(_clock(120 * MS))       # the simulator's repeated /clock while it waits
        assert reports[-1] == 100 * MS - 1
        due[0] = 150 * MS                              # the timer ran: its next call lies ahead
        participant._report_withheld()
        assert reports[-1] == 120 * MS
        due[0] = 140 * MS                              # the next call is due and never comes
        participant._on_clock(_clock(160 * MS))
        assert reports[-1] == 140 * MS - 1
        wall[0] += OWED_GRACE + 0.01
        participant._on_clock(_clock(160 * MS))
        assert reports[-1] == 160 * MS                 # the world goes on
    finally:
        participant.destroy()
        node.destroy_node()
