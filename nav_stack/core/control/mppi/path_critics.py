"""The path-tracking MPPI critics in plain numpy (PathAlign, PathFollow, PathAngle) and the per-cycle
facts they share; critics_jit.py compiles the same.

Two facts are computed once per cycle, on first use, as Nav2's CriticData optionals are: the
*furthest reached* path point (trajectories in batch order; each end's nearest path point, searched
from the furthest found so far; the furthest of those) and which path points are *valid* (on the grid
and below the inscribed cost). Distances use sqrt(dx² + dy²) as Nav2 does.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from nav_stack.core.control.mppi.critic_params import PathAngleMode
from nav_stack.core.control.mppi.params import MPPIParams
from nav_stack.core.control.mppi.scene import Rollouts, Scene
from nav_stack.core.geometry import FloatArray, angle_diff, angle_diffs
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE, IntArray

BoolArray = np.ndarray


def powered(term: FloatArray, weight: float, power: int) -> FloatArray:
    """A critic's (weight · term)^power."""
    return np.asarray((term * weight) ** power if power > 1 else term * weight)


def arc_lengths(points: FloatArray) -> FloatArray:
    """Distance (m) along the points from the first to each."""
    d = np.diff(points[:, :2], axis=0)
    return np.concatenate(([0.0], np.cumsum(np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]))))


class CycleFacts:
    """Per-cycle facts several critics share, computed on first use (Nav2's CriticData optionals)."""

    def __init__(self, scene: Scene, rollouts: Rollouts, params: MPPIParams, min_turning_r: float) -> None:
        self.scene, self.rollouts, self.params, self.min_turning_r = scene, rollouts, params, min_turning_r
        self._furthest: int | None = None
        self._valid: BoolArray | None = None

    @property
    def furthest_reached(self) -> int:
        """Nav2's findPathFurthestReachedPoint (an index into the path, 0..N-1)."""
        if self._furthest is None:
            path, r = self.scene.path, self.rollouts
            d2 = (r.x[:, -1:] - path[:, 0]) ** 2 + (r.y[:, -1:] - path[:, 1]) ** 2
            furthest = 0
            for row in d2:
                furthest = max(furthest, furthest + int(np.argmin(row[furthest:])))
            self._furthest = furthest
        return self._furthest

    @property
    def path_valid(self) -> BoolArray:
        """Whether path points 0..N-2 are free to stand on (off-grid, inscribed, lethal, unknown: not)."""
        if self._valid is None:
            path = self.scene.path[:-1]
            cost = self.scene.grid.cost_at(path[:, 0], path[:, 1])
            self._valid = np.asarray(cost < INSCRIBED_INFLATED_OBSTACLE)
        return self._valid


def closest_path_point(along: FloatArray, dist: FloatArray, start: IntArray) -> IntArray:
    """Nav2's findClosestPathPt for many trajectories: the path point whose arc length ``along`` is
    nearest ``dist``, searched from index ``start`` + 1 on (a tie goes to the later point)."""
    i = np.maximum(np.searchsorted(along, dist, side="right"), start + 1)
    beyond = i >= len(along)
    i = np.minimum(i, len(along) - 1)
    earlier = (dist - along[i - 1]) < (along[i] - dist)
    return np.asarray(np.where(beyond, len(along) - 1, np.where(earlier, i - 1, i)), dtype=np.int64)


def occupied(valid: BoolArray, furthest: int, ratio: float) -> bool:
    """Whether more than ``ratio`` of the path points before the furthest reached one (and more than
    two) are blocked: then the path is taken by an obstacle and PathAlign lets the others steer."""
    blocked = np.cumsum(~valid[:furthest])
    return bool(np.any((blocked / max(furthest, 1) > ratio) & (blocked > 2)))


def path_align_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> FloatArray:
    """PathAlignCritic: the mean distance from every ``trajectory_point_step``-th pose to the valid
    path point at the same distance along the path (yaw difference too with use_path_orientations);
    off near the goal, before any trajectory reaches offset_from_furthest points along, and when the
    path is occupied. Only the path before the furthest reached point counts, as in Nav2 Jazzy: a pose
    that has travelled further is compared with the last point before it."""
    zeros = np.zeros(len(r.x))
    path = scene.path
    if len(path) < 2 or scene.goal_within(p.threshold_to_consider):
        return zeros
    furthest = ctx.furthest_reached
    if furthest < max(p.offset_from_furthest, 1) or occupied(ctx.path_valid, furthest,
                                                             p.max_path_occupancy_ratio):
        return zeros
    points = path[:furthest]
    along = arc_lengths(points)
    cols = np.arange(0, r.x.shape[1], p.trajectory_point_step)
    x, y, yaw = r.x[:, cols], r.y[:, cols], r.yaw[:, cols]
    dx, dy = np.diff(x, axis=1), np.diff(y, axis=1)
    travelled = np.cumsum(np.sqrt(dx * dx + dy * dy), axis=1)
    total, count = np.zeros(len(r.x)), np.zeros(len(r.x))
    nearest = np.zeros(len(r.x), dtype=np.int64)
    for k in range(travelled.shape[1]):
        nearest = closest_path_point(along, travelled[:, k], nearest)
        valid = ctx.path_valid[nearest]
        ex, ey = points[nearest, 0] - x[:, k + 1], points[nearest, 1] - y[:, k + 1]
        d2 = ex * ex + ey * ey
        if p.use_path_orientations:
            turn = angle_diffs(yaw[:, k + 1], points[nearest, 2])
            d2 = d2 + turn * turn
        total += np.where(valid, np.sqrt(d2), 0.0)
        count += valid
    mean = np.where(count > 0, total / np.maximum(count, 1), 0.0)
    return powered(mean, p.cost_weight, p.cost_power)


def follow_index(path_len: int, furthest: int, offset: int, valid: BoolArray) -> int:
    """The path point PathFollow aims at: offset beyond the furthest reached, moved on past blocked
    points (but not onto the last one)."""
    last = path_len - 1
    index = min(furthest + offset, last)
    while index < last - 1 and not valid[index]:
        index += 1
    return index


def path_follow_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> FloatArray:
    """PathFollowCritic: the distance from each trajectory's end to the follow point; off near the goal."""
    path = scene.path
    if len(path) < 2 or scene.goal_within(p.threshold_to_consider):
        return np.zeros(len(r.x))
    target = path[follow_index(len(path), ctx.furthest_reached, p.offset_from_furthest, ctx.path_valid)]
    ex, ey = r.x[:, -1] - target[0], r.y[:, -1] - target[1]
    return powered(np.sqrt(ex * ex + ey * ey), p.cost_weight, p.cost_power)


def effective_path_angle_mode(mode: int, params: MPPIParams) -> int:
    """Nav2 falls back to forward preference when reversing is not allowed (vx_min >= 0)."""
    if mode == PathAngleMode.NO_DIRECTIONAL_PREFERENCE and params.vx_min >= 0.0:
        return int(PathAngleMode.FORWARD_PREFERENCE)
    return int(mode)


def heading_error(mode: int, yaw: float, bearing: float, path_yaw: float) -> float:
    """|angle| between a heading and the bearing to the path point (Nav2's posePointAngle): mode 1
    also accepts driving there backwards; mode 2 flips the bearing where the path runs the other way."""
    if mode == PathAngleMode.NO_DIRECTIONAL_PREFERENCE:
        return min(abs(angle_diff(yaw, bearing)), abs(angle_diff(yaw + math.pi, bearing)))
    if mode == PathAngleMode.CONSIDER_FEASIBLE_PATH_ORIENTATIONS and \
            abs(angle_diff(path_yaw, bearing)) > math.pi / 2:
        bearing += math.pi
    return abs(angle_diff(yaw, bearing))


def path_angle_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> FloatArray:
    """PathAngleCritic: when the robot points more than max_angle_to_furthest away from the path point
    offset_from_furthest beyond the furthest reached, the mean angle between each pose's heading and
    its bearing to that point (flipped per ``mode``); off near the goal."""
    zeros = np.zeros(len(r.x))
    if scene.goal_within(p.threshold_to_consider):
        return zeros
    target = scene.path[min(ctx.furthest_reached + p.offset_from_furthest, len(scene.path) - 1)]
    mode = effective_path_angle_mode(p.mode, ctx.params)
    robot = scene.robot
    bearing = math.atan2(target[1] - robot.y, target[0] - robot.x)
    if heading_error(mode, robot.yaw, bearing, float(target[2])) < p.max_angle_to_furthest:
        return zeros
    bearings = np.arctan2(target[1] - r.y, target[0] - r.x)
    if mode == PathAngleMode.NO_DIRECTIONAL_PREFERENCE:
        flip = np.abs(angle_diffs(bearings, r.yaw)) >= math.pi / 2
        bearings = np.where(flip, angle_diffs(bearings + math.pi, 0.0), bearings)
    elif mode == PathAngleMode.CONSIDER_FEASIBLE_PATH_ORIENTATIONS:
        flip = np.abs(angle_diffs(target[2], bearings)) >= math.pi / 2
        bearings = np.where(flip, angle_diffs(bearings + math.pi, 0.0), bearings)
    error = np.abs(angle_diffs(bearings, r.yaw))
    return powered(error.mean(axis=1), p.cost_weight, p.cost_power)
