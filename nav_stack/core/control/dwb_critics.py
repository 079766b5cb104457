"""DWB critics, vectorised: each scores all K sampled trajectories at once.

A critic returns a (K,) float array; ``inf`` rejects a trajectory (DWB's IllegalTrajectory).
The map-grid critics (PathDist, GoalDist, PathAlign, GoalAlign) score the trajectory end (or a
point ``forward_point_distance`` ahead of it) by its 4-connected cell distance to the path or
the goal through non-obstacle cells, computed each cycle like DWB's MapGrid; unreachable cells
score the grid size, obstacle cells reject.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nav_stack.core.control.base import BoolArray, CostGrid, Footprint, IntArray, Twist2D
from nav_stack.core.geometry import FloatArray, Pose2D, normalize_angles
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE


@dataclass(frozen=True)
class Trajectories:
    """K sampled commands and their simulated poses: ``poses`` (K, T+1, 3), first column = robot."""

    commands: FloatArray  # (K, 2): vx, wz
    poses: FloatArray


@dataclass(frozen=True)
class CriticContext:
    """What the critics see in one cycle (all in the local costmap frame)."""

    robot: Pose2D
    velocity: Twist2D
    path: FloatArray  # (N, 3) pruned, cut local path
    goal: Pose2D  # last pose of ``path``
    grid: CostGrid
    footprint: Footprint


def grid_distance(passable: BoolArray, seeds: BoolArray, targets: IntArray) -> IntArray:
    """4-connected cell distance from ``seeds`` through ``passable`` cells (-1 = unreachable).

    Wavefront by whole-array dilation; stops once every flat index in ``targets`` has a value.
    """
    dist = np.full(passable.shape, -1, dtype=np.int64)
    frontier = seeds & passable
    dist[frontier] = 0
    flat = dist.reshape(-1)
    targets = targets[passable.reshape(-1)[targets]]
    d = 0
    while frontier.any() and (flat[targets] < 0).any():
        d += 1
        grown = np.zeros_like(frontier)
        grown[1:] |= frontier[:-1]
        grown[:-1] |= frontier[1:]
        grown[:, 1:] |= frontier[:, :-1]
        grown[:, :-1] |= frontier[:, 1:]
        frontier = grown & passable & (dist < 0)
        dist[frontier] = d
    return dist


def _flat_cells(grid: CostGrid, x: FloatArray, y: FloatArray) -> tuple[IntArray, BoolArray]:
    mx, my = grid.spec.world_to_cell(x, y)
    inside = grid.spec.in_bounds(mx, my)
    flat = np.where(inside, my * grid.spec.width + mx, 0)
    return flat, inside


def _path_seed(grid: CostGrid, path: FloatArray) -> BoolArray:
    """Cells under the path, densified to half a cell so no gap opens between poses."""
    seeds = np.zeros(grid.spec.shape, dtype=bool)
    pts = path[:, :2]
    if len(pts) > 1:
        seg = np.diff(pts, axis=0)
        n = np.maximum(1, np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / (0.5 * grid.spec.resolution))).astype(int)
        t = np.concatenate([np.arange(k) / k for k in n])
        base = np.repeat(np.arange(len(seg)), n)
        pts = np.vstack((pts[base] + t[:, None] * seg[base], pts[-1:]))
    flat, inside = _flat_cells(grid, pts[:, 0], pts[:, 1])
    seeds.reshape(-1)[flat[inside]] = True
    return seeds


class MapGridScorer:
    """Distance-map lookup shared by PathDist/PathAlign (path seeds) and GoalDist/GoalAlign (goal seed)."""

    def __init__(self, ctx: CriticContext, seed_path: FloatArray) -> None:
        self.ctx = ctx
        self.seeds = _path_seed(ctx.grid, seed_path)
        self.passable = ctx.grid.costs < INSCRIBED_INFLATED_OBSTACLE

    def score(
        self, x: FloatArray, y: FloatArray, fx: FloatArray, fy: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Scores of the points (x, y) and (fx, fy) (trajectory ends and forward points), one wavefront."""
        flat, inside = _flat_cells(self.ctx.grid, np.concatenate((x, fx)), np.concatenate((y, fy)))
        dist = grid_distance(self.passable, self.seeds, flat[inside]).reshape(-1)[flat]
        unreachable = float(self.ctx.grid.spec.width * self.ctx.grid.spec.height)
        out = np.where(dist < 0, unreachable, dist.astype(float))
        out[~inside | ~self.passable.reshape(-1)[flat]] = np.inf
        return out[: len(x)], out[len(x) :]


def base_obstacle(ctx: CriticContext, traj: Trajectories, sum_scores: bool = False) -> FloatArray:
    """Footprint cost along each trajectory (max, or sum); any collision rejects."""
    p = traj.poses
    cost = ctx.footprint.cost(ctx.grid, p[..., 0], p[..., 1], p[..., 2])
    score = cost.sum(axis=1) if sum_scores else cost.max(axis=1)
    return np.where(ctx.footprint.collides(cost).any(axis=1), np.inf, score.astype(float))


def forward_points(traj: Trajectories, distance: float) -> tuple[FloatArray, FloatArray]:
    end = traj.poses[:, -1]
    return end[:, 0] + distance * np.cos(end[:, 2]), end[:, 1] + distance * np.sin(end[:, 2])


@dataclass
class RotateToGoalState:
    """DWB RotateToGoal's latch: once stopped inside the goal window the robot only rotates."""

    rotating: bool = False


def rotate_to_goal(
    ctx: CriticContext,
    traj: Trajectories,
    state: RotateToGoalState,
    xy_goal_tolerance: float,
    trans_stopped_velocity: float,
    slowing_factor: float,
    lookahead_time: float,
) -> FloatArray:
    """0 outside the goal window; inside: slow down first, then rotate in place onto the goal yaw."""
    k = len(traj.commands)
    if math.hypot(ctx.robot.x - ctx.goal.x, ctx.robot.y - ctx.goal.y) > xy_goal_tolerance:
        state.rotating = False
        return np.zeros(k)
    end_yaw = traj.poses[:, -1, 2]
    if lookahead_time >= 0.0:
        end_yaw = ctx.robot.yaw + traj.commands[:, 1] * lookahead_time
    rotation = np.abs(normalize_angles(end_yaw - ctx.goal.yaw))
    speed = np.abs(traj.commands[:, 0])
    current = abs(ctx.velocity.vx)
    if not state.rotating and current <= trans_stopped_velocity:
        state.rotating = True
    if not state.rotating:
        return np.where(speed >= current, np.inf, slowing_factor * speed**2 + rotation)
    return np.where(speed > 0.0, np.inf, rotation)


@dataclass
class OscillationState:
    """Direction trends of the last commands and whether a flip happened since the last reset."""

    x_sign: int = 0
    w_sign: int = 0
    x_flipped: bool = False
    w_flipped: bool = False
    anchor: Pose2D | None = None


def oscillation(traj: Trajectories, state: OscillationState, x_only_threshold: float) -> FloatArray:
    """Reject commands that would reverse a direction that already reversed since the last reset."""
    vx, wz = traj.commands[:, 0], traj.commands[:, 1]
    bad = np.zeros(len(vx), dtype=bool)
    if state.x_flipped and state.x_sign != 0:
        bad |= np.sign(vx) == -state.x_sign
    if state.w_flipped and state.w_sign != 0:
        bad |= (np.abs(vx) < x_only_threshold) & (np.sign(wz) == -state.w_sign)
    return np.where(bad, np.inf, 0.0)


def oscillation_debrief(
    state: OscillationState,
    cmd: Twist2D,
    robot: Pose2D,
    reset_dist: float,
    reset_angle: float,
    x_only_threshold: float,
) -> None:
    """Record the chosen command; flips are forgotten once the robot moved or turned enough."""
    if state.anchor is not None and (
        math.hypot(robot.x - state.anchor.x, robot.y - state.anchor.y) >= reset_dist
        or abs(normalize_angles(np.array(robot.yaw - state.anchor.yaw))) >= reset_angle
    ):
        state.x_flipped = state.w_flipped = False
        state.anchor = None
    sx = int(np.sign(cmd.vx))
    if sx != 0:
        if state.x_sign != 0 and sx != state.x_sign:
            state.x_flipped, state.anchor = True, state.anchor or robot
        state.x_sign = sx
    sw = int(np.sign(cmd.wz))
    if sw != 0 and abs(cmd.vx) < x_only_threshold:
        if state.w_sign != 0 and sw != state.w_sign:
            state.w_flipped, state.anchor = True, state.anchor or robot
        state.w_sign = sw
