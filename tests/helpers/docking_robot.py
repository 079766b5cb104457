"""A fake kinematic robot for docking_server's integration test: it owns /clock and the robot's TF.

Every TICK_WALL_S of wall time it advances sim time by ``step`` s (``step / TICK_WALL_S`` times real
time) and publishes /clock, odom→base_link on /tf (map→odom once on /tf_static), the dock's tag as
``detected_dock_pose`` in ``base_link`` (tests.helpers.docking_world.tag_pose_for: the SimpleChargingDock
convention) unless ``hidden``, and ``battery_state``: CHARGING with 1 A while base_link is within
CHARGE_RADIUS of the dock pose, else DISCHARGING with -0.5 A. It integrates cmd_vel (Twist) as a
unicycle, keeps a command CMD_TIMEOUT_S of sim time (sim2d's 0.5 s) and is held at the dock's face
(it cannot pass the dock pose along the dock's heading), as a physical dock holds a robot.
"""

from __future__ import annotations

import math
import threading
from typing import Any

from geometry_msgs.msg import PoseStamped, Twist
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rosgraph_msgs.msg import Clock as ClockMsg
from sensor_msgs.msg import BatteryState

from nav_stack.core.docking import SimpleChargingDockParams
from nav_stack.core.docking.spatial import compose, inverse
from nav_stack.core.geometry import Pose2D
from ros_tools.cmd_vel import CMD_VEL_QOS
from ros_tools.tf import Transform
from ros_tools.tf.ros import StaticTransformBroadcaster, TransformBroadcaster, transform_to_msg
from tests.helpers.docking_world import pose3d, tag_pose_for

TICK_WALL_S = 0.01
CMD_TIMEOUT_S = 0.5
CHARGE_RADIUS = 0.02


def _stamp(seconds: float) -> Any:
    from builtin_interfaces.msg import Time

    whole = int(seconds)
    return Time(sec=whole, nanosec=round((seconds - whole) * 1e9) % 1_000_000_000)


class FakeDockingRobot(Node):
    """See the module docstring. ``robot`` and ``dock`` are in odom; ``map_to_odom`` places odom in map."""

    def __init__(self, robot: Pose2D, dock: Pose2D, map_to_odom: Pose2D, tag: SimpleChargingDockParams,
                 step: float = 0.04, start_s: float = 100.0, **kwargs: Any) -> None:
        super().__init__("fake_docking_robot", **kwargs)
        self.robot, self.dock, self.tag, self.step_s = robot, dock, tag, step
        self.sim_s = start_s
        self.hidden = False
        self.commands: list[tuple[float, float]] = []
        self._command = (0.0, 0.0)
        self._command_s = -math.inf
        self._lock = threading.Lock()
        self._clock_pub = self.create_publisher(ClockMsg, "/clock", 10)
        self._tf = TransformBroadcaster(self)
        self._tf_static = StaticTransformBroadcaster(self)
        odom_in_map = Transform.from_xy_yaw(*map_to_odom)
        self._tf_static.send([transform_to_msg(odom_in_map, "map", "odom", _stamp(0.0))])
        self._detection = self.create_publisher(PoseStamped, "detected_dock_pose", 10)
        self._battery = self.create_publisher(BatteryState, "battery_state", 10)
        self.create_subscription(Twist, "cmd_vel", self._on_cmd_vel, CMD_VEL_QOS)
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        self._timer = self.create_timer(TICK_WALL_S, self._tick, clock=wall)

    def _on_cmd_vel(self, msg: Twist) -> None:
        with self._lock:
            self._command, self._command_s = (msg.linear.x, msg.angular.z), self.sim_s
            self.commands.append(self._command)

    def distance_to_dock(self) -> float:
        return math.hypot(self.robot.x - self.dock.x, self.robot.y - self.dock.y)

    def _move(self, dt: float) -> None:
        with self._lock:
            v, w = self._command if self.sim_s - self._command_s <= CMD_TIMEOUT_S else (0.0, 0.0)
        x, y, yaw = self.robot
        moved = Pose2D(x + v * dt * math.cos(yaw), y + v * dt * math.sin(yaw), yaw + w * dt)
        c, s = math.cos(self.dock.yaw), math.sin(self.dock.yaw)
        ahead = (moved.x - self.dock.x) * c + (moved.y - self.dock.y) * s
        if ahead > 0.0 and math.hypot(moved.x - self.dock.x, moved.y - self.dock.y) < 0.15:
            moved = Pose2D(moved.x - ahead * c, moved.y - ahead * s, moved.yaw)  # against the dock's face
        self.robot = moved

    def _tick(self) -> None:
        self._move(self.step_s)
        self.sim_s += self.step_s
        stamp = _stamp(self.sim_s)
        self._clock_pub.publish(ClockMsg(clock=stamp))
        self._tf.send([transform_to_msg(Transform.from_xy_yaw(*self.robot), "odom", "base_link", stamp)])
        if not self.hidden:
            seen = compose(inverse(pose3d(self.robot)), tag_pose_for(self.dock, self.tag))
            msg = PoseStamped()
            msg.header.frame_id, msg.header.stamp = "base_link", stamp
            msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = seen.x, seen.y, seen.z
            o = msg.pose.orientation
            o.x, o.y, o.z, o.w = seen.qx, seen.qy, seen.qz, seen.qw
            self._detection.publish(msg)
        charging = self.distance_to_dock() < CHARGE_RADIUS
        battery = BatteryState(current=1.0 if charging else -0.5, percentage=0.5, present=True)
        battery.header.stamp = stamp
        battery.power_supply_status = (BatteryState.POWER_SUPPLY_STATUS_CHARGING if charging
                                       else BatteryState.POWER_SUPPLY_STATUS_DISCHARGING)
        self._battery.publish(battery)
