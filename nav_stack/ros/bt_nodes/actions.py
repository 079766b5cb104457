"""The Nav2 action leaves: planning, path following and the recovery behaviours.

Port names and defaults are Nav2 Jazzy's (nav2_behavior_tree/plugins/action). Recovery behaviours
(Spin, BackUp, Wait; DriveOnHeading only when ``is_recovery`` is set) add one to the blackboard's
``number_recoveries`` when they start, which the navigator reports in its feedback.
"""

from __future__ import annotations

import math
from typing import Any

from nav2_msgs.action import (
    BackUp,
    ComputePathThroughPoses,
    ComputePathToPose,
    DriveOnHeading,
    FollowPath,
    Spin,
    Wait,
)

from nav_stack.core.bt import PortList, input_port, output_port
from nav_stack.core.bt.status import NodeStatus
from nav_stack.ros.bt_nodes.action_node import BtActionNode
from nav_stack.ros.common.conversions import duration_msg

RECOVERIES_KEY = "number_recoveries"


class _PlanAction(BtActionNode):
    """A planner_server leaf: plan from the robot (or ``start``) to its targets; writes ``path``.

    Subclasses name the action, the targets' port and the goal field it fills.
    """

    targets_port = ""
    targets_description = ""

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(),
                input_port(cls.targets_port, object, "{" + cls.targets_port + "}", cls.targets_description),
                input_port("start", object, description="start pose; the robot pose when not set"),
                input_port("planner_id", str, "", "planner plugin id"),
                output_port("path", object, description="the plan (nav_msgs/Path)"))

    def set_targets(self, goal: Any, targets: Any) -> None:
        raise NotImplementedError

    def make_goal(self) -> Any:
        goal = self.action_type.Goal()
        self.set_targets(goal, self.get_input(self.targets_port))
        goal.planner_id = str(self.get_input("planner_id"))
        start = self.get_input_or("start", None)
        if start is not None:
            goal.start, goal.use_start = start, True
        return goal

    def on_success(self, result: Any) -> NodeStatus:
        self.set_output("path", result.path)
        return NodeStatus.SUCCESS


class ComputePathToPoseAction(_PlanAction):
    """Plan from the robot (or ``start``) to ``goal``; writes ``path``."""

    action_type = ComputePathToPose
    default_server_name = "compute_path_to_pose"
    targets_port = "goal"
    targets_description = "destination (geometry_msgs/PoseStamped)"

    def set_targets(self, goal: Any, targets: Any) -> None:
        goal.goal = targets


class ComputePathThroughPosesAction(_PlanAction):
    """Plan through ``goals`` in order; writes ``path``."""

    action_type = ComputePathThroughPoses
    default_server_name = "compute_path_through_poses"
    targets_port = "goals"
    targets_description = "poses to pass through (PoseStamped list)"

    def set_targets(self, goal: Any, targets: Any) -> None:
        goal.goals = list(targets)


class FollowPathAction(BtActionNode):
    """Follow ``path`` with the controller; a new path on the blackboard is sent as a new goal."""

    action_type = FollowPath
    default_server_name = "follow_path"

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(),
                input_port("path", object, "{path}", "path to follow (nav_msgs/Path)"),
                input_port("controller_id", str, "", "controller plugin id"),
                input_port("goal_checker_id", str, "", "goal checker plugin id"),
                input_port("progress_checker_id", str, "", "progress checker plugin id"))

    def make_goal(self) -> Any:
        goal = FollowPath.Goal()
        goal.path = self.get_input("path")
        goal.controller_id = str(self.get_input("controller_id"))
        goal.goal_checker_id = str(self.get_input("goal_checker_id"))
        goal.progress_checker_id = str(self.get_input("progress_checker_id"))
        return goal

    def updated_goal(self) -> Any:
        sent = self._goal
        path = self.get_input_or("path", sent.path)
        ids = (str(self.get_input("controller_id")), str(self.get_input("goal_checker_id")),
               str(self.get_input("progress_checker_id")))
        path_changed = path is not sent.path and path != sent.path and len(path.poses) > 0
        if not path_changed and ids == (sent.controller_id, sent.goal_checker_id, sent.progress_checker_id):
            return None
        return self.make_goal()


class _Recovery(BtActionNode):
    """A behaviour-server action that counts as a recovery when ``is_recovery`` is set."""

    counts_by_default = True

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(),
                input_port("is_recovery", bool, cls.counts_by_default, "count it in number_of_recoveries"))

    def on_start(self) -> NodeStatus:
        if bool(self.get_input("is_recovery")):
            board = self.config.blackboard
            board.set("@" + RECOVERIES_KEY, int(board.get("@" + RECOVERIES_KEY, 0)) + 1)
        return super().on_start()


class SpinAction(_Recovery):
    """Rotate in place by ``spin_dist`` rad."""

    action_type = Spin
    default_server_name = "spin"

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(),
                input_port("spin_dist", float, 1.57, "rad to turn (sign = direction)"),
                input_port("time_allowance", float, 10.0, "s the spin may take"))

    def make_goal(self) -> Any:
        goal = Spin.Goal()
        goal.target_yaw = float(self.get_input("spin_dist"))
        goal.time_allowance = duration_msg(float(self.get_input("time_allowance")))
        return goal


class BackUpAction(_Recovery):
    """Drive backwards ``backup_dist`` m at ``backup_speed`` m/s (positive values, as Nav2 clients send)."""

    action_type = BackUp
    default_server_name = "backup"

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(),
                input_port("backup_dist", float, 0.15, "m to back up"),
                input_port("backup_speed", float, 0.025, "m/s"),
                input_port("time_allowance", float, 10.0, "s the manoeuvre may take"))

    def make_goal(self) -> Any:
        goal = BackUp.Goal()
        goal.target.x = float(self.get_input("backup_dist"))
        goal.speed = float(self.get_input("backup_speed"))
        goal.time_allowance = duration_msg(float(self.get_input("time_allowance")))
        return goal


class DriveOnHeadingAction(_Recovery):
    """Drive ``dist_to_travel`` m along the current heading at ``speed`` m/s."""

    action_type = DriveOnHeading
    default_server_name = "drive_on_heading"
    counts_by_default = False

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(),
                input_port("dist_to_travel", float, 0.15, "m (same sign as speed)"),
                input_port("speed", float, 0.025, "m/s"),
                input_port("time_allowance", float, 10.0, "s the manoeuvre may take"))

    def make_goal(self) -> Any:
        goal = DriveOnHeading.Goal()
        goal.target.x = float(self.get_input("dist_to_travel"))
        goal.speed = float(self.get_input("speed"))
        goal.time_allowance = duration_msg(float(self.get_input("time_allowance")))
        return goal


class WaitAction(_Recovery):
    """Wait ``wait_duration`` s (on the behaviour server's clock)."""

    action_type = Wait
    default_server_name = "wait"

    @classmethod
    def provided_ports(cls) -> PortList:
        return (*super().provided_ports(), input_port("wait_duration", float, 1.0, "s to wait"))

    def make_goal(self) -> Any:
        seconds = float(self.get_input("wait_duration"))
        if not math.isfinite(seconds) or seconds < 0.0:
            self._fail(f"wait_duration must be a finite number of seconds >= 0, got {seconds}")
            return None
        goal = Wait.Goal()
        goal.time = duration_msg(seconds)
        return goal
