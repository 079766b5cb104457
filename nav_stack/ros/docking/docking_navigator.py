"""The docking server's way to its staging pose: a NavigateToPose goal to ``navigate_to_pose``.

The docking sequence asks for the navigation and keeps its deadline (``max_staging_time``) and its
one retry; this only sends the goal (with ``navigator_bt_xml`` as ``behavior_tree``, Nav2's), awaits
its result in a coroutine and reports (succeeded, message). A server that is not there within
SERVER_WAIT s (wall: discovery takes wall time), a goal no copy of which is acknowledged, or a rejected
goal are failures with a message saying so. :meth:`StagingNavigator.cancel` cancels the running goal.
"""

from __future__ import annotations

from typing import Any

from action_msgs.msg import GoalStatus
from nav2_msgs.action import NavigateToPose
from rclpy.node import Node

from nav_stack.core.docking import StagingGoal
from nav_stack.ros.common.conversions import pose_stamped
from ros_tools.runtime.actions import ActionClient, acknowledged
from ros_tools.runtime.coroutines import until
from ros_tools.runtime.waiting import sleep, steady_clock

NAVIGATE_TO_POSE = "navigate_to_pose"
SERVER_WAIT = 5.0  # s (wall) for navigate_to_pose to be discovered
SERVER_POLL = 0.1  # s (wall) between two looks for it
SENDS = 3  # copies of the goal sent (ACK_RETRY_S apart) before giving up on an acknowledgement
STATUS_NAMES = {GoalStatus.STATUS_ABORTED: "aborted", GoalStatus.STATUS_CANCELED: "was canceled",
                GoalStatus.STATUS_SUCCEEDED: "succeeded"}


class StagingNavigator:
    """Sends one NavigateToPose at a time for the docking server."""

    def __init__(self, node: Node, behavior_tree: str = "") -> None:
        self.node, self.behavior_tree = node, behavior_tree
        self.client = ActionClient(node, NavigateToPose, NAVIGATE_TO_POSE)
        self._handle: Any = None
        self._wanted = False

    async def navigate(self, goal: StagingGoal) -> tuple[bool, str]:
        """Navigate to ``goal``; (succeeded, what went wrong)."""
        self._wanted = True
        clock, waited = steady_clock(), 0.0
        while not self.client.server_is_ready():
            if waited >= SERVER_WAIT or not self._wanted:
                return False, f"'{NAVIGATE_TO_POSE}' is not available (waited {waited:.0f} s)"
            await sleep(self.node, SERVER_POLL, clock)
            waited += SERVER_POLL
        message = NavigateToPose.Goal(
            pose=pose_stamped(*goal.pose, goal.frame, self.node.get_clock().now().to_msg()),
            behavior_tree=self.behavior_tree)
        sent = await acknowledged(self.node, self.client, message, SENDS, lambda: self._wanted)
        if sent is None:
            return False, f"'{NAVIGATE_TO_POSE}' acknowledged none of {SENDS} copies of the goal"
        handle = sent.result()
        if not handle.accepted:
            return False, f"'{NAVIGATE_TO_POSE}' rejected the goal"
        self._handle = handle
        if not self._wanted:  # cancelled while the goal was being acknowledged
            handle.cancel_goal_async()
        try:
            response = await until(handle.get_result_async())
        finally:
            self._handle = None
        if response.status == GoalStatus.STATUS_SUCCEEDED and response.result.error_code == 0:
            return True, ""
        status = STATUS_NAMES.get(response.status, str(response.status))
        result = response.result
        detail = f": {result.error_msg}" if result.error_msg else ""
        return False, f"'{NAVIGATE_TO_POSE}' {status} with error code {result.error_code}{detail}"

    def cancel(self) -> None:
        """Cancel the running navigation (or the one being sent)."""
        self._wanted = False
        if self._handle is not None:
            self._handle.cancel_goal_async()

    def destroy(self) -> None:
        self.cancel()
        self.client.destroy()
