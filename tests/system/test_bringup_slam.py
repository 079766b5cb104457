"""Nav2's "navigation with SLAM" workflow: `nav-bringup --slam` runs SLAM instead of map_server + AMCL,
publishes a growing /map in the world's frame, and NavigateToPose succeeds on it."""

from __future__ import annotations

import math

import pytest

from navsuite_testing.ros import spin_until, spinning
from tests.helpers.nav_ros_bt_stack import READY, Bringup

pytestmark = [pytest.mark.ros, pytest.mark.slow]


def test_slam_bringup_maps_and_navigates_on_the_growing_map(ros_context):
    import rclpy
    from action_msgs.msg import GoalStatus
    from nav2_msgs.action import NavigateToPose
    from nav_msgs.msg import OccupancyGrid, Odometry
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    from ros_tools.runtime.actions import ActionClient, send_until_acknowledged

    stack = Bringup("--slam")
    node = rclpy.create_node("slam_bringup_probe", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    try:
        stack.wait_for_line(READY, timeout=240.0)
        maps: list[OccupancyGrid] = []
        truth: list[Odometry] = []
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        node.create_subscription(OccupancyGrid, "/map", maps.append, latched)
        node.create_subscription(Odometry, "/ground_truth", truth.append, 10)
        spin_until(executor, lambda: bool(maps) and bool(truth), 60.0, "/map from SLAM and ground truth")
        first = maps[-1]
        assert sum(1 for v in first.data if v == 100) > 20, "the first SLAM map shows no walls"

        client = ActionClient(node, NavigateToPose, "navigate_to_pose")
        spin_until(executor, client.server_is_ready, 60.0, "navigate_to_pose")
        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = "map"
        goal.pose.pose.position.x, goal.pose.pose.position.y = -1.4, -0.5
        goal.pose.pose.orientation.w = 1.0
        sent = send_until_acknowledged(client, goal, 30.0, spinning(executor))
        result = sent.result().get_result_async()
        spin_until(executor, result.done, 240.0, "the navigation result")
        assert result.result().status == GoalStatus.STATUS_SUCCEEDED, stack.output()
        pose = truth[-1].pose.pose.position
        # The goal checker judges SLAM's estimate (xy_goal_tolerance 0.25 m, config/nav2_params.yaml); the
        # truth may be off by SLAM's pose error too (bench_slam: under 0.1 m). CI run CW: 0.323 m.
        assert math.hypot(pose.x + 1.4, pose.y + 0.5) < 0.25 + 0.1
        assert len(maps) >= 1 and maps[-1].header.frame_id == "map"
    finally:
        node.destroy_node()
        executor.shutdown()
        assert stack.stop() is not None
