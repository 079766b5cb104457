"""`python -m sim2d.ros.cli` as a child process publishes /clock at the requested pose and speed."""

from __future__ import annotations

import math
from typing import Any

import pytest
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from navsuite_testing.ros import spin_until, start_python, stop_process

pytestmark = pytest.mark.ros


def test_cli_runs_the_node_with_flags(ros_context: Any) -> None:
    pytest.importorskip("tf2_msgs.msg")
    proc = start_python("sim2d.ros.cli", ["--world", "turtlebot3_world", "--robot", "burger", "--rtf", "5",
                                          "--x", "-1.0", "--y", "-0.5", "--yaw", "0.5"])
    node = Node("cli_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    truth: list[Odometry] = []
    node.create_subscription(Odometry, "/ground_truth", truth.append, 10)
    try:

        def stepped() -> bool:
            """Ground truth of a sim that has stepped: Fast DDS's shared-memory transport can hand a
            new reader the stamp-0 sample of an earlier, dead sim2d of this domain while this one
            is still importing."""
            stamp = truth[-1].header.stamp if truth else None
            return stamp is not None and (stamp.sec, stamp.nanosec) > (0, 0)

        spin_until(executor, lambda: stepped() or proc.poll() is not None, 30.0, "ground truth of a live sim")
        assert proc.poll() is None, stop_process(proc)
        pose = truth[-1].pose.pose
        assert (pose.position.x, pose.position.y) == pytest.approx((-1.0, -0.5))
        assert 2.0 * math.atan2(pose.orientation.z, pose.orientation.w) == pytest.approx(0.5)
    finally:
        executor.shutdown()
        node.destroy_node()
        output = stop_process(proc)
    assert "robot burger" in output
