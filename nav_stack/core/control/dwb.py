"""DWB local planner: sample (vx, ωz) in the dynamic window, simulate, score with critics, pick the lowest.

Trajectory generation follows DWB's StandardTrajectoryGenerator: the velocity window is the
current velocity ± the acceleration/deceleration limits over ``sim_time``, clipped to the
velocity limits; each sampled command is simulated for ``sim_time`` with the velocity ramping
from the current one at the acceleration limits, in steps no longer than
``linear_granularity`` / ``angular_granularity``. All K = vx_samples × vtheta_samples trajectories
are simulated and scored as arrays. Score = Σ scale·critic; ``inf`` rejects; if every trajectory
is rejected the controller raises NoValidControl (FollowPath 106).

Defaults are the TB3 values of Nav2's nav2_params.yaml (Humble, DWB as default controller).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nav_stack.core.control.base import CircleFootprint, CostGrid, Footprint, NoValidControl, Twist2D
from nav_stack.core.control.dwb_critics import (
    CriticContext,
    MapGridScorer,
    OscillationState,
    RotateToGoalState,
    Trajectories,
    base_obstacle,
    forward_points,
    oscillation,
    oscillation_debrief,
    rotate_to_goal,
)
from nav_stack.core.geometry import FloatArray, Pose2D


@dataclass(frozen=True)
class DWBParams:
    """DWB knobs (Nav2 names); critic scales of the TB3 configuration."""

    min_vel_x: float = 0.0
    max_vel_x: float = 0.26
    max_vel_theta: float = 1.0
    min_speed_xy: float = 0.0
    max_speed_xy: float = 0.26
    min_speed_theta: float = 0.0
    acc_lim_x: float = 2.5
    acc_lim_theta: float = 3.2
    decel_lim_x: float = -2.5
    decel_lim_theta: float = -3.2
    vx_samples: int = 20
    vtheta_samples: int = 20
    sim_time: float = 1.7  # s
    linear_granularity: float = 0.05  # m
    angular_granularity: float = 0.025  # rad
    # critics
    base_obstacle_scale: float = 0.02
    base_obstacle_sum_scores: bool = False
    path_align_scale: float = 32.0
    path_align_forward_point_distance: float = 0.1
    goal_align_scale: float = 24.0
    goal_align_forward_point_distance: float = 0.1
    path_dist_scale: float = 32.0
    goal_dist_scale: float = 24.0
    rotate_to_goal_scale: float = 32.0
    rotate_to_goal_slowing_factor: float = 5.0
    rotate_to_goal_lookahead_time: float = -1.0
    oscillation_scale: float = 1.0
    oscillation_reset_dist: float = 0.05
    oscillation_reset_angle: float = 0.2
    x_only_threshold: float = 0.05
    xy_goal_tolerance: float = 0.25  # the critics' goal window
    trans_stopped_velocity: float = 0.25

    def __post_init__(self) -> None:
        if self.vx_samples < 1 or self.vtheta_samples < 1:
            raise ValueError(
                f"DWBParams samples must be >= 1, got vx {self.vx_samples} vtheta {self.vtheta_samples}"
            )
        if not (self.sim_time > 0 and self.linear_granularity > 0 and self.angular_granularity > 0):
            raise ValueError("DWBParams sim_time, linear_granularity and angular_granularity must be > 0")
        if self.max_vel_x < self.min_vel_x or self.max_vel_theta < 0:
            raise ValueError(
                f"DWBParams velocity limits are inconsistent: min_vel_x {self.min_vel_x}, "
                f"max_vel_x {self.max_vel_x}, max_vel_theta {self.max_vel_theta}"
            )
        if (
            self.acc_lim_x <= 0
            or self.acc_lim_theta <= 0
            or self.decel_lim_x >= 0
            or self.decel_lim_theta >= 0
        ):
            raise ValueError("DWBParams acc_lim_* must be > 0 and decel_lim_* < 0")


def _window(
    current: float, lo: float, hi: float, acc: float, decel: float, horizon: float, n: int
) -> FloatArray:
    top = min(hi, current + acc * horizon)
    bottom = max(lo, current + decel * horizon)
    if bottom > top:  # current speed outside the limits: sample only what is reachable toward them
        bottom = top = min(max(current, lo), hi)
    return np.linspace(bottom, top, n) if n > 1 else np.array([top])


def generate_trajectories(p: DWBParams, robot: Pose2D, velocity: Twist2D) -> Trajectories:
    """All admissible samples of the dynamic window and their simulated poses (K, T+1, 3)."""
    vx = _window(velocity.vx, p.min_vel_x, p.max_vel_x, p.acc_lim_x, p.decel_lim_x, p.sim_time, p.vx_samples)
    wz = _window(
        velocity.wz,
        -p.max_vel_theta,
        p.max_vel_theta,
        p.acc_lim_theta,
        p.decel_lim_theta,
        p.sim_time,
        p.vtheta_samples,
    )
    cmd = np.stack(np.meshgrid(vx, wz, indexing="ij"), axis=-1).reshape(-1, 2)
    speed = np.abs(cmd[:, 0])
    valid = (speed <= p.max_speed_xy + 1e-9) & ~((speed == 0.0) & (cmd[:, 1] == 0.0))
    if p.min_speed_xy > 0:
        valid &= ~((speed < p.min_speed_xy) & (np.abs(cmd[:, 1]) < p.min_speed_theta))
    cmd = cmd[valid]
    steps = max(
        1,
        math.ceil(
            max(
                np.abs(cmd[:, 0]).max(initial=0.0) * p.sim_time / p.linear_granularity,
                np.abs(cmd[:, 1]).max(initial=0.0) * p.sim_time / p.angular_granularity,
            )
        ),
    )
    dt = p.sim_time / steps
    t = dt * np.arange(1, steps + 1)
    # velocity ramps from the current one toward each sample at the acceleration limits
    v = velocity.vx + np.minimum(np.maximum(cmd[:, :1] - velocity.vx, p.decel_lim_x * t), p.acc_lim_x * t)
    w = velocity.wz + np.minimum(
        np.maximum(cmd[:, 1:] - velocity.wz, p.decel_lim_theta * t), p.acc_lim_theta * t
    )
    poses = np.empty((len(cmd), steps + 1, 3))
    poses[:, 0] = robot
    yaw = poses[:, :, 2]
    np.cumsum(w * dt, axis=1, out=yaw[:, 1:])
    yaw += robot.yaw
    step = v * dt
    np.cumsum(step * np.cos(yaw[:, :-1]), axis=1, out=poses[:, 1:, 0])
    np.cumsum(step * np.sin(yaw[:, :-1]), axis=1, out=poses[:, 1:, 1])
    poses[:, 1:, 0] += robot.x
    poses[:, 1:, 1] += robot.y
    return Trajectories(cmd, poses)


class DWBController:
    """Stateful DWB (oscillation and rotate-to-goal latches); call ``reset()`` for a new path."""

    def __init__(self, params: DWBParams | None = None, footprint: Footprint | None = None) -> None:
        self.params = params or DWBParams()
        self.footprint: Footprint = footprint or CircleFootprint()
        self._oscillation = OscillationState()
        self._rotate = RotateToGoalState()
        self.last_trajectory: FloatArray = np.zeros((0, 3))

    def reset(self) -> None:
        self._oscillation = OscillationState()
        self._rotate = RotateToGoalState()

    def score(
        self, robot: Pose2D, velocity: Twist2D, path: FloatArray, grid: CostGrid
    ) -> tuple[Trajectories, FloatArray]:
        """Trajectories and their total scores (inf = rejected)."""
        p = self.params
        goal = Pose2D(*(float(v) for v in path[-1]))
        ctx = CriticContext(robot, velocity, path, goal, grid, self.footprint)
        traj = generate_trajectories(p, robot, velocity)
        end = traj.poses[:, -1]
        total = p.base_obstacle_scale * base_obstacle(ctx, traj, p.base_obstacle_sum_scores)
        total += p.oscillation_scale * oscillation(traj, self._oscillation, p.x_only_threshold)
        total += p.rotate_to_goal_scale * rotate_to_goal(
            ctx,
            traj,
            self._rotate,
            p.xy_goal_tolerance,
            p.trans_stopped_velocity,
            p.rotate_to_goal_slowing_factor,
            p.rotate_to_goal_lookahead_time,
        )
        near_goal = math.hypot(robot.x - goal.x, robot.y - goal.y) <= p.xy_goal_tolerance
        forward_path = forward_points(traj, p.path_align_forward_point_distance)
        forward_goal = forward_points(traj, p.goal_align_forward_point_distance)
        path_end, path_fwd = MapGridScorer(ctx, path).score(end[:, 0], end[:, 1], *forward_path)
        goal_end, goal_fwd = MapGridScorer(ctx, path[-1:]).score(end[:, 0], end[:, 1], *forward_goal)
        total += p.path_dist_scale * path_end + p.goal_dist_scale * goal_end
        if not near_goal:  # alignment is meaningless once only the final rotation remains
            total += p.path_align_scale * path_fwd + p.goal_align_scale * goal_fwd
        return traj, total

    def compute_velocity(self, robot: Pose2D, velocity: Twist2D, path: FloatArray, grid: CostGrid) -> Twist2D:
        """Best command for this cycle; NoValidControl when every trajectory is rejected."""
        if len(path) == 0:
            raise NoValidControl("empty local path")
        traj, total = self.score(robot, velocity, path, grid)
        if len(total) == 0 or not np.isfinite(total).any():
            raise NoValidControl(f"no valid trajectories out of {len(total)}")
        best = int(np.argmin(total))
        cmd = Twist2D(float(traj.commands[best, 0]), float(traj.commands[best, 1]))
        self.last_trajectory = traj.poses[best]
        p = self.params
        oscillation_debrief(
            self._oscillation,
            cmd,
            robot,
            p.oscillation_reset_dist,
            p.oscillation_reset_angle,
            p.x_only_threshold,
        )
        return cmd
