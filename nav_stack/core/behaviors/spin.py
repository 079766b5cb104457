"""Spin in place by a relative angle (nav2_behaviors Spin).

Command law each cycle: ω = clamp(√(2·rotational_acc_lim·remaining), min_rotational_vel,
max_rotational_vel) with the sign of the target, so the robot decelerates onto the target as if
braking at the acceleration limit. Turned angle is accumulated from successive yaw readings,
so targets beyond ±π work.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nav_stack.core.behaviors.base import BehaviorParams, BehaviorResult, CollisionLookahead, SpinErrorCode
from nav_stack.core.control.base import CostGrid, Footprint, Twist2D
from nav_stack.core.geometry import Pose2D, angle_diff


@dataclass(frozen=True)
class SpinGoal:
    target_yaw: float  # rad, relative; sign = direction
    time_allowance: float = 10.0  # s


def spin_speed(params: BehaviorParams, remaining: float, target_sign: float) -> float:
    """Yaw rate (rad/s) for ``remaining`` (rad, ≥ 0) of rotation left."""
    speed = math.sqrt(2.0 * params.rotational_acc_lim * max(remaining, 0.0))
    return math.copysign(min(max(speed, params.min_rotational_vel), params.max_rotational_vel), target_sign)


class Spin:
    """State machine: ``start`` then ``step`` until a :class:`BehaviorResult` comes back."""

    def __init__(self, params: BehaviorParams | None = None, footprint: Footprint | None = None) -> None:
        self.params = params or BehaviorParams()
        self._lookahead = CollisionLookahead(self.params, footprint)
        self._goal = SpinGoal(0.0)
        self._start_time = 0.0
        self._prev_yaw = 0.0
        self.angular_distance_traveled = 0.0  # feedback (rad)
        self._turned = 0.0

    def start(self, goal: SpinGoal, pose: Pose2D, now: float) -> BehaviorResult | None:
        if not (math.isfinite(goal.target_yaw) and math.isfinite(goal.time_allowance)):
            return BehaviorResult(SpinErrorCode.UNKNOWN, f"spin goal is not finite: {goal}", 0.0)
        self._goal, self._start_time, self._prev_yaw = goal, now, pose.yaw
        self._turned = self.angular_distance_traveled = 0.0
        return None

    def step(self, pose: Pose2D, now: float, grid: CostGrid | None = None) -> Twist2D | BehaviorResult:
        elapsed = now - self._start_time
        if elapsed > self._goal.time_allowance:
            return BehaviorResult(
                SpinErrorCode.TIMEOUT,
                f"spin did not finish within {self._goal.time_allowance:.2f} s",
                elapsed,
            )
        self._turned += angle_diff(pose.yaw, self._prev_yaw)
        self._prev_yaw = pose.yaw
        self.angular_distance_traveled = abs(self._turned)
        remaining = abs(self._goal.target_yaw) - abs(self._turned)
        if remaining < 1e-6:
            return BehaviorResult(SpinErrorCode.NONE, "", elapsed)
        cmd = Twist2D(0.0, spin_speed(self.params, remaining, self._goal.target_yaw))
        if grid is not None and self._lookahead.collision_ahead(pose, cmd, grid, max_rotation=remaining):
            return BehaviorResult(
                SpinErrorCode.COLLISION_AHEAD, "collision ahead: cannot safely execute spin", elapsed
            )
        return cmd
