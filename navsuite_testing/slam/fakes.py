"""A fake robot for the slam node's in-process tests: TF and LaserScans from the analytic hexagon room.

The robot "teleports" along ground-truth poses: each ``step()`` publishes odom → base_footprint on
/tf and then a scan from the pose (exact analytic lidar of navsuite_testing/slam/world.py, seeded
noise) with the same stamp, so the node always finds the odometry of a scan. Stamps advance by
SCAN_PERIOD per step on a fake timeline, independent of the wall clock. Odometry starts at the
origin of ``odom`` (as sim2d's does), so map → odom equals the start pose when nothing drifts.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from builtin_interfaces.msg import Time
from rclpy.node import Node
from sensor_msgs.msg import LaserScan as LaserScanMsg

from nav_stack.core.geometry import Pose2D, compose
from nav_stack.core.grid import GridSpec
from nav_stack.core.slam import inverse
from nav_stack.ros.common.qos import DEFAULT
from navsuite_testing.slam.world import World, hexagon_world, interpolate
from ros_tools.tf import Transform
from ros_tools.tf.ros import StaticTransformBroadcaster, TransformBroadcaster, transform_to_msg

START = Pose2D(-2.0, -0.5, 0.0)
LASER_X = -0.064  # m, waffle base_footprint → base_scan (z ignored)
SCAN_PERIOD = 0.2  # s of fake time per step (LDS-01 at 5 Hz)
TRUTH_SPEC = GridSpec(130, 110, 0.05, -3.25, -2.75)  # covers the hexagon room


def stamp(seconds: float) -> Time:
    whole = math.floor(seconds)
    return Time(sec=int(whole), nanosec=round((seconds - whole) * 1e9))


def tour(world: World) -> list[Pose2D]:
    """A look around at the start, then through the room past four pillars (0.1 m steps)."""
    spin = [Pose2D(START.x, START.y, 0.3 * k) for k in range(22)]
    goals = [Pose2D(-0.55, -0.55, 0.0), Pose2D(0.55, -1.6, 0.0), Pose2D(1.6, 0.0, 0.0),
             Pose2D(0.55, 1.6, 0.0), Pose2D(-1.6, 0.4, 0.0)]
    out = list(spin)
    for goal in goals:
        out += interpolate(world.path(TRUTH_SPEC, out[-1], goal, 0.3), 0.1)[1:]
    return out


class FakeRobot(Node):
    """Publishes the static laser mount once, then TF + scan per ``step(pose)``."""

    def __init__(self, seed: int = 0, **kwargs: Any) -> None:
        super().__init__("fake_slam_robot", **kwargs)
        self.world = hexagon_world()
        self.rng = np.random.default_rng(seed)
        self.time = 100.0  # s on the fake timeline
        self.odom_origin = START  # where odom's origin lies in the world (no drift: map→odom = START)
        self.scan_pub = self.create_publisher(LaserScanMsg, "/scan", DEFAULT)
        self.tf = TransformBroadcaster(self)
        self.tf_static = StaticTransformBroadcaster(self)
        self.tf_static.send([transform_to_msg(Transform(LASER_X, 0.0, 0.122), "base_footprint", "base_scan",
                                              stamp(0.0))])
        self.sent: list[tuple[Pose2D, LaserScanMsg]] = []  # (odometry pose, scan) of every step

    def step(self, pose: Pose2D, before_scan: Callable[[float], None] | None = None,
             scan_first: bool = False) -> float:
        """Publish the robot at world ``pose``: its odometry TF, then ``before_scan(stamp)`` if given
        (e.g. to wait until the node has that TF), then the scan; returns the stamp (s) used.
        ``scan_first`` sends the scan before its odometry instead (the node must wait for it)."""
        self.time += SCAN_PERIOD
        odom = compose(inverse(self.odom_origin), pose)
        when = stamp(self.time)
        odom_msg = transform_to_msg(Transform.from_xy_yaw(*odom), "odom", "base_footprint", when)
        if not scan_first:
            self.tf.send([odom_msg])
        if before_scan is not None:
            before_scan(self.time)
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        sensor = Pose2D(pose.x + c * LASER_X, pose.y + s * LASER_X, pose.yaw)
        scan = self.world.scan(sensor, noise_std=0.01, rng=self.rng)
        msg = LaserScanMsg()
        msg.header.frame_id, msg.header.stamp = "base_scan", when
        msg.angle_min, msg.angle_increment = scan.angle_min, scan.angle_increment
        msg.angle_max = scan.angle_min + scan.angle_increment * (len(scan.ranges) - 1)
        msg.range_min, msg.range_max = scan.range_min, scan.range_max
        msg.ranges = [float(r) for r in scan.ranges]
        self.scan_pub.publish(msg)
        if scan_first:
            self.tf.send([odom_msg])
        self.sent.append((odom, msg))
        return self.time
