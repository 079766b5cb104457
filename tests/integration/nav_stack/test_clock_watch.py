"""ClockWatch: a node on sim time whose /clock stops while it is busy says so once, in wall time,
and says when the clock runs again; an idle node says nothing."""

from __future__ import annotations

import re

import pytest

pytest.importorskip("rosgraph_msgs.msg")

from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock

from nav_stack.ros.common.clock_watch import ClockWatch
from navsuite_testing.ros import spin_until

pytestmark = pytest.mark.ros


def _clock(seconds: int) -> Clock:
    msg = Clock()
    msg.clock.sec = seconds
    return msg


def test_a_stopped_clock_is_reported_while_busy_and_its_return_too(ros_context, capfd):
    node = Node("clock_watch_probe", context=ros_context,
                parameter_overrides=[Parameter("use_sim_time", value=True)])
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    publisher = node.create_publisher(Clock, "/clock", 10)
    try:
        publisher.publish(_clock(5))
        spin_until(executor, lambda: node.get_clock().now().nanoseconds == 5_000_000_000, 20.0,
                   "the node clock to read /clock")
        busy = ClockWatch(node, lambda: True, "navigation", timeout=2.0)
        idle = ClockWatch(node, lambda: False, "nothing", timeout=2.0)
        spin_until(executor, lambda: busy.still_for >= 2.0, 20.0, "the busy watch to count 2 s")
        publisher.publish(_clock(6))
        spin_until(executor, lambda: busy.still_for == 0.0, 20.0, "the busy watch to see the clock move")
        assert idle.still_for == 0.0
    finally:
        executor.shutdown()
        node.destroy_node()
    err = capfd.readouterr().err
    assert err.count("navigation waits on simulated time, and /clock has not advanced for 2 s") == 1
    assert "is the simulator paused, stopped or gone?" in err
    assert re.search(r"/clock runs again after \d+ s \(wall\)", err)
    assert "nothing waits on simulated time" not in err
