"""The two navigators of bt_navigator: what a goal writes on the blackboard and what feedback says.

Nav2 splits bt_navigator into navigator plugins (NavigateToPoseNavigator,
NavigateThroughPosesNavigator) that share one tree runner; these classes are that split. A
navigator turns an action goal into blackboard entries (``goal`` or ``goals``, in the global
frame) and computes feedback the way Nav2 Jazzy does (reference/nav2.md §2):

* current_pose: robot base in the global frame (TF);
* distance_remaining: length of the current path from its pose nearest the robot;
* estimated_time_remaining: distance / |odom velocity| when the speed is > 0.01 m/s and the
  distance > 0.1 m, else 0;
* navigation_time: now - goal start; number_of_recoveries: the blackboard counter.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import NavigateThroughPoses, NavigateToPose

from nav_stack.core.bt import Blackboard
from nav_stack.core.geometry import cumulative_lengths, nearest_index
from nav_stack.ros.bt_nodes.actions import RECOVERIES_KEY
from nav_stack.ros.common.conversions import duration_msg, path_to_array, pose_stamped
from nav_stack.ros.common.frames import FrameError, Frames
from nav_stack.ros.navigator.localization_guard import untrusted_message
from navsuite_data import config_path, resolve

TREES_DIR = config_path("trees")  # the default trees: shipped data (navsuite_data)
MIN_SPEED_FOR_ETA = 0.01  # m/s
MIN_DISTANCE_FOR_ETA = 0.1  # m


#: Kilted's NavigateToPose result codes, used by both navigators: Jazzy's messages name only NONE,
#: and a failed goal must never end with 0 (a client could not tell it from a success).
UNKNOWN, FAILED_TO_LOAD_BEHAVIOR_TREE, TF_ERROR = 9000, 9001, 9002


class GoalError(ValueError):
    """A goal that cannot be navigated, with its result ``code`` (TF_ERROR for frame problems)."""

    def __init__(self, message: str, code: int = UNKNOWN) -> None:
        super().__init__(message)
        self.code = code


def _always_trusted() -> str | None:
    return None


@dataclass
class RobotState:
    """What goals and feedback need besides the blackboard: TF, the global frame, the odometry speed
    (m/s) and ``trust``: None while localization can be trusted, else why not (localization_guard.py)."""

    frames: Frames
    global_frame: str
    speed: float = 0.0
    trust: Callable[[], str | None] = _always_trusted


def has_robot_pose(robot: RobotState) -> bool:
    """Whether TF knows the robot base in the global frame now."""
    try:
        robot.frames.robot_pose(robot.global_frame)
    except FrameError:
        return False
    return True


class PathProgress:
    """Remaining path length (m), caching the cumulative lengths of the last path seen."""

    def __init__(self) -> None:
        self._path: Any = None
        self._points = np.zeros((0, 3))
        self._cumulative = np.zeros(0)

    def remaining(self, path: Any, x: float, y: float) -> float:
        if path is None or not path.poses:
            return 0.0
        if path is not self._path:
            self._path = path
            self._points = path_to_array(path)
            self._cumulative = cumulative_lengths(self._points)
        index = nearest_index(self._points, x, y)
        return float(self._cumulative[-1] - self._cumulative[index])


class Navigator:
    """Base: action type, default tree and the goal/feedback translation of one navigator."""

    action_type: ClassVar[Any] = None
    action_name: ClassVar[str] = ""
    default_tree_file: ClassVar[str] = ""

    def __init__(self, default_tree: str, path_key: str = "path") -> None:
        # a parameter's path as given (or a shipped config/trees/... name); empty: the shipped default
        self.default_tree = str(resolve(default_tree) if default_tree else TREES_DIR / self.default_tree_file)
        self.path_key = path_key
        self._progress = PathProgress()

    def tree_file(self, goal: Any) -> str:
        """The tree a goal asks for: its ``behavior_tree`` field, else the default."""
        return goal.behavior_tree or self.default_tree

    def write_goal(self, goal: Any, board: Blackboard, robot: RobotState) -> None:
        """Put the goal's poses on the blackboard (in the global frame); GoalError when impossible.

        As Nav2 Jazzy's navigators, a goal is refused (TF_ERROR) while the robot's own pose is not
        known in the global frame: before localization publishes map -> odom, a plan would start
        from nowhere and the controller would fail later with a less useful message. For the same
        reason a goal is refused (UNKNOWN) while localization says that pose is not trustworthy.
        """
        try:
            robot.frames.robot_pose(robot.global_frame)
        except FrameError as error:
            raise GoalError(f"Initial robot pose is not available: {error}", TF_ERROR) from error
        reason = robot.trust()
        if reason is not None:
            raise GoalError(untrusted_message(reason))
        self._write_goal(goal, board, robot)

    def _write_goal(self, goal: Any, board: Blackboard, robot: RobotState) -> None:
        raise NotImplementedError

    def feedback(self, board: Blackboard, robot: RobotState, started: float, now: float, stamp: Any) -> Any:
        """The feedback message for the current state (pose fields stay empty if TF fails)."""
        msg = self.action_type.Feedback()
        msg.navigation_time = duration_msg(now - started)
        msg.number_of_recoveries = int(board.get(RECOVERIES_KEY, 0))
        try:
            pose = robot.frames.robot_pose(robot.global_frame)
        except FrameError:
            return msg
        msg.current_pose = pose_stamped(pose.x, pose.y, pose.yaw, robot.global_frame, stamp)
        distance = self._progress.remaining(board.get(self.path_key, None), pose.x, pose.y)
        msg.distance_remaining = distance
        if robot.speed > MIN_SPEED_FOR_ETA and distance > MIN_DISTANCE_FOR_ETA:
            msg.estimated_time_remaining = duration_msg(distance / robot.speed)
        return msg


def to_global(pose: PoseStamped, robot: RobotState) -> PoseStamped:
    """``pose`` expressed in the global frame; GoalError (TF_ERROR) for an empty or unknown frame,
    as Nav2 refuses them (an empty frame_id is not taken as the global frame)."""
    frame = pose.header.frame_id.lstrip("/")
    if not frame:
        raise GoalError(f"the goal's header.frame_id is empty: set it to the frame of the pose "
                        f"(e.g. '{robot.global_frame}')", TF_ERROR)
    if frame == robot.global_frame:
        out = PoseStamped()
        out.header.frame_id = robot.global_frame
        out.header.stamp = pose.header.stamp
        out.pose = pose.pose
        return out
    try:
        planar = robot.frames.to_frame(pose, robot.global_frame)
    except FrameError as error:
        raise GoalError(f"cannot transform the goal from '{frame}' to '{robot.global_frame}': {error}",
                        TF_ERROR) from error
    if math.isnan(planar.yaw):
        raise GoalError(f"the goal orientation {pose.pose.orientation} cannot be normalised")
    return pose_stamped(planar.x, planar.y, planar.yaw, robot.global_frame, pose.header.stamp)


class NavigateToPoseNavigator(Navigator):
    """``navigate_to_pose``: one goal pose on the blackboard key ``goal``."""

    action_type = NavigateToPose
    action_name = "navigate_to_pose"
    default_tree_file = "navigate_to_pose_w_replanning_and_recovery.xml"

    def __init__(self, default_tree: str, path_key: str = "path", goal_key: str = "goal") -> None:
        super().__init__(default_tree, path_key)
        self.goal_key = goal_key

    def _write_goal(self, goal: Any, board: Blackboard, robot: RobotState) -> None:
        board.set(self.goal_key, to_global(goal.pose, robot))


class NavigateThroughPosesNavigator(Navigator):
    """``navigate_through_poses``: the pose list on the blackboard key ``goals``."""

    action_type = NavigateThroughPoses
    action_name = "navigate_through_poses"
    default_tree_file = "navigate_through_poses_w_replanning_and_recovery.xml"

    def __init__(self, default_tree: str, path_key: str = "path", goals_key: str = "goals") -> None:
        super().__init__(default_tree, path_key)
        self.goals_key = goals_key

    def _write_goal(self, goal: Any, board: Blackboard, robot: RobotState) -> None:
        if not goal.poses:
            raise GoalError("the goal has no poses")
        board.set(self.goals_key, [to_global(pose, robot) for pose in goal.poses])

    def feedback(self, board: Blackboard, robot: RobotState, started: float, now: float, stamp: Any) -> Any:
        msg = super().feedback(board, robot, started, now, stamp)
        msg.number_of_poses_remaining = len(board.get(self.goals_key, []) or [])
        return msg
