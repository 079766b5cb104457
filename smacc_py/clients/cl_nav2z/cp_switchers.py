"""Planner, controller and goal-checker selection for Nav2's BT selector nodes.

Nav2's PlannerSelector/ControllerSelector/GoalCheckerSelector BT nodes (and nav_stack's planner and
controller servers and bt_navigator, ``nav_stack/ros/common/selectors.py``) subscribe ``planner_selector``,
``controller_selector`` and ``goal_checker_selector`` (std_msgs/String) with reliable + transient local
QoS, depth 1, so a selection published before the BT starts still applies.

Presets name only plugins that nav_stack declares (config/nav2_params.yaml: ``planner_plugins``,
``controller_plugins``); a test reads the file to keep it so. SMACC2's other presets select its own
planner plugins (forward, backward, undo-path, pure-spinning), which neither a standard Nav2 nor
nav_stack has: a server given such an id aborts every goal (INVALID_PLANNER / INVALID_CONTROLLER), so
``set_preset`` refuses them, naming the missing plugin and the cl_nav2z behavior that does that motion
with the behavior-server actions instead.
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import String

from smacc_py.core import ISmaccComponent
from smacc_py.ros.context import ros_context

SELECTOR_QOS = QoSProfile(
    depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL
)

#: Preset name → (planner id, controller id), all declared by nav_stack's planner and controller servers.
PRESETS: dict[str, tuple[str, str]] = {
    "default": ("GridBased", "FollowPath"),
}

#: SMACC2 presets whose plugins do not exist here → (planner id, controller id, what to use instead).
SMACC2_ONLY_PRESETS: dict[str, tuple[str, str, str]] = {
    "forward": ("ForwardGlobalPlanner", "ForwardLocalPlanner", "CbNavigateForward (drive_on_heading)"),
    "backward": ("BackwardGlobalPlanner", "BackwardLocalPlanner", "CbNavigateBackwards (backup)"),
    "undo_path_backward": ("UndoPathGlobalPlanner", "BackwardLocalPlanner", "CbUndoPathBackwards"),
    "pure_spinning": ("ForwardGlobalPlanner", "PureSpinningLocalPlanner", "CbPureSpinning or CbRotate"),
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
        """Select and publish a preset (``PRESETS``). ValueError, publishing nothing, for SMACC2's presets
        whose plugins do not exist here (naming the plugin and the alternative) and for unknown names."""
        if name in SMACC2_ONLY_PRESETS:
            planner, controller, instead = SMACC2_ONLY_PRESETS[name]
            raise ValueError(
                f"CpPlannerSwitcher: preset {name!r} selects planner {planner!r} and controller "
                f"{controller!r}, SMACC2's own plugins, which nav_stack does not declare "
                f"(config/nav2_params.yaml); use {instead} instead. Presets: {sorted(PRESETS)}"
            )
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
