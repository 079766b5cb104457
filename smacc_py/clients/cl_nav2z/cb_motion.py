"""Relative motions on Nav2's behavior-server actions (SMACC2 used custom planner plugins for these).

* ``CbNavigateForward(distance)`` → ``drive_on_heading`` (straight, collision-checked).
* ``CbNavigateBackwards(distance)`` → ``backup``.
* ``CbSpin(yaw_rad)`` → ``spin``; ``CbRotate(deg)`` the same in degrees; ``CbAbsoluteRotate(deg)`` spins by
  the difference between the wanted map yaw and CpPose's yaw; ``CbRotateLookAt(x, y)`` does the same
  with the heading that faces the point (x, y).
* ``CbUndoPathBackwards`` drives back along CpOdomTracker's working path: a straight path is undone with
  one ``backup`` (or ``drive_on_heading`` if it was driven backwards) of its length; any other path is
  handed reversed to the controller server's ``follow_path`` (the controller decides whether the robot
  turns around). The path is popped when the undo succeeds.

Distances in m, speeds in m/s, angles as named; ``time_allowance`` defaults to twice the nominal
duration plus 10 s.
"""

from __future__ import annotations

import math
from typing import Any

from builtin_interfaces.msg import Duration
from nav2_msgs.action import BackUp, DriveOnHeading, FollowPath, Spin
from nav_msgs.msg import Path

from smacc_py.clients.cl_nav2z.cb_action_base import CbNav2ZActionBase
from smacc_py.clients.cl_nav2z.client import BACKUP, DRIVE_ON_HEADING, FOLLOW_PATH, SPIN
from smacc_py.clients.cl_nav2z.cp_odom_tracker import CpOdomTracker
from smacc_py.clients.cl_nav2z.cp_pose import CpPose, make_pose_stamped
from smacc_py.clients.cl_nav2z.geometry import Pose2D, is_straight, normalize_angle, path_length
from smacc_py.clients.cl_nav2z.odom_path import WorkingMode
from smacc_py.ros.action_client import GoalOutcome, GoalTicket

SPIN_NOMINAL_SPEED = 0.4  # rad/s, for the default time allowance only


def allowance(nominal_s: float) -> Duration:
    """Twice the nominal duration plus 10 s, as a Duration."""
    seconds = 2.0 * nominal_s + 10.0
    return Duration(sec=int(seconds), nanosec=int((seconds % 1.0) * 1e9))


def straight_goal(action_type: Any, distance: float, speed: float) -> Any:
    """A BackUp/DriveOnHeading goal (target.x = distance, same sign as speed)."""
    goal = action_type.Goal()
    goal.target.x = float(distance)
    goal.speed = float(math.copysign(abs(speed), distance))
    goal.time_allowance = allowance(abs(distance) / max(abs(speed), 1e-3))
    return goal


def spin_goal(yaw: float) -> Any:
    """A Spin goal for a relative yaw (rad)."""
    return Spin.Goal(target_yaw=float(yaw), time_allowance=allowance(abs(yaw) / SPIN_NOMINAL_SPEED))


class CbNavigateForward(CbNav2ZActionBase):
    """Drive ``distance`` m straight ahead at ``speed`` m/s (negative distance: backwards)."""

    record_path = True

    def __init__(self, distance: float, speed: float = 0.2) -> None:
        if not math.isfinite(distance) or distance == 0.0 or not speed > 0.0:
            raise ValueError(
                f"CbNavigateForward: need a non-zero distance and speed > 0, got {distance}, {speed}"
            )
        self.distance, self.speed = float(distance), float(speed)

    def make_goal(self) -> tuple[str, Any] | None:
        return DRIVE_ON_HEADING, straight_goal(DriveOnHeading, self.distance, self.speed)


class CbNavigateBackwards(CbNav2ZActionBase):
    """Back up ``distance`` m (positive) at ``speed`` m/s."""

    record_path = True

    def __init__(self, distance: float, speed: float = 0.15) -> None:
        if not distance > 0.0 or not speed > 0.0:
            raise ValueError(f"CbNavigateBackwards: distance and speed must be > 0, got {distance}, {speed}")
        self.distance, self.speed = float(distance), float(speed)

    def make_goal(self) -> tuple[str, Any] | None:
        return BACKUP, straight_goal(BackUp, self.distance, self.speed)


class CbSpin(CbNav2ZActionBase):
    """Spin by ``yaw`` rad (positive: counter-clockwise) with the collision-checked Spin behavior."""

    def __init__(self, yaw: float) -> None:
        self.yaw = float(yaw)

    def make_goal(self) -> tuple[str, Any] | None:
        return SPIN, spin_goal(self.yaw)


class CbRotate(CbSpin):
    """Rotate by ``degrees`` relative to the current heading."""

    def __init__(self, degrees: float) -> None:
        super().__init__(math.radians(degrees))


class CbAbsoluteRotate(CbNav2ZActionBase):
    """Turn to the absolute heading ``degrees`` in CpPose's reference frame (shortest way)."""

    def __init__(self, degrees: float) -> None:
        self.target_yaw = math.radians(degrees)

    def target_heading(self, pose: Pose2D) -> float | None:
        """The heading (rad, CpPose's reference frame) to turn to from ``pose``; None after posting a
        failure. Subclasses that aim at something override it."""
        return self.target_yaw

    def make_goal(self) -> tuple[str, Any] | None:
        cp_pose = self.requires_component(CpPose)
        pose = cp_pose.refresh()
        if pose is None:
            self.post_failure_event(reason=f"no robot pose: {cp_pose.last_error}")
            return None
        heading = self.target_heading(pose)
        if heading is None:
            return None
        return SPIN, spin_goal(normalize_angle(heading - pose[2]))


class CbRotateLookAt(CbAbsoluteRotate):
    """Turn in place to face the point (``x``, ``y``) m in CpPose's reference frame (SMACC2 takes a
    PoseStamped and uses only its position). Fails when the robot stands within ``min_distance`` m of
    the point, where no heading faces it."""

    def __init__(self, x: float, y: float, *, min_distance: float = 0.01) -> None:
        for field, value in (("x", x), ("y", y), ("min_distance", min_distance)):
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"CbRotateLookAt: {field} must be a finite number, got {value!r}")
        super().__init__(0.0)
        self.look_at, self.min_distance = (float(x), float(y)), float(min_distance)

    def target_heading(self, pose: Pose2D) -> float | None:
        dx, dy = self.look_at[0] - pose[0], self.look_at[1] - pose[1]
        if math.hypot(dx, dy) < self.min_distance:
            self.post_failure_event(reason=f"CbRotateLookAt: the robot at ({pose[0]:.3f}, {pose[1]:.3f}) is "
                                    f"within {self.min_distance} m of the point {self.look_at}")
            return None
        return math.atan2(dy, dx)


def undo_plan(path: list[Pose2D], heading_tolerance: float = 0.3) -> tuple[str, float] | None:
    """How to undo ``path``: (BACKUP | DRIVE_ON_HEADING, length) for a straight path driven facing along
    (or against) it, (FOLLOW_PATH, length) otherwise; None when there is nothing to undo."""
    length = path_length(path)
    if len(path) < 2 or length < 0.01:
        return None
    if is_straight(path):
        direction = math.atan2(path[-1][1] - path[0][1], path[-1][0] - path[0][0])
        heading = path[-1][2]
        if abs(normalize_angle(heading - direction)) <= heading_tolerance:
            return BACKUP, length
        if abs(normalize_angle(heading - direction - math.pi)) <= heading_tolerance:
            return DRIVE_ON_HEADING, length
    return FOLLOW_PATH, length


class CbUndoPathBackwards(CbNav2ZActionBase):
    """Go back along the recorded odometry path (see the module docstring)."""

    def __init__(self, speed: float = 0.15, controller_id: str = "", goal_checker_id: str = "") -> None:
        self.speed, self.controller_id, self.goal_checker_id = speed, controller_id, goal_checker_id
        self.plan: tuple[str, float] | None = None

    def make_goal(self) -> tuple[str, Any] | None:
        tracker = self.requires_component(CpOdomTracker)
        path = tracker.path()
        self.plan = undo_plan(path)
        if self.plan is None:
            self.post_success_event(reason="no recorded path to undo")
            return None
        key, length = self.plan
        if key == BACKUP:
            return key, straight_goal(BackUp, length, self.speed)
        if key == DRIVE_ON_HEADING:
            return key, straight_goal(DriveOnHeading, length, self.speed)
        tracker.set_working_mode(WorkingMode.CLEAR_PATH)
        msg = Path()
        msg.header.frame_id = tracker.odom_frame
        msg.poses = [make_pose_stamped(tracker.odom_frame, *pose) for pose in reversed(path)]
        return key, FollowPath.Goal(
            path=msg, controller_id=self.controller_id, goal_checker_id=self.goal_checker_id
        )

    def on_goal_done(self, ticket: GoalTicket) -> None:
        tracker = self.requires_component(CpOdomTracker)
        tracker.set_working_mode(WorkingMode.IDLE)
        if ticket.outcome is GoalOutcome.SUCCEEDED:
            tracker.pop_path()
