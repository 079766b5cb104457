"""The SLAM system run's observer: ground truth against slam/pose, collisions, AMCL's pose, TF and a
NavigateToPose client, on one node spun in a background thread and taking part in sim2d's lockstep.

Shared by tests/system/test_slam_exploration.py (which asserts on what it gathers) and
bench/bench_slam_system.py (which records the pose error of an exploration run).
"""

from __future__ import annotations

import itertools
import math
from collections import deque
from typing import Any

from geometry_msgs.msg import PointStamped, PoseWithCovarianceStamped
from nav2_msgs.action import NavigateToPose
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import UInt32

from nav_stack.ros.common.qos import LATCHED
from navsuite_testing.ros import BackgroundSpin
from ros_tools.runtime.actions import ActionClient
from ros_tools.runtime.lockstep import LockstepParticipant
from ros_tools.tf.ros import TransformListener

#: The probe's lockstep role: a run that should wait for it lists it among sim2d's participants.
PROBE_ROLE = "slam_system_probe"


class Probe:
    """Ground truth vs slam/pose (errors), collision count, and a NavigateToPose client; spun in a thread."""

    def __init__(self, context: Any) -> None:
        self.node = Node("slam_system_probe", context=context)
        self.truth: tuple[float, float, float] | None = None  # t, x, y
        self._recent_truth: deque[tuple[float, float, float]] = deque(maxlen=400)  # ~13 s at 30 Hz
        self.errors: list[float] = []
        self.collisions: list[int] = []
        self.contacts: list[str] = []  # where each new collision happened, for the failure message
        self.node.create_subscription(Odometry, "/ground_truth", self._on_truth, 10)
        self.node.create_subscription(PoseWithCovarianceStamped, "/slam/pose", self._on_pose, LATCHED)
        self.node.create_subscription(UInt32, "/sim2d/collision_count", self._on_collision_count, LATCHED)
        self.node.create_subscription(PointStamped, "/sim2d/collisions", self._on_contact, 10)
        self.amcl_poses: list[PoseWithCovarianceStamped] = []
        self.node.create_subscription(PoseWithCovarianceStamped, "/amcl_pose", self.amcl_poses.append,
                                      LATCHED)
        self.navigate = ActionClient(self.node, NavigateToPose, "navigate_to_pose")
        # In lockstep, so that it sees every ground-truth pose however loaded the machine is.
        self.lockstep = LockstepParticipant(self.node, PROBE_ROLE)
        # Made before the executor spins, destroyed after: a subscription destroyed while another
        # thread builds its wait set kills that thread (rclpy's InvalidHandle).
        self.tf = TransformListener(self.node)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        self._spin = BackgroundSpin(self.executor, "slam probe")

    def _on_truth(self, msg: Odometry) -> None:
        stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        self.truth = (stamp, msg.pose.pose.position.x, msg.pose.pose.position.y)
        self._recent_truth.append(self.truth)

    def truth_at(self, stamp: float) -> tuple[float, float] | None:
        """Ground-truth position (m) at ``stamp`` (sim s), interpolated; None outside what was received.

        The SLAM pose is stamped with its scan, and arrives after the scan is processed, when the
        newest ground truth is already later: comparing with that one would add up to 0.26 m/s times
        the gap to the error being measured.
        """
        for (t0, x0, y0), (t1, x1, y1) in itertools.pairwise(list(self._recent_truth)):
            if t0 <= stamp <= t1:
                k = (stamp - t0) / (t1 - t0) if t1 > t0 else 0.0
                return x0 + k * (x1 - x0), y0 + k * (y1 - y0)
        return None

    def _on_collision_count(self, msg: UInt32) -> None:
        self.collisions.append(msg.data)

    def _on_contact(self, msg: PointStamped) -> None:
        robot = "unknown" if self.truth is None else f"({self.truth[1]:.2f}, {self.truth[2]:.2f})"
        stamp = msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9
        self.contacts.append(f"t={stamp:.1f} s contact ({msg.point.x:.2f}, {msg.point.y:.2f}) robot {robot}")

    def _on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        truth = self.truth_at(msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9)
        if truth is not None:
            p = msg.pose.pose.position
            self.errors.append(math.hypot(p.x - truth[0], p.y - truth[1]))

    def close(self) -> None:
        self._spin.stop()  # first: nothing may be destroyed under a spinning thread
        self.lockstep.destroy()
        self.tf.destroy()
        self.node.destroy_node()
