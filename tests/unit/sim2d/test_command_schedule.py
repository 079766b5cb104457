"""Stamped commands take effect at stamp + delay, whenever they arrive (sim2d/core/command_schedule.py).

The point of issue 17: the same command sequence, arriving at different moments of the lockstep
window, must move the robot the same way. The last test drives the core simulator twice with the
same stamped commands delivered at different sim times and asserts identical trajectories; applied
on arrival (the old behaviour) they differ.
"""

from __future__ import annotations

import numpy as np
import pytest

from sim2d.core.command_schedule import CommandSchedule
from sim2d.core.robot import robot_model
from sim2d.core.simulator import SimParams, Simulator
from sim2d.core.world import load_world

MS = 1_000_000  # ns


def test_a_command_waits_for_its_stamp_plus_delay() -> None:
    schedule = CommandSchedule(100 * MS)
    assert schedule.add(50 * MS, 0.2, 0.1, now_ns=60 * MS) == 150 * MS
    assert schedule.due(145 * MS) == []
    (command,) = schedule.due(150 * MS)
    assert (command.v, command.w) == (0.2, 0.1)
    assert schedule.late == 0 and len(schedule) == 0


def test_commands_come_out_in_stamp_order_and_ties_in_arrival_order() -> None:
    schedule = CommandSchedule(10 * MS)
    schedule.add(20 * MS, 2.0, 0.0, now_ns=0)
    schedule.add(10 * MS, 1.0, 0.0, now_ns=0)
    schedule.add(20 * MS, 3.0, 0.0, now_ns=0)
    assert [c.v for c in schedule.due(30 * MS)] == [1.0, 2.0, 3.0]


def test_a_late_command_applies_at_once_and_is_counted() -> None:
    schedule = CommandSchedule(50 * MS)
    assert schedule.add(0, 0.3, 0.0, now_ns=80 * MS) == 80 * MS
    assert schedule.late == 1 and schedule.worst_late_ns == 30 * MS
    assert len(schedule.due(80 * MS)) == 1


def test_clear_and_bad_delay() -> None:
    schedule = CommandSchedule(0)
    schedule.add(0, 1.0, 0.0, now_ns=0)
    schedule.clear()
    assert schedule.due(10**12) == []
    with pytest.raises(ValueError, match="delay"):
        CommandSchedule(-1)


def _drive(arrival_lag_ns: list[int], scheduled: bool) -> list[tuple[float, float, float]]:
    """Command k (stamped k * 50 ms) reaches the sim ``arrival_lag_ns[k]`` after its stamp."""
    sim = Simulator(load_world("turtlebot3_world"), robot_model("waffle"), SimParams(),
                    np.random.default_rng(0))
    schedule = CommandSchedule(100 * MS)
    commands = [(k * 50 * MS, 0.2, 0.5 if (k // 10) % 2 else -0.5) for k in range(40)]
    poses = []
    pending = sorted((stamp + lag, stamp, v, w)
                     for (stamp, v, w), lag in zip(commands, arrival_lag_ns, strict=True))
    while sim.time_ns < 2_200 * MS:
        while pending and pending[0][0] <= sim.time_ns:     # arrivals, as the node's callback sees them
            _, stamp, v, w = pending.pop(0)
            if scheduled:
                schedule.add(stamp, v, w, sim.time_ns)
            else:
                sim.command(v, w)
        for command in schedule.due(sim.time_ns):           # what Sim2dNode._step does before a step
            sim.command(command.v, command.w)
        sim.step()
        poses.append((sim.pose.x, sim.pose.y, sim.pose.yaw))
    assert schedule.late == 0
    return poses


def test_the_trajectory_does_not_depend_on_when_commands_arrive() -> None:
    rng = np.random.default_rng(7)
    early = [0] * 40
    jittered = [int(lag) * 5 * MS for lag in rng.integers(0, 11, size=40)]  # 0 to 50 ms: one lockstep lead
    assert _drive(early, scheduled=True) == _drive(jittered, scheduled=True)
    assert _drive(early, scheduled=False) != _drive(jittered, scheduled=False)   # the old behaviour
