"""ROS-backed BT helpers that need TF or topics: RemovePassedGoals and the selectors' topic source.

* ``RemovePassedGoals`` (Nav2 Jazzy): drops the leading poses of ``input_goals`` that lie within
  ``radius`` m of the robot (always keeping the last one) and writes the rest to ``output_goals``;
  FAILURE when the robot pose is not available from TF.
* ``SelectorTopics``: the ``selection_source`` of the core selectors. It subscribes the selector
  topics (std_msgs/String, reliable + transient local) so PlannerSelector & co. see the latest
  selection; a tree naming another ``topic_name`` gets its subscription on first use.
"""

from __future__ import annotations

import math
import threading

from rclpy.node import Node

from nav_stack.core.bt import NodeConfig, PortList, SyncActionNode, input_port, output_port
from nav_stack.core.bt.status import NodeStatus
from nav_stack.ros.bt_nodes.context import BtRosContext
from nav_stack.ros.common.frames import FrameError
from nav_stack.ros.common.selectors import Selector

SELECTOR_TOPICS = ("planner_selector", "controller_selector", "goal_checker_selector",
                   "progress_checker_selector")


class RemovePassedGoals(SyncActionNode):
    """Remove via-points the robot already reached."""

    def __init__(self, name: str, config: NodeConfig, *, ros: BtRosContext) -> None:
        super().__init__(name, config)
        self.ros = ros

    @classmethod
    def provided_ports(cls) -> PortList:
        return (
            input_port("input_goals", object, "{goals}", "remaining poses (PoseStamped list)"),
            output_port("output_goals", object, description="poses not yet reached"),
            input_port("radius", float, 0.5, "m within which a via-point counts as reached"),
            input_port("global_frame", str, "", "frame of the goals; default the navigator's"),
            input_port("robot_base_frame", str, "", "robot frame; default the navigator's"),
        )

    def tick(self) -> NodeStatus:
        goals = list(self.get_input_or("input_goals", []) or [])
        if not goals:
            return NodeStatus.FAILURE
        frames = self.ros.frames
        if frames is None:
            return NodeStatus.FAILURE
        global_frame = str(self.get_input("global_frame")) or self.ros.global_frame
        base = str(self.get_input("robot_base_frame")) or self.ros.robot_base_frame
        try:
            robot = frames.frame_pose(global_frame, base)
        except FrameError as error:
            self.ros.node.get_logger().warn(f"{self.name}: {error}")
            return NodeStatus.FAILURE
        radius = float(self.get_input("radius"))
        while len(goals) > 1:
            p = goals[0].pose.position
            if math.hypot(p.x - robot.x, p.y - robot.y) > radius:
                break
            goals.pop(0)
        self.set_output("output_goals", goals)
        return NodeStatus.SUCCESS


class SelectorTopics:
    """topic name → latest selection received on it (None before any), for ``TreeContext``."""

    def __init__(self, node: Node, topics: tuple[str, ...] = SELECTOR_TOPICS) -> None:
        self._node = node
        self._lock = threading.Lock()
        self._selectors: dict[str, Selector] = {topic: Selector(node, topic) for topic in topics}

    def __call__(self, topic: str) -> str | None:
        with self._lock:
            selector = self._selectors.get(topic)
            if selector is None:
                selector = self._selectors[topic] = Selector(self._node, topic)
        return selector.selected or None

    def destroy(self) -> None:
        with self._lock:
            for selector in self._selectors.values():
                selector.destroy()
            self._selectors.clear()

