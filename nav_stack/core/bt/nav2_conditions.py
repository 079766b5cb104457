"""Nav2 conditions and selectors (nav2_behavior_tree, Jazzy) that need no ROS.

* ``GoalUpdated``: on the tick that finds it IDLE it remembers ``goal``/``goals`` and fails; on later
  ticks it succeeds once when either changed. (Inside a ReactiveFallback whose other child is
  RUNNING it is reset to IDLE every tick and so never fires: BT.CPP 4 behaviour, reproduced;
  upstream navigation2 issue #6082.)
* ``WouldAPlannerRecoveryHelp`` / ``WouldAControllerRecoveryHelp``: SUCCESS when ``error_code`` is one
  a recovery can fix (generic ``AreErrorCodesPresent`` with a preset list).
* ``PlannerSelector`` and friends: output the latest selection received on ``topic_name`` (from the
  injected selection source, else the root blackboard entry of that name), or ``default_*``;
  FAILURE when neither exists. A received selection sticks, as a latched subscription does.
"""

from __future__ import annotations

from typing import Any, ClassVar

from nav_stack.core.bt.node import ConditionNode, NodeConfig, SyncActionNode
from nav_stack.core.bt.ports import PortList, input_port, output_port, semicolon_list
from nav_stack.core.bt.status import NodeStatus

# nav2_msgs error codes (reference/nav2.md §1).
PLANNER_UNKNOWN, PLANNER_TIMEOUT, PLANNER_NO_VALID_PATH = 200, 207, 208
THROUGH_POSES_UNKNOWN, THROUGH_POSES_TIMEOUT, THROUGH_POSES_NO_VALID_PATH = 300, 307, 308
CONTROLLER_UNKNOWN, CONTROLLER_PATIENCE_EXCEEDED = 100, 104
CONTROLLER_FAILED_TO_MAKE_PROGRESS, CONTROLLER_NO_VALID_CONTROL = 105, 106

_NOT_READ: Any = object()


class GoalUpdated(ConditionNode):
    """SUCCESS when the blackboard goal (or goals) changed since this node was last IDLE."""

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self._goal: Any = _NOT_READ
        self._goals: Any = _NOT_READ

    @classmethod
    def provided_ports(cls) -> PortList:
        return (
            input_port("goal", object, "{goal}", "destination pose"),
            input_port("goals", object, "{goals}", "destination poses (through-poses navigation)"),
        )

    def tick(self) -> NodeStatus:
        goal = self.get_input_or("goal", None)
        goals = self.get_input_or("goals", None)
        if not self.status.is_active:
            self._goal, self._goals = goal, goals
            return NodeStatus.FAILURE
        if goal != self._goal or goals != self._goals:
            self._goal, self._goals = goal, goals
            return NodeStatus.SUCCESS
        return NodeStatus.FAILURE


class AreErrorCodesPresent(ConditionNode):
    """SUCCESS when ``error_code`` is in ``error_codes_to_check`` (";"-separated integers)."""

    default_codes: ClassVar[tuple[int, ...]] = ()

    @classmethod
    def provided_ports(cls) -> PortList:
        return (
            input_port("error_code", int, description="the error code to look at (usually {key})"),
            input_port("error_codes_to_check", tuple, cls.default_codes or "",
                       "codes that count as present", converter=semicolon_list(int)),
        )

    def tick(self) -> NodeStatus:
        code = self.get_input_or("error_code", None)
        if code is None:
            return NodeStatus.FAILURE
        present = int(code) in self.get_input("error_codes_to_check")
        return NodeStatus.SUCCESS if present else NodeStatus.FAILURE


class WouldAPlannerRecoveryHelp(AreErrorCodesPresent):
    """Planner failures that clearing the costmap may fix: UNKNOWN, NO_VALID_PATH, TIMEOUT."""

    default_codes = (PLANNER_UNKNOWN, PLANNER_NO_VALID_PATH, PLANNER_TIMEOUT,
                     THROUGH_POSES_UNKNOWN, THROUGH_POSES_NO_VALID_PATH, THROUGH_POSES_TIMEOUT)


class WouldAControllerRecoveryHelp(AreErrorCodesPresent):
    """Controller failures a recovery may fix: UNKNOWN, PATIENCE_EXCEEDED, no progress, no control."""

    default_codes = (CONTROLLER_UNKNOWN, CONTROLLER_PATIENCE_EXCEEDED,
                     CONTROLLER_FAILED_TO_MAKE_PROGRESS, CONTROLLER_NO_VALID_CONTROL)


class _Selector(SyncActionNode):
    """Shared logic of the four Nav2 selectors; subclasses name the selected thing."""

    what: ClassVar[str] = ""

    def __init__(self, name: str, config: NodeConfig) -> None:
        super().__init__(name, config)
        self._last_selected = ""

    @classmethod
    def provided_ports(cls) -> PortList:
        return (
            input_port(f"default_{cls.what}", str, "", f"{cls.what} used until a selection arrives"),
            input_port("topic_name", str, f"{cls.what}_selector", "topic carrying the selection"),
            output_port(f"selected_{cls.what}", str, description=f"the {cls.what} to use"),
        )

    def _received(self) -> str | None:
        topic = str(self.get_input("topic_name"))
        source = self.config.context.selection_source
        if source is not None:
            return source(topic)
        value = self.config.blackboard.get("@" + topic, None)
        return None if value is None else str(value)

    def tick(self) -> NodeStatus:
        received = self._received()
        if received:
            self._last_selected = received
        if not self._last_selected:
            default = str(self.get_input(f"default_{self.what}"))
            if not default:
                return NodeStatus.FAILURE
            self._last_selected = default
        self.set_output(f"selected_{self.what}", self._last_selected)
        return NodeStatus.SUCCESS


class PlannerSelector(_Selector):
    """Selects the planner id (``selected_planner``)."""

    what = "planner"


class ControllerSelector(_Selector):
    """Selects the controller id (``selected_controller``)."""

    what = "controller"


class GoalCheckerSelector(_Selector):
    """Selects the goal checker id (``selected_goal_checker``)."""

    what = "goal_checker"


class ProgressCheckerSelector(_Selector):
    """Selects the progress checker id (``selected_progress_checker``)."""

    what = "progress_checker"
