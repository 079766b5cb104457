"""RViz's "Nav2 Goal": a PoseStamped on ``goal_pose`` becomes a NavigateToPose goal of our own server.

Why a module of its own: the goal goes through bt_navigator's action server like any client's
(so it has a goal id, feedback, a result, and preempts as any goal does), and that path crosses
DDS even inside one node. The node's own client discovers its own server a while after activation
(longer under load), and a request or its acknowledgement can be dropped while the match
completes. So the forwarder waits for the server and resends until acknowledged, in a coroutine:
the subscription callback never blocks. Only the newest pose is forwarded.
"""

from __future__ import annotations

from typing import Any

from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import NavigateToPose
from rclpy.action import ActionClient

from nav_stack.ros.common.qos import DEFAULT
from ros_tools.runtime.actions import acknowledged
from ros_tools.runtime.coroutines import spawn
from ros_tools.runtime.waiting import sleep, steady_clock

SERVER_WAIT_S = 10.0  # s (wall) a pose waits for navigate_to_pose before it is dropped with a warning
SENDS = 3  # copies of a goal sent (actions.ACK_RETRY_S apart) before it is given up with a warning
POLL_S = 0.05  # s (wall) between checks for the server


class GoalPoseForwarder:
    """Subscribes ``goal_pose`` on ``node`` and sends each pose to ``node``'s ``navigate_to_pose``."""

    def __init__(self, node: Any) -> None:
        self.node = node
        self._clock = steady_clock()
        self._newest = 0  # sequence number of the newest pose; an older one stops forwarding
        self._client = ActionClient(node, NavigateToPose, "navigate_to_pose")
        self._sub = node.create_subscription(PoseStamped, "goal_pose", self._on_goal_pose, DEFAULT)

    def _on_goal_pose(self, msg: PoseStamped) -> None:
        self._newest += 1
        position = msg.pose.position
        self.node.get_logger().info(f"goal_pose: navigating to ({position.x:.2f}, {position.y:.2f})")
        spawn(self.node, self._forward(msg, self._newest))

    async def _forward(self, msg: PoseStamped, sequence: int) -> None:
        log = self.node.get_logger()
        wanted = lambda: sequence == self._newest  # noqa: E731 - a newer pose replaces this one
        waited = 0.0
        while not self._client.server_is_ready():
            if not wanted():
                return
            if waited >= SERVER_WAIT_S:
                log.warn(f"goal_pose dropped: navigate_to_pose not available after {SERVER_WAIT_S:.0f} s")
                return
            await sleep(self.node, POLL_S, self._clock)
            waited += POLL_S
        if await acknowledged(self.node, self._client, NavigateToPose.Goal(pose=msg), SENDS, wanted,
                              self._clock) is None and wanted():
            log.warn(f"goal_pose dropped: navigate_to_pose acknowledged none of {SENDS} copies")

    def destroy(self) -> None:
        self.node.destroy_subscription(self._sub)
        self._client.destroy()
