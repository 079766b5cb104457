"""A stand-alone NavigateToPose action server used by the cross-process system test.

It runs in its own process (``python tests/helpers/nav2_echo_server.py``), accepts every goal,
publishes ``FEEDBACK_STEPS`` feedback messages whose distance_remaining falls to zero, and succeeds
with an error_msg that echoes the goal, so the test can check that goal, feedback and result all
crossed the process boundary intact. It prints "ready" once the server exists.
"""

from __future__ import annotations

import sys

from ros_tools.dds import keep_dds_local

FEEDBACK_STEPS = 5
#: Not Nav2's "navigate_to_pose": a stack left running by another test must not answer our goals.
ACTION_NAME = "echo_navigate_to_pose"


def main() -> int:
    keep_dds_local()
    import rclpy
    from nav2_msgs.action import NavigateToPose
    from rclpy.executors import ExternalShutdownException

    from ros_tools.runtime.actions import ActionServer
    from ros_tools.runtime.waiting import sleep, steady_clock

    async def execute(goal_handle):  # type: ignore[no-untyped-def]
        pose = goal_handle.request.pose.pose.position
        # Feedback is only useful once the client's feedback subscription has matched ours: wait
        # for it (10 s at most) without blocking the executor.
        feedback_topic = f"{ACTION_NAME}/_action/feedback"
        for _ in range(1000):
            if node.count_subscribers(feedback_topic) > 0:
                break
            await sleep(node, 0.01, steady_clock())
        for step in range(FEEDBACK_STEPS):
            feedback = NavigateToPose.Feedback()
            feedback.distance_remaining = float(FEEDBACK_STEPS - 1 - step)
            feedback.number_of_recoveries = step
            feedback.current_pose.header.frame_id = "map"
            goal_handle.publish_feedback(feedback)
        goal_handle.succeed()
        result = NavigateToPose.Result()
        result.error_code = NavigateToPose.Result.NONE
        frame = goal_handle.request.pose.header.frame_id
        result.error_msg = f"reached ({pose.x:.2f}, {pose.y:.2f}) in {frame}"
        return result

    rclpy.init()
    node = rclpy.create_node("nav2_echo_server")
    server = ActionServer(node, NavigateToPose, ACTION_NAME, execute)
    print("ready", flush=True)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        server.destroy()
        node.destroy_node()
        if rclpy.ok():
            rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
