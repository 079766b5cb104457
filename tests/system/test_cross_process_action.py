"""The installed interfaces work across processes: a NavigateToPose goal, its feedback and its
result travel over real DDS between this test process and a separate server process."""

from __future__ import annotations

import pytest

from navsuite_testing.ros import REPO, spin_until, spinning, start_python, stop_process
from tests.helpers.nav2_echo_server import ACTION_NAME

pytestmark = pytest.mark.ros


def test_navigate_to_pose_goal_feedback_and_result_cross_processes(ros_context):
    import rclpy
    from action_msgs.msg import GoalStatus
    from nav2_msgs.action import NavigateToPose
    from rclpy.executors import SingleThreadedExecutor

    from ros_tools.runtime.actions import ActionClient, send_until_acknowledged

    server = start_python(REPO / "tests" / "helpers" / "nav2_echo_server.py")
    node = rclpy.create_node("cross_process_client", context=ros_context)
    executor = SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    try:
        client = ActionClient(node, NavigateToPose, ACTION_NAME)
        spin_until(executor, lambda: client.server_is_ready() or server.poll() is not None, 30.0,
                   "the NavigateToPose server in the other process")
        assert server.poll() is None, stop_process(server)

        goal = NavigateToPose.Goal()
        goal.pose.header.frame_id = "map"
        goal.pose.pose.position.x = 2.0
        goal.pose.pose.position.y = -0.5
        goal.pose.pose.orientation.w = 1.0
        feedback: list[NavigateToPose.Feedback] = []
        send = send_until_acknowledged(client, goal, 30.0, spinning(executor),
                                       lambda msg: feedback.append(msg.feedback))
        handle = send.result()
        assert handle.accepted
        result_future = handle.get_result_async()
        spin_until(executor, result_future.done, 30.0, "the result")

        response = result_future.result()
        assert response.status == GoalStatus.STATUS_SUCCEEDED
        assert response.result.error_code == NavigateToPose.Result.NONE
        assert response.result.error_msg == "reached (2.00, -0.50) in map"
        # Feedback is best effort at the end of a goal; at least some must arrive, in order.
        assert feedback, "no feedback crossed the process boundary"
        distances = [f.distance_remaining for f in feedback]
        assert distances == sorted(distances, reverse=True)
        assert all(f.current_pose.header.frame_id == "map" for f in feedback)
    finally:
        node.destroy_node()
        executor.shutdown()
        stop_process(server)
