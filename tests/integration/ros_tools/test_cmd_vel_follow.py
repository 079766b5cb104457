"""CmdVelPublisher(stamped=None) publishes the type the robot's cmd_vel subscription takes.

nav-bringup's simulator takes TwistStamped in lockstep, and a tool run by hand beside it (nav-teleop,
a state machine) is not told: it must find out from the graph, or every command is silently lost
(a subscriber of the other type gets nothing).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
import rclpy
from geometry_msgs.msg import Twist, TwistStamped
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from navsuite_testing.ros import spin_until
from ros_tools.cmd_vel import CMD_VEL_QOS, CmdVelPublisher, subscribers_take_stamped

pytestmark = pytest.mark.ros


@pytest.fixture
def robot_context() -> Iterator[Context]:
    """The robot's own context (its own DDS participant, as another process: DDS refuses two types on
    one topic within one participant)."""
    context = Context()
    rclpy.init(context=context)
    try:
        yield context
    finally:
        rclpy.try_shutdown(context=context)


@pytest.mark.parametrize("robot_type", [TwistStamped, Twist])
def test_an_unset_publisher_follows_the_robots_type(ros_context: Any, robot_context: Context,
                                                     robot_type: type) -> None:
    robot = Node("robot", context=robot_context)
    tool = Node("tool", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    robot_executor = SingleThreadedExecutor(context=robot_context)
    executor.add_node(tool)
    robot_executor.add_node(robot)
    received: list[Any] = []
    robot.create_subscription(robot_type, "cmd_vel", received.append, CMD_VEL_QOS)
    try:
        cmd = CmdVelPublisher(tool, None)
        spin_until(executor, lambda: subscribers_take_stamped(tool) is not None, 10.0,
                   "the robot's subscription")
        assert subscribers_take_stamped(tool) is (robot_type is TwistStamped)

        def sent() -> bool:
            cmd.publish(0.1, 0.2, stamp_ns=1_500_000_000)
            robot_executor.spin_once(timeout_sec=0.01)
            return bool(received)
        spin_until(executor, sent, 10.0, "a command of the robot's type")
        assert cmd.stamped is (robot_type is TwistStamped)
        twist = received[-1].twist if robot_type is TwistStamped else received[-1]
        assert (twist.linear.x, twist.angular.z) == pytest.approx((0.1, 0.2))
        if robot_type is TwistStamped:
            assert (received[-1].header.stamp.sec, received[-1].header.stamp.nanosec) == (1, 500_000_000)
    finally:
        executor.shutdown()
        robot_executor.shutdown()
        tool.destroy_node()
        robot.destroy_node()


def test_a_set_publisher_keeps_its_type(ros_context: Any, robot_context: Context) -> None:
    tool = Node("tool", context=ros_context)
    robot = Node("robot", context=robot_context)
    robot.create_subscription(TwistStamped, "cmd_vel", lambda _m: None, CMD_VEL_QOS)
    try:
        cmd = CmdVelPublisher(tool, False)
        cmd.publish(0.1, 0.0)
        cmd.follow_subscribers()
        assert cmd.stamped is False    # Nav2's parameter, when given, is obeyed
    finally:
        tool.destroy_node()
        robot.destroy_node()
