"""DriveOnHeading and BackUp: drive straight at constant speed until a distance is covered.

The distance is measured in the local (odom) frame from the start pose. DriveOnHeading requires
``target.x`` and ``speed`` of the same sign; BackUp forces both negative (clients send positive
values), as Nav2 does. Either rejects a target with y or z ≠ 0 (INVALID_INPUT).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from nav_stack.core.behaviors.base import (
    BackUpErrorCode,
    BehaviorParams,
    BehaviorResult,
    CollisionLookahead,
    DriveOnHeadingErrorCode,
)
from nav_stack.core.control.base import CostGrid, Footprint, Twist2D
from nav_stack.core.geometry import Pose2D


@dataclass(frozen=True)
class DriveGoal:
    """geometry_msgs/Point target (only x used), speed (m/s), time allowance (s)."""

    target_x: float
    speed: float
    time_allowance: float = 10.0
    target_y: float = 0.0
    target_z: float = 0.0


class DriveOnHeading:
    """State machine: ``start`` then ``step`` until a :class:`BehaviorResult` comes back."""

    codes: type[DriveOnHeadingErrorCode] | type[BackUpErrorCode] = DriveOnHeadingErrorCode
    name = "drive_on_heading"

    def __init__(self, params: BehaviorParams | None = None, footprint: Footprint | None = None) -> None:
        self.params = params or BehaviorParams()
        self._lookahead = CollisionLookahead(self.params, footprint)
        self._goal = DriveGoal(0.0, 0.0)
        self._origin = Pose2D(0.0, 0.0, 0.0)
        self._start_time = 0.0
        self.distance_traveled = 0.0  # feedback (m)

    def _normalise(self, goal: DriveGoal) -> DriveGoal | str:
        if (goal.target_x > 0.0) != (goal.speed > 0.0):
            return f"speed {goal.speed} and target x {goal.target_x} must have the same sign"
        return goal

    def start(self, goal: DriveGoal, pose: Pose2D, now: float) -> BehaviorResult | None:
        invalid = _code(self.codes, "INVALID_INPUT")
        if goal.target_y != 0.0 or goal.target_z != 0.0:
            return BehaviorResult(
                invalid,
                f"{self.name} only drives along x; got target y {goal.target_y}, z {goal.target_z}",
                0.0,
            )
        if not all(math.isfinite(v) for v in (goal.target_x, goal.speed, goal.time_allowance)):
            return BehaviorResult(invalid, f"{self.name} goal is not finite: {goal}", 0.0)
        normalised = self._normalise(goal)
        if isinstance(normalised, str):
            return BehaviorResult(invalid, normalised, 0.0)
        self._goal, self._origin, self._start_time = normalised, pose, now
        self.distance_traveled = 0.0
        return None

    def step(self, pose: Pose2D, now: float, grid: CostGrid | None = None) -> Twist2D | BehaviorResult:
        elapsed = now - self._start_time
        if elapsed > self._goal.time_allowance:
            return BehaviorResult(
                _code(self.codes, "TIMEOUT"),
                f"{self.name} did not cover "
                f"{abs(self._goal.target_x):.3f} m within {self._goal.time_allowance:.2f} s",
                elapsed,
            )
        self.distance_traveled = math.hypot(pose.x - self._origin.x, pose.y - self._origin.y)
        remaining = abs(self._goal.target_x) - self.distance_traveled
        if remaining <= 0.0:
            return BehaviorResult(0, "", elapsed)
        cmd = Twist2D(self._goal.speed, 0.0)
        if grid is not None and self._lookahead.collision_ahead(pose, cmd, grid, max_distance=remaining):
            return BehaviorResult(
                _code(self.codes, "COLLISION_AHEAD"),
                f"collision ahead: cannot safely execute {self.name}",
                elapsed,
            )
        return cmd


class BackUp(DriveOnHeading):
    """DriveOnHeading backwards: target and speed magnitudes are used, both made negative."""

    codes = BackUpErrorCode
    name = "backup"

    def _normalise(self, goal: DriveGoal) -> DriveGoal | str:
        return DriveGoal(-abs(goal.target_x), -abs(goal.speed), goal.time_allowance)


def _code(codes: type[enum.IntEnum], name: str) -> int:
    return int(codes[name])
