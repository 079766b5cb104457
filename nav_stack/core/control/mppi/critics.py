"""The MPPI critics in plain numpy: the readable reference of what kernels_jit computes.

Each critic returns the cost it adds to every trajectory (B,), as Nav2 Jazzy's critic of the same
name defines it (``(weight · term)^power``); the obstacle critics also say whether every trajectory
collides (Nav2's fail_flag, which makes the optimizer retry). Inputs: the scene (robot, path, goal,
costmap) and the rollouts (B, T). Semantics worth knowing:

* Costmap lookups: a point off the grid costs 255 (NO_INFORMATION); 253..255 collide for a round
  robot (unknown space collides: the local costmap does not track it); with ``consider_footprint``
  253 does not, the footprint's own cost decides.
* "Near the goal" is the robot's straight-line distance to the goal (Nav2's
  withinPositionGoalTolerance), not the path length.
* The path critics share two facts computed once per cycle: the furthest path point any
  trajectory's end comes nearest to, and which path points are free.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from nav_stack.core.control.mppi.params import MotionModel, MPPIParams
from nav_stack.core.control.mppi.path_critics import (
    CycleFacts,
    path_align_critic,
    path_angle_critic,
    path_follow_critic,
    powered,
)
from nav_stack.core.control.mppi.scene import Rollouts, Scene
from nav_stack.core.geometry import FloatArray, angle_diffs
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION

BoolArray = np.ndarray
#: rad/s below which a sampled motion counts as straight (no turning radius to check)
STRAIGHT_WZ = 1e-6


def footprint_cost(scene: Scene, x: FloatArray, y: FloatArray, yaw: FloatArray) -> FloatArray:
    """The highest cost under the footprint's outline at each pose (the centre's for a round robot)."""
    outline = scene.footprint.outline
    if not len(outline):
        return scene.grid.cost_at(x, y).astype(np.float64)
    c, s = np.cos(yaw)[..., None], np.sin(yaw)[..., None]
    px = x[..., None] + c * outline[:, 0] - s * outline[:, 1]
    py = y[..., None] + s * outline[:, 0] + c * outline[:, 1]
    return np.asarray(scene.grid.cost_at(px, py).max(axis=-1), dtype=np.float64)


def _collision_costs(scene: Scene, x: FloatArray, y: FloatArray, yaw: FloatArray, consider_footprint: bool
                     ) -> tuple[FloatArray, FloatArray, BoolArray, BoolArray]:
    """(centre cost, cost that decides collisions, whether the footprint was costed, collides) per pose."""
    centre = scene.grid.cost_at(x, y).astype(np.float64)
    decisive, used = centre.copy(), np.zeros(centre.shape, dtype=bool)
    if consider_footprint:
        possible = scene.footprint.circumscribed_cost
        used = (centre >= 1.0) & (centre != NO_INFORMATION) & ((centre >= possible) | (possible < 1.0))
        if used.any():
            decisive[used] = footprint_cost(scene, x[used], y[used], yaw[used])
    inscribed_collides = (decisive == INSCRIBED_INFLATED_OBSTACLE) & (not consider_footprint)
    collides = (decisive >= LETHAL_OBSTACLE) | inscribed_collides
    return centre, decisive, used, collides & (centre >= 1.0)


def _before_first(hits: BoolArray) -> BoolArray:
    """Per row, the points strictly before the first hit (all of them without one)."""
    first = np.where(hits.any(axis=1), hits.argmax(axis=1), hits.shape[1])
    return np.asarray(np.arange(hits.shape[1]) < first[:, None])


def cost_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> tuple[FloatArray, bool]:
    """CostCritic: every ``trajectory_point_step``-th pose adds its centre cost (critical_cost from
    near_collision_cost up; nothing near the goal); a collision makes the whole term collision_cost.
    Scaled by cost_weight / 254 / (poses checked)."""
    cols = np.arange(0, r.x.shape[1], p.trajectory_point_step)
    x, y, yaw = r.x[:, cols], r.y[:, cols], r.yaw[:, cols]
    centre, _, _, collides = _collision_costs(scene, x, y, yaw, p.consider_footprint)
    near_goal = scene.goal_within(p.near_goal_distance)
    point = np.where(centre >= p.near_collision_cost, p.critical_cost, 0.0 if near_goal else centre)
    point[centre < 1.0] = 0.0
    hit = collides.any(axis=1)
    total = np.where(hit, p.collision_cost, (point * _before_first(collides)).sum(axis=1))
    return powered(total, p.cost_weight / 254.0 / len(cols), p.cost_power), bool(hit.all())


def obstacles_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> tuple[FloatArray, bool]:
    """ObstaclesCritic: costs back to distances d (inflation inverted); poses closer than
    collision_margin_distance add (margin − d) · critical_weight, every costed pose adds
    (inflation_radius − d) · repulsion_weight (normalised by the batch minimum and T, not near the
    goal); a collision makes the critical term collision_cost."""
    _, decisive, used, collides = _collision_costs(scene, r.x, r.y, r.yaw, p.consider_footprint)
    counted = _before_first(collides) & (decisive >= 1.0)
    hit = collides.any(axis=1)
    raw, repulsive = np.zeros(len(r.x)), np.zeros(len(r.x))
    if p.inflation_radius != 0.0 and p.cost_scaling_factor != 0.0:
        k, inscribed = p.cost_scaling_factor, scene.footprint.inscribed_radius
        with np.errstate(divide="ignore"):
            dist = (k * inscribed - np.log(decisive) + math.log(INSCRIBED_INFLATED_OBSTACLE)) / k
        dist = np.where(used, dist, dist - inscribed)
        close = counted & (dist < p.collision_margin_distance)
        raw = np.where(close, p.collision_margin_distance - dist, 0.0).sum(axis=1)
        if not scene.goal_within(p.near_goal_distance):
            repulsive = np.where(counted, p.inflation_radius - dist, 0.0).sum(axis=1)
    raw = np.where(hit, p.collision_cost, raw)
    normalised = (repulsive - repulsive.min()) / r.x.shape[1]
    total = p.critical_weight * raw + p.repulsion_weight * normalised
    return powered(total, 1.0, p.cost_power), bool(hit.all())


def constraint_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> FloatArray:
    """ConstraintCritic: Σ model_dt · (speed beyond the limits); Ackermann adds the turning radius
    missing to min_turning_r. The limits include vy_max even for DiffDrive, as in Nav2."""
    mp = ctx.params
    max_vel = math.hypot(mp.vx_max, mp.vy_max)
    min_vel = math.copysign(math.hypot(mp.vx_min, mp.vy_max), 1.0 if mp.vx_min > 0.0 else -1.0)
    speed = r.vx
    if mp.model is MotionModel.Omni:
        speed = np.copysign(1.0, r.vx) * np.hypot(r.vx, r.vy)
    beyond = np.maximum(speed - max_vel, 0.0) + np.maximum(min_vel - speed, 0.0)
    if mp.model is MotionModel.Ackermann:
        turning = np.abs(r.wz) > STRAIGHT_WZ
        radius = np.abs(r.vx) / np.where(turning, np.abs(r.wz), 1.0)
        beyond = beyond + np.where(turning, np.maximum(ctx.min_turning_r - radius, 0.0), 0.0)
    return powered((beyond * mp.model_dt).sum(axis=1), p.cost_weight, p.cost_power)


def goal_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> FloatArray:
    """GoalCritic: within threshold_to_consider of the goal, the mean distance of the poses to it."""
    if not scene.goal_within(p.threshold_to_consider):
        return np.zeros(len(r.x))
    dist = np.hypot(r.x - scene.goal[0], r.y - scene.goal[1])
    return powered(dist.mean(axis=1), p.cost_weight, p.cost_power)


def goal_angle_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> FloatArray:
    """GoalAngleCritic: within threshold_to_consider of the goal, the mean |yaw − goal yaw|."""
    if not scene.goal_within(p.threshold_to_consider):
        return np.zeros(len(r.x))
    error = np.abs(angle_diffs(r.yaw, scene.goal[2]))
    return powered(error.mean(axis=1), p.cost_weight, p.cost_power)


def prefer_forward_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> FloatArray:
    """PreferForwardCritic: away from the goal, Σ model_dt · (reverse speed)."""
    if scene.goal_within(p.threshold_to_consider):
        return np.zeros(len(r.x))
    backward = np.maximum(-r.vx, 0.0) * ctx.params.model_dt
    return powered(backward.sum(axis=1), p.cost_weight, p.cost_power)


def twirling_critic(p: Any, scene: Scene, r: Rollouts, ctx: CycleFacts) -> FloatArray:
    """TwirlingCritic: outside the goal checker's xy tolerance, the mean |wz|."""
    if scene.goal_within(ctx.params.goal_dist_tol):
        return np.zeros(len(r.x))
    return powered(np.abs(r.wz).mean(axis=1), p.cost_weight, p.cost_power)


#: critic name → its reference function; the obstacle critics also return the fail flag
CRITICS: dict[str, Callable[..., Any]] = {
    "ConstraintCritic": constraint_critic,
    "CostCritic": cost_critic,
    "ObstaclesCritic": obstacles_critic,
    "GoalCritic": goal_critic,
    "GoalAngleCritic": goal_angle_critic,
    "PathAlignCritic": path_align_critic,
    "PathFollowCritic": path_follow_critic,
    "PathAngleCritic": path_angle_critic,
    "PreferForwardCritic": prefer_forward_critic,
    "TwirlingCritic": twirling_critic,
}
FAIL_FLAG_CRITICS = ("CostCritic", "ObstaclesCritic")


def evaluate(critics: list[tuple[str, Any]], scene: Scene, rollouts: Rollouts, params: MPPIParams,
             min_turning_r: float) -> tuple[FloatArray, bool]:
    """Every enabled critic's cost (C, B) in list order, and whether an obstacle critic found every
    trajectory colliding (the last such critic decides, as Nav2's assignment of fail_flag does)."""
    ctx = CycleFacts(scene, rollouts, params, min_turning_r)
    costs = np.zeros((len(critics), len(rollouts.x)))
    fail = False
    for k, (name, p) in enumerate(critics):
        if not p.enabled:
            continue
        out = CRITICS[name](p, scene, rollouts, ctx)
        if name in FAIL_FLAG_CRITICS:
            costs[k], fail = out
        else:
            costs[k] = out
    return costs, fail
