"""The fake stack's lockstep (tests/helpers/smacc_ros_fake_nav2.py): its clock waits for the named role,
as sim2d's does, so a loaded state machine cannot fall behind its odometry."""

from __future__ import annotations

from typing import Any

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Header

from navsuite_testing.ros import spin_until
from ros_tools.runtime.lockstep import PROGRESS_QOS, PROGRESS_TOPIC, participant_name
from tests.helpers.smacc_ros_fake_nav2 import START_S, TICK_S, FakeNav2

pytestmark = pytest.mark.ros
RATE = 10.0  # sim s per wall s when free
STEP_S = TICK_S * RATE


def test_the_clock_holds_until_the_role_reports_and_then_leads_it_by_one_tick(ros_context: Any) -> None:
    fake = FakeNav2(ros_context, bond_nodes=(), clock_rate=RATE, lockstep_roles=("Machine",)).start()
    probe = rclpy.create_node("lockstep_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(probe)
    clocks: list[float] = []
    probe.create_subscription(Clock, "/clock", lambda m: clocks.append(m.clock.sec + m.clock.nanosec * 1e-9),
                              10)
    progress = probe.create_publisher(Header, PROGRESS_TOPIC, PROGRESS_QOS)

    def report(sim_s: float) -> None:
        msg = Header(frame_id=participant_name("Machine"))
        msg.stamp.sec, msg.stamp.nanosec = int(sim_s), int((sim_s % 1.0) * 1e9)
        progress.publish(msg)

    try:
        spin_until(executor, lambda: len(clocks) >= 3, 10.0, "the held clock's re-sends")
        assert set(clocks) == {START_S}  # nobody reported: it re-sends the time it holds at
        for _ in range(5):  # each report of the newest time lets the clock move exactly one tick on
            newest = clocks[-1]
            report(newest)
            spin_until(executor, lambda newest=newest: clocks[-1] > newest, 10.0, "the clock's next tick")
            assert clocks[-1] == pytest.approx(newest + STEP_S, abs=1e-6)
        report(0.0)  # the role leaves: nothing holds the clock any more
        free_from = clocks[-1]
        spin_until(executor, lambda: clocks[-1] > free_from + 10 * STEP_S, 10.0, "the free clock")
    finally:
        fake.stop()
        probe.destroy_node()
