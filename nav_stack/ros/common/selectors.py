"""Runtime plugin selection topics: ``planner_selector``, ``controller_selector``, ``goal_checker_selector``.

In Nav2 the BT nodes PlannerSelector / ControllerSelector / GoalCheckerSelector subscribe these
std_msgs/String topics (reliable, transient local) and write the chosen id into the goal they send.
Our servers also subscribe them: a goal whose id field is empty uses the last selected id, and
when nothing was selected either, the first plugin of the server's plugin list. A goal that names
an id always wins. Our bt_navigator fills the ids from the same topics, so both paths agree.
"""

from __future__ import annotations

from rclpy.node import Node
from std_msgs.msg import String

from nav_stack.ros.common.qos import LATCHED


class Selector:
    """The last id published on a selector topic."""

    def __init__(self, node: Node, topic: str) -> None:
        self.topic = topic
        self.selected = ""
        self._node = node
        self._sub = node.create_subscription(String, topic, self._on_msg, LATCHED)

    def _on_msg(self, msg: String) -> None:
        if msg.data != self.selected:
            self._node.get_logger().info(f"{self.topic}: now using '{msg.data}'")
        self.selected = msg.data

    def resolve(self, requested: str, default: str) -> str:
        """The id to use: the goal's, else the selected one, else ``default``."""
        return requested or self.selected or default

    def destroy(self) -> None:
        self._node.destroy_subscription(self._sub)
