"""behavior_server's assisted_teleop over DDS with a fake local costmap and robot: a teleop command
toward a wall is slowed, then stopped at the wall; preempt_teleop ends the goal with success and the
time allowance with TIMEOUT."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

pytest.importorskip("nav2_msgs.action")

from action_msgs.msg import GoalStatus
from builtin_interfaces.msg import Duration, Time
from geometry_msgs.msg import Point32, PolygonStamped, Twist
from nav2_msgs.action import AssistedTeleop
from nav2_msgs.msg import Costmap
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_msgs.msg import Empty

from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec
from nav_stack.ros.behaviors.behavior_server import build_nodes
from nav_stack.ros.common.conversions import costmap_msg
from nav_stack.ros.common.frames import FrameError
from nav_stack.ros.common.qos import LATCHED
from navsuite_testing.nav.world import Harness, get_result, send_goal
from navsuite_testing.ros import wait_until
from ros_tools.cmd_vel import CMD_VEL_QOS
from ros_tools.runtime.actions import ActionClient
from ros_tools.tf import Transform
from ros_tools.tf.ros import StaticTransformBroadcaster, transform_to_msg

pytestmark = pytest.mark.ros

SPEC = GridSpec(80, 40, 0.05, -0.5, -1.0)  # odom: x -0.5 .. 3.5, y -1 .. 1
SQUARE = ((0.1, 0.1), (0.1, -0.1), (-0.1, -0.1), (-0.1, 0.1))  # the robot outline, m


class FakeRobot(Node):
    """The local costmap (a wall across x = 1.00 .. 1.05 m), the robot's TF and outline, a teleop operator
    re-sending its command at 10 Hz, and what the behavior server sends on cmd_vel."""

    def __init__(self, context: Any) -> None:
        super().__init__("fake_robot", context=context)
        costs = np.zeros(SPEC.shape, dtype=np.uint8)
        costs[:, 30] = LETHAL_OBSTACLE
        self.create_publisher(Costmap, "local_costmap/costmap_raw", LATCHED).publish(
            costmap_msg(costs, SPEC, "odom", Time()))
        self.footprint_pub = self.create_publisher(PolygonStamped, "local_costmap/published_footprint",
                                                   LATCHED)
        self.tf_static = StaticTransformBroadcaster(self)
        self.place(0.0)
        self.teleop_pub = self.create_publisher(Twist, "cmd_vel_teleop", CMD_VEL_QOS)
        self.preempt_pub = self.create_publisher(Empty, "preempt_teleop", 10)
        self.teleop: Twist | None = None
        self.create_timer(0.1, self._send_teleop)
        self.cmd_vel: list[Twist] = []
        self.create_subscription(Twist, "cmd_vel", self.cmd_vel.append, CMD_VEL_QOS)

    def place(self, x: float) -> None:
        """Put the robot at (x, 0), heading +x: TF odom→base_link and the outline around it."""
        pose = Transform.from_xy_yaw(x, 0.0, 0.0)
        self.tf_static.send([transform_to_msg(pose, "odom", "base_link", Time())])
        footprint = PolygonStamped()
        footprint.header.frame_id = "odom"
        footprint.polygon.points = [Point32(x=x + px, y=py) for px, py in SQUARE]
        self.footprint_pub.publish(footprint)

    def drive(self, vx: float, wz: float = 0.0) -> None:
        self.teleop = Twist()
        self.teleop.linear.x, self.teleop.angular.z = vx, wz

    def _send_teleop(self) -> None:
        if self.teleop is not None:
            self.teleop_pub.publish(self.teleop)

    def heard(self, vx: float, wz: float = 0.0) -> bool:
        return any(abs(m.linear.x - vx) < 1e-9 and abs(m.angular.z - wz) < 1e-9 for m in self.cmd_vel)


class Rig:
    def __init__(self, context: Any) -> None:
        self.harness = Harness(context)
        self.robot = FakeRobot(context)
        self.server: Any = build_nodes(context=context, parameter_overrides=[
            Parameter("behavior_plugins", value=["spin", "assisted_teleop", "wait"])])[0]
        self.harness.add(self.robot, self.server)
        self.harness.bring_up(self.server)
        wait_until(lambda: self.server._grid is not None and self.server._footprint_msg is not None, 20.0,
                   "the local costmap and the footprint at the behavior server")
        wait_until(lambda: self.robot_x() == 0.0, 20.0, "TF odom→base_link at the behavior server")
        self.client = ActionClient(self.robot, AssistedTeleop, "assisted_teleop")

    def robot_x(self) -> float | None:
        try:
            return float(self.server.frames.robot_pose("odom").x)
        except FrameError:
            return None

    def start(self, allowance_s: int = 0) -> Any:
        return send_goal(self.client, AssistedTeleop.Goal(time_allowance=Duration(sec=allowance_s)))


@pytest.fixture
def rig(ros_context: Any) -> Iterator[Rig]:
    r: Rig | None = None
    try:
        r = Rig(ros_context)
        yield r
    finally:
        if r is not None:
            r.harness.close()


def test_a_command_toward_the_wall_is_slowed_and_preempt_ends_the_goal(rig: Rig) -> None:
    robot = rig.robot
    handle = rig.start()
    robot.drive(1.2, 0.5)  # the outline's nose reaches the wall 0.8 s ahead: 80 % of the command
    wait_until(lambda: robot.heard(1.2 * 0.8, 0.5 * 0.8), 10.0, "the slowed teleop command on cmd_vel")
    assert not robot.heard(1.2, 0.5)  # never forwarded unscaled
    robot.drive(0.5)  # clear for the whole projection: forwarded as it is
    wait_until(lambda: robot.heard(0.5), 10.0, "the unscaled teleop command on cmd_vel")
    robot.teleop = None
    wait_until(lambda: robot.preempt_pub.get_subscription_count() > 0, 10.0, "preempt_teleop matched")
    robot.preempt_pub.publish(Empty())
    status, result = get_result(handle, 10.0)
    assert (status, result.error_code) == (GoalStatus.STATUS_SUCCEEDED, 0)
    wait_until(lambda: robot.cmd_vel[-1].linear.x == 0.0, 5.0, "a stop after the goal")


def test_at_the_wall_the_command_is_stopped_and_the_time_allowance_ends_the_goal(rig: Rig) -> None:
    robot = rig.robot
    robot.place(0.88)  # nose 2 cm from the wall
    wait_until(lambda: rig.robot_x() == pytest.approx(0.88, abs=1e-9), 10.0, "the robot moved")
    handle = rig.start(allowance_s=4)
    robot.drive(0.5)
    wait_until(lambda: len(robot.cmd_vel) >= 5, 10.0, "commands on cmd_vel")
    assert all(m.linear.x == 0.0 for m in robot.cmd_vel)  # toward the wall: stopped at once
    robot.drive(-0.3)  # backing away is free
    wait_until(lambda: robot.heard(-0.3), 10.0, "the backing-away command on cmd_vel")
    status, result = get_result(handle, 10.0)
    assert (status, result.error_code) == (GoalStatus.STATUS_ABORTED, AssistedTeleop.Result.TIMEOUT)
    assert "time allowance" in result.error_msg
    elapsed = result.total_elapsed_time.sec + result.total_elapsed_time.nanosec * 1e-9
    assert elapsed > 4.0
