"""Rotation Shim (nav2_rotation_shim_controller): fast in-place turns in front of another controller.

Why: DWB scores where each sampled trajectory ends after ``sim_time``, so it turns toward a new
path at roughly (heading error)/sim_time and settles slowly on a heading. Nav2's answer is this
shim. While the heading to a path point ``forward_sampling_distance`` ahead is off by more than
``angular_dist_threshold``, it turns in place at ``rotate_to_heading_angular_vel``, within
``max_angular_accel``, braking so as to stop on the heading; below ``angular_disengage_threshold``
it hands the path to the primary controller. With ``rotate_to_goal_heading`` it also takes over the
final turn onto the goal's yaw once the goal is within ``goal_dist_tol`` (the goal checker's
xy tolerance). A turn that would put the footprint into an obstacle raises NoValidControl, as Nav2
does after simulating ``simulate_ahead_time`` of it.

Differences from Nav2 Jazzy: the path heading is checked on every cycle rather than after each
new path (this stack sends the path again at 1 Hz while replanning, so Nav2 checks about as
often), and the goal-heading turn is latched per goal like RPP's ``stateful``: localization
jitter during the turn must not hand the robot back to the primary 0.26 m from the goal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from nav_stack.core.control.base import (
    CostGrid,
    Footprint,
    NoValidControl,
    Twist2D,
    motion_collides,
    turn_in_place,
)
from nav_stack.core.control.server import LocalController
from nav_stack.core.geometry import FloatArray, Pose2D, normalize_angles


@dataclass(frozen=True)
class RotationShimParams:
    """Nav2's parameter names and code defaults; ``goal_dist_tol`` and ``controller_frequency`` come
    from the controller server (goal checker, control rate)."""

    angular_dist_threshold: float = 0.785  # rad: start turning in place above this heading error
    angular_disengage_threshold: float = 0.785  # rad: hand over to the primary below this one
    forward_sampling_distance: float = 0.5  # m along the path to the point whose heading is compared
    rotate_to_heading_angular_vel: float = 1.8  # rad/s
    max_angular_accel: float = 3.2  # rad/s²
    simulate_ahead_time: float = 1.0  # s of the turn checked for collisions
    rotate_to_goal_heading: bool = False
    goal_dist_tol: float = 0.25  # m
    controller_frequency: float = 20.0  # Hz

    def __post_init__(self) -> None:
        if not 0.0 <= self.angular_disengage_threshold <= self.angular_dist_threshold:
            raise ValueError(
                "RotationShimParams: need 0 <= angular_disengage_threshold <= angular_dist_threshold, got "
                f"{self.angular_disengage_threshold} and {self.angular_dist_threshold}"
            )
        for name in ("rotate_to_heading_angular_vel", "max_angular_accel", "controller_frequency",
                     "forward_sampling_distance"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"RotationShimParams.{name} must be > 0, got {getattr(self, name)}")


def sampled_heading_error(robot: Pose2D, path: FloatArray, distance: float) -> float:
    """Angle (rad, + = left) from the robot's heading to the first path pose at least ``distance``
    (m) from the robot, or to the path's end when none is that far."""
    offsets = np.hypot(path[:, 0] - robot.x, path[:, 1] - robot.y)
    beyond = np.nonzero(offsets >= distance)[0]
    x, y = path[int(beyond[0]) if len(beyond) else -1, :2]
    return float(normalize_angles(np.array(math.atan2(y - robot.y, x - robot.x) - robot.yaw)))


class RotationShim:
    """Wraps a primary controller (DWB, RPP); ``params`` are the shim's own."""

    def __init__(self, primary: LocalController, params: RotationShimParams | None = None,
                 footprint: Footprint | None = None) -> None:
        self.primary = primary
        self.params = params or RotationShimParams()
        self.footprint = footprint
        self.rotating = False  # turning toward the path heading (the disengage threshold applies)
        self._heading_goal: tuple[float, float] | None = None  # goal whose yaw the shim turns onto

    @property
    def last_trajectory(self) -> Any:
        """The primary's last local plan (for /local_plan); empty while the shim turns."""
        return None if self.rotating else getattr(self.primary, "last_trajectory", None)

    def reset(self) -> None:
        self.rotating = False
        self._heading_goal = None
        self.primary.reset()

    def compute_velocity(self, robot: Pose2D, velocity: Twist2D, path: FloatArray, grid: CostGrid) -> Twist2D:
        if len(path) == 0:
            raise NoValidControl("empty local path")
        p = self.params
        goal = path[-1]
        if p.rotate_to_goal_heading and self._near_goal(robot, goal):
            self.rotating = False
            yaw_error = float(normalize_angles(np.array(goal[2] - robot.yaw)))
            return self._turn(robot, velocity, yaw_error, grid)
        error = sampled_heading_error(robot, path, p.forward_sampling_distance)
        threshold = p.angular_disengage_threshold if self.rotating else p.angular_dist_threshold
        if abs(error) > threshold:
            self.rotating = True
            return self._turn(robot, velocity, error, grid)
        self.rotating = False
        return self.primary.compute_velocity(robot, velocity, path, grid)

    def _near_goal(self, robot: Pose2D, goal: FloatArray) -> bool:
        """Within goal_dist_tol of the goal, or still turning onto the heading of this same goal."""
        goal_xy = (float(goal[0]), float(goal[1]))
        if self._heading_goal is not None and math.dist(self._heading_goal, goal_xy) < 1e-3:
            return True
        if math.hypot(goal[0] - robot.x, goal[1] - robot.y) <= self.params.goal_dist_tol:
            self._heading_goal = goal_xy
            return True
        return False

    def _turn(self, robot: Pose2D, velocity: Twist2D, angle: float, grid: CostGrid) -> Twist2D:
        p = self.params
        wz = turn_in_place(angle, velocity.wz, p.rotate_to_heading_angular_vel, p.max_angular_accel,
                           1.0 / p.controller_frequency)
        if self.footprint is not None:
            steps = np.linspace(0.0, p.simulate_ahead_time, 11)
            yaws = robot.yaw + np.clip(wz * steps, -abs(angle), abs(angle))  # no further than the target
            xs, ys = np.full_like(yaws, robot.x), np.full_like(yaws, robot.y)
            if motion_collides(self.footprint, grid, xs, ys, yaws):
                raise NoValidControl("the in-place turn toward the path heading would collide")
        return Twist2D(0.0, wz)
