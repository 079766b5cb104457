"""The slam node's in-process observer: a probe node on slam/pose, /map and the node's services, and
the lockstep drive that feeds the fake robot's tour to the node one scan at a time.

Shared by tests/integration/nav_stack/test_slam_node.py and bench/bench_slam_system.py (time per
scan): both need every scan processed in order, so each step waits for the node's pose of that stamp
(the node keeps one scan in its mailbox and would drop the rest).
"""

from __future__ import annotations

import functools
from typing import Any

from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.srv import SaveMap
from nav_msgs.msg import OccupancyGrid
from rclpy.node import Node
from std_srvs.srv import SetBool

from nav_stack.ros.common.qos import LATCHED
from nav_stack.ros.slam.slam_node import SlamNode
from navsuite_testing.ros import wait_until
from navsuite_testing.slam.fakes import FakeRobot
from ros_tools.tf.buffer import TransformError


class Probe(Node):
    """Collects slam/pose and /map; calls the node's services."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__("slam_probe", **kwargs)
        self.poses: list[PoseWithCovarianceStamped] = []
        self.maps: list[OccupancyGrid] = []
        self.create_subscription(PoseWithCovarianceStamped, "/slam/pose", self.poses.append, LATCHED)
        self.create_subscription(OccupancyGrid, "/map", self.maps.append, LATCHED)
        self.save = self.create_client(SaveMap, "/slam/save_map")
        self.pause = self.create_client(SetBool, "/slam/pause_new_measurements")

    def stamps(self) -> list[float]:
        return [p.header.stamp.sec + p.header.stamp.nanosec * 1e-9 for p in self.poses]

    def call(self, client: Any, request: Any) -> Any:
        wait_until(client.service_is_ready, 10.0, f"service {client.srv_name}")
        future = client.call_async(request)
        wait_until(future.done, 30.0, f"response of {client.srv_name}")
        return future.result()


def drive(robot: FakeRobot, probe: Probe, poses: list[Any], slam: SlamNode) -> None:
    """Publish each pose and wait for the node's pose of that scan. The scan goes out only once the
    node has the odometry TF at its stamp: it drops a scan whose TF is 0.3 s late, which happened in
    loaded CI runs."""

    def has_odometry(t: float) -> bool:
        try:
            slam.tf.lookup("odom", "base_footprint", t)
        except TransformError:
            return False
        return True

    def node_has_odometry(t: float) -> None:
        wait_until(lambda: has_odometry(t), 10.0, f"the slam node's odometry TF at {t:.1f} s")

    def has_pose_of_scan(t: float) -> bool:
        return any(abs(s - t) < 1e-6 for s in probe.stamps()[-3:])

    for pose in poses:
        t = robot.step(pose, before_scan=node_has_odometry)
        wait_until(functools.partial(has_pose_of_scan, t), 10.0, f"slam/pose of the scan at {t:.1f} s")
