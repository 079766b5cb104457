"""A fake robot for amcl node tests: /map, static base_footprint→base_scan, odom TF and scans at 10 Hz.

The robot stands still at ``pose`` (map frame) with odom = map, so AMCL's map→odom should come out
as the identity. Scans are cast in the map by navsuite_testing.nav.fake_lidar (not by nav_stack), with
a few REP 117 readings (+inf no return, -inf too close) mixed in.
"""

from __future__ import annotations

import math

import numpy as np
from rclpy.node import Node
from sensor_msgs.msg import LaserScan

from nav_stack.core.map_io import load_map
from nav_stack.ros.common.conversions import occupancy_msg
from nav_stack.ros.common.qos import LATCHED
from navsuite_testing.localization.nodes import MAP_YAML
from navsuite_testing.nav.fake_lidar import cast_ranges
from ros_tools.tf.ros import StaticTransformBroadcaster, TransformBroadcaster, transform_to_msg
from ros_tools.tf.transform import Transform

LASER_OFFSET = (-0.064, 0.0)  # m, TB3 waffle base_footprint → base_scan
BEAMS = 360


class FakeRobot:
    """Publishes what sim2d would, for a robot parked at ``pose``."""

    def __init__(self, node: Node, pose: tuple[float, float, float] = (-2.0, -0.5, 0.0)) -> None:
        self.node = node
        self.pose = pose
        self.map = load_map(MAP_YAML)
        from nav_msgs.msg import OccupancyGrid

        self.map_pub = node.create_publisher(OccupancyGrid, "/map", LATCHED)
        self.scan_pub = node.create_publisher(LaserScan, "/scan", 10)
        self.tf = TransformBroadcaster(node)
        StaticTransformBroadcaster(node).send([transform_to_msg(
            Transform(LASER_OFFSET[0], LASER_OFFSET[1], 0.17), "base_footprint", "base_scan",
            node.get_clock().now().to_msg())])
        self.ranges = self._ranges()
        self.scans = 0
        self.timer = node.create_timer(0.1, self.publish)

    def publish_map(self) -> None:
        stamp = self.node.get_clock().now().to_msg()
        self.map_pub.publish(occupancy_msg(self.map.data, self.map.spec, "map", stamp))

    def _ranges(self) -> np.ndarray:
        x, y, yaw = self.pose
        lx = x + math.cos(yaw) * LASER_OFFSET[0] - math.sin(yaw) * LASER_OFFSET[1]
        ly = y + math.sin(yaw) * LASER_OFFSET[0] + math.cos(yaw) * LASER_OFFSET[1]
        angles = np.arange(BEAMS) * (2.0 * math.pi / BEAMS)
        ranges = cast_ranges(self.map.data, self.map.spec, (lx, ly, yaw), angles, 3.5,
                             noise_std=0.01, rng=np.random.default_rng(3))
        ranges[::45] = np.inf  # REP 117: no return
        ranges[7::90] = -np.inf  # REP 117: closer than range_min
        return ranges

    def publish(self) -> None:
        stamp = self.node.get_clock().now().to_msg()
        x, y, yaw = self.pose
        self.tf.send([transform_to_msg(Transform.from_xy_yaw(x, y, yaw), "odom", "base_footprint", stamp)])
        msg = LaserScan()
        msg.header.stamp = stamp
        msg.header.frame_id = "base_scan"
        msg.angle_min, msg.angle_increment = 0.0, 2.0 * math.pi / BEAMS
        msg.angle_max = msg.angle_increment * (BEAMS - 1)
        msg.range_min, msg.range_max = 0.12, 3.5
        msg.ranges = self.ranges.astype(np.float32).tolist()
        self.scan_pub.publish(msg)
        self.scans += 1
