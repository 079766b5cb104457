"""nav-teleop (the keyboard teleop used to drive SLAM runs): key semantics and what --keys publishes."""

from __future__ import annotations

from typing import Any

import pytest
from geometry_msgs.msg import Twist, TwistStamped
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from nav_stack.ros.tools.teleop import LIMITS, TeleopState
from navsuite_testing.ros import spin_until, start_python, stop_process


def test_keys_step_clamp_and_stop() -> None:
    state = TeleopState(*LIMITS["waffle"])
    for _ in range(40):
        state.press("w")
    assert state.linear == 0.26
    for _ in range(30):
        state.press("d")
    assert state.angular == -1.82
    assert not state.press("z") and (state.linear, state.angular) == (0.26, -1.82)
    state.press(" ")
    assert (state.linear, state.angular) == (0.0, 0.0)


def _replay(context: Any, keys: str, stamped: bool) -> list[tuple[float, float]]:
    node = Node("teleop_probe", context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    received: list[tuple[float, float]] = []

    def on_cmd(msg: Any) -> None:
        twist = msg.twist if stamped else msg
        received.append((round(twist.linear.x, 3), round(twist.angular.z, 3)))

    node.create_subscription(TwistStamped if stamped else Twist, "/cmd_vel", on_cmd, 10)
    ros_args = ["--ros-args", "-p", "enable_stamped_cmd_vel:=true"] if stamped else []
    proc = start_python("nav_stack.ros.tools.teleop", ["--keys", keys, "--period", "0.05", *ros_args])
    try:
        spin_until(executor, lambda: proc.poll() is not None, 30.0, "nav-teleop to finish")
        spin_until(executor, lambda: len(received) >= len(keys) + 1, 5.0, "every command")
    finally:
        output = stop_process(proc)
        executor.shutdown()
        node.destroy_node()
    assert proc.returncode == 0, output
    return received


@pytest.mark.ros
def test_keys_mode_publishes_each_command_then_stops(ros_context: Any) -> None:
    received = _replay(ros_context, "wwwad", stamped=False)
    assert received == [(0.01, 0.0), (0.02, 0.0), (0.03, 0.0), (0.03, 0.1), (0.03, 0.0), (0.0, 0.0)]


@pytest.mark.ros
def test_keys_mode_publishes_twist_stamped_when_enabled(ros_context: Any) -> None:
    assert _replay(ros_context, "xa", stamped=True) == [(-0.01, 0.0), (-0.01, 0.1), (0.0, 0.0)]
