"""Planner, controller and goal-checker selection for Nav2's BT selector nodes.

Nav2's PlannerSelector/ControllerSelector/GoalCheckerSelector BT nodes subscribe ``planner_selector``,
``controller_selector`` and ``goal_checker_selector`` (std_msgs/String) with reliable + transient local
QoS, depth 1, so a selection published before the BT starts still applies. The presets keep SMACC2's
names; SMACC2's own forward/backward/pure-spinning/undo planner plugins do not exist in a standard
Nav2 (nor in nav_stack), which is why the motion behaviors here use the behavior-server actions and
only ``set_default_planners`` selects plugins that exist.
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String

from smacc_py.core import ISmaccComponent
from smacc_py.ros.context import ros_context

SELECTOR_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)

PRESETS: dict[str, tuple[str, str]] = {
    "default": ("GridBased", "FollowPath"),
    "forward": ("ForwardGlobalPlanner", "ForwardLocalPlanner"),
    "backward": ("BackwardGlobalPlanner", "BackwardLocalPlanner"),
    "undo_path_backward": ("UndoPathGlobalPlanner", "BackwardLocalPlanner"),
    "pure_spinning": ("ForwardGlobalPlanner", "PureSpinningLocalPlanner"),
}


class CpPlannerSwitcher(ISmaccComponent):
    """Publishes the desired planner and controller ids (``commit_publish``)."""

    def __init__(
        self, planner_topic: str = "planner_selector", controller_topic: str = "controller_selector"
    ) -> None:
        self.planner_topic, self.controller_topic = planner_topic, controller_topic
        self.desired_planner, self.desired_controller = PRESETS["default"]

    def on_initialize(self) -> None:
        node = ros_context(self.sm).node
        self._planner_pub = node.create_publisher(String, self.planner_topic, SELECTOR_QOS)
        self._controller_pub = node.create_publisher(String, self.controller_topic, SELECTOR_QOS)

    def set_desired_global_planner(self, planner_id: str) -> None:
        """Choose the planner id (published on ``commit_publish``)."""
        self.desired_planner = planner_id

    def set_desired_controller(self, controller_id: str) -> None:
        """Choose the controller id (published on ``commit_publish``)."""
        self.desired_controller = controller_id

    def commit_publish(self) -> None:
        """Publish both selections."""
        self._planner_pub.publish(String(data=self.desired_planner))
        self._controller_pub.publish(String(data=self.desired_controller))

    def set_preset(self, name: str) -> None:
        """Select and publish a preset (``PRESETS``); ValueError naming the known ones."""
        try:
            self.desired_planner, self.desired_controller = PRESETS[name]
        except KeyError:
            raise ValueError(
                f"CpPlannerSwitcher: unknown preset {name!r}; known: {sorted(PRESETS)}"
            ) from None
        self.commit_publish()

    def set_default_planners(self) -> None:
        """GridBased planner + FollowPath controller (Nav2's defaults)."""
        self.set_preset("default")


class CpGoalCheckerSwitcher(ISmaccComponent):
    """Publishes the goal checker id on ``goal_checker_selector``."""

    def __init__(
        self, topic: str = "goal_checker_selector", default_goal_checker: str = "goal_checker"
    ) -> None:
        self.topic, self.default_goal_checker = topic, default_goal_checker
        self.current = default_goal_checker

    def on_initialize(self) -> None:
        self._pub = ros_context(self.sm).node.create_publisher(String, self.topic, SELECTOR_QOS)

    def set_goal_checker_id(self, goal_checker_id: str | None = None) -> None:
        """Publish ``goal_checker_id`` (default: the default goal checker)."""
        self.current = goal_checker_id or self.default_goal_checker
        self._pub.publish(String(data=self.current))
