"""Goal checkers and the progress checker of the controller server (nav2_controller plugins).

Final rotation at the goal and progress: a robot turning in place at the goal does not move, so a
SimpleProgressChecker would report FAILED_TO_MAKE_PROGRESS during a long final rotation. The
controller server therefore resets the progress checker once when ``goal_checker.xy_reached``
becomes true (the position part of the goal is met, only yaw remains) and from then on checks with
``turning=True``: a heading change of FINAL_TURN_PROGRESS counts as progress too (as Nav2's
PoseProgressChecker's ``required_movement_angle``). A robot that can neither move nor turn there
(wedged against an obstacle) still fails after ``movement_time_allowance`` instead of turning
forever.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nav_stack.core.control.base import Twist2D
from nav_stack.core.geometry import Pose2D, angle_diff

FINAL_TURN_PROGRESS = 0.5  # rad: heading change that counts as progress while turning at the goal


@dataclass(frozen=True)
class GoalCheckerParams:
    """SimpleGoalChecker knobs; the stopped_* knobs are used by StoppedGoalChecker only."""

    xy_goal_tolerance: float = 0.25  # m
    yaw_goal_tolerance: float = 0.25  # rad
    stateful: bool = True  # once xy is reached, only yaw is checked until reset()
    symmetric_yaw_tolerance: bool = False  # also accept the goal yaw + π (robots that may reverse)
    trans_stopped_velocity: float = 0.25  # m/s
    rot_stopped_velocity: float = 0.25  # rad/s

    def __post_init__(self) -> None:
        for name in (
            "xy_goal_tolerance",
            "yaw_goal_tolerance",
            "trans_stopped_velocity",
            "rot_stopped_velocity",
        ):
            value = getattr(self, name)
            if not (value >= 0.0 and math.isfinite(value)):
                raise ValueError(f"GoalCheckerParams.{name} must be a finite value >= 0, got {value}")


class SimpleGoalChecker:
    """Goal reached when within xy and yaw tolerance (xy latched when ``stateful``)."""

    def __init__(self, params: GoalCheckerParams | None = None) -> None:
        self.params = params or GoalCheckerParams()
        self.xy_reached = False

    def reset(self) -> None:
        """Forget the latched xy state (new goal)."""
        self.xy_reached = False

    def within_xy(self, pose: Pose2D, goal: Pose2D) -> bool:
        return math.hypot(pose.x - goal.x, pose.y - goal.y) <= self.params.xy_goal_tolerance

    def yaw_error(self, pose: Pose2D, goal: Pose2D) -> float:
        """|heading error| (rad), the smaller of the two ends when the tolerance is symmetric."""
        err = abs(angle_diff(goal.yaw, pose.yaw))
        return min(err, math.pi - err) if self.params.symmetric_yaw_tolerance else err

    def is_goal_reached(self, pose: Pose2D, goal: Pose2D, velocity: Twist2D) -> bool:
        if not (self.params.stateful and self.xy_reached):
            self.xy_reached = self.within_xy(pose, goal)
        return self.xy_reached and self.yaw_error(pose, goal) <= self.params.yaw_goal_tolerance


class StoppedGoalChecker(SimpleGoalChecker):
    """SimpleGoalChecker that also requires the robot to be (nearly) stopped."""

    def is_goal_reached(self, pose: Pose2D, goal: Pose2D, velocity: Twist2D) -> bool:
        if not super().is_goal_reached(pose, goal, velocity):
            return False
        return (
            abs(velocity.vx) <= self.params.trans_stopped_velocity
            and abs(velocity.wz) <= self.params.rot_stopped_velocity
        )


@dataclass(frozen=True)
class ProgressCheckerParams:
    """SimpleProgressChecker knobs (Nav2 defaults)."""

    required_movement_radius: float = 0.5  # m
    movement_time_allowance: float = 10.0  # s

    def __post_init__(self) -> None:
        if not self.required_movement_radius > 0.0 or not self.movement_time_allowance > 0.0:
            raise ValueError(f"ProgressCheckerParams need a radius > 0 m and allowance > 0 s, got {self}")


class SimpleProgressChecker:
    """Fails when the robot stays within ``required_movement_radius`` for ``movement_time_allowance``.

    Rotation counts only at the goal (``turning``; see the module docstring).
    """

    def __init__(self, params: ProgressCheckerParams | None = None) -> None:
        self.params = params or ProgressCheckerParams()
        self._baseline: Pose2D | None = None
        self._baseline_time = 0.0

    def reset(self) -> None:
        """Drop the baseline; the next check starts a fresh window at the pose it is given."""
        self._baseline = None

    def check(self, pose: Pose2D, now: float, turning: bool = False) -> bool:
        """True while progress is adequate; ``now`` in seconds (sim or steady clock).

        ``turning``: the robot is turning at the goal, so FINAL_TURN_PROGRESS of heading counts too.
        """
        base = self._baseline
        if (
            base is None
            or math.hypot(pose.x - base.x, pose.y - base.y) > self.params.required_movement_radius
            or (turning and abs(angle_diff(pose.yaw, base.yaw)) > FINAL_TURN_PROGRESS)
        ):
            self._baseline, self._baseline_time = pose, now
            return True
        return now - self._baseline_time <= self.params.movement_time_allowance
