"""Regulated Pure Pursuit's parameters and its pure math: the carrot, the curvature, the speed
regulations (nav2_regulated_pure_pursuit_controller's defaults and formulas; rpp.py runs them).

Units: m, s, m/s, rad/s; costs are costmap values 0..255.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nav_stack.core.geometry import FloatArray, path_length
from nav_stack.core.grid import FREE_SPACE, MAX_NON_OBSTACLE, NO_INFORMATION


@dataclass(frozen=True)
class RPPParams:
    """RPP knobs with Nav2's code defaults; ``inscribed_radius`` and ``goal_dist_tol`` come from the
    costmap and the goal checker in Nav2, ``controller_frequency`` from the controller server."""

    desired_linear_vel: float = 0.5
    lookahead_dist: float = 0.6
    min_lookahead_dist: float = 0.3
    max_lookahead_dist: float = 0.9
    lookahead_time: float = 1.5
    use_velocity_scaled_lookahead_dist: bool = False
    rotate_to_heading_angular_vel: float = 1.8
    use_rotate_to_heading: bool = True
    rotate_to_heading_min_angle: float = 0.785
    max_angular_accel: float = 3.2
    min_approach_linear_velocity: float = 0.05
    approach_velocity_scaling_dist: float = 0.6
    use_regulated_linear_velocity_scaling: bool = True
    regulated_linear_scaling_min_radius: float = 0.9
    regulated_linear_scaling_min_speed: float = 0.25
    use_cost_regulated_linear_velocity_scaling: bool = True
    cost_scaling_dist: float = 0.6
    cost_scaling_gain: float = 1.0
    inflation_cost_scaling_factor: float = 3.0
    use_collision_detection: bool = True
    max_allowed_time_to_collision_up_to_carrot: float = 1.0
    inscribed_radius: float = 0.22
    goal_dist_tol: float = 0.25
    controller_frequency: float = 20.0
    stateful: bool = True

    def __post_init__(self) -> None:
        if not 0.0 < self.min_lookahead_dist <= self.max_lookahead_dist:
            raise ValueError(
                f"RPPParams lookahead bounds invalid: min {self.min_lookahead_dist}, "
                f"max {self.max_lookahead_dist}"
            )
        for name in (
            "desired_linear_vel",
            "lookahead_dist",
            "controller_frequency",
            "inflation_cost_scaling_factor",
            "regulated_linear_scaling_min_radius",
            "cost_scaling_dist",
            "approach_velocity_scaling_dist",
        ):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"RPPParams.{name} must be > 0, got {getattr(self, name)}")


def find_carrot(path: FloatArray, lookahead: float) -> FloatArray:
    """Point (x, y) at distance ``lookahead`` from the origin on a robot-frame path (its end if closer).

    The first pose at or beyond the lookahead and its predecessor bound a segment that crosses
    the lookahead circle; the crossing is returned (Nav2's use_interpolation).
    """
    dist = np.hypot(path[:, 0], path[:, 1])
    beyond = np.nonzero(dist >= lookahead)[0]
    if len(beyond) == 0:
        return np.asarray(path[-1, :2], dtype=np.float64)
    i = int(beyond[0])
    if i == 0:
        return np.asarray(path[0, :2], dtype=np.float64)
    a, b = path[i - 1, :2], path[i, :2]
    d = b - a
    qa, qb, qc = float(d @ d), 2.0 * float(a @ d), float(a @ a) - lookahead**2
    t = (-qb + math.sqrt(max(qb * qb - 4.0 * qa * qc, 0.0))) / (2.0 * qa) if qa > 0.0 else 1.0
    return np.asarray(a + min(max(t, 0.0), 1.0) * d, dtype=np.float64)


def curvature_to(carrot: FloatArray) -> float:
    """Pure pursuit curvature 2y/L² (1/m) of the arc from the robot through the carrot."""
    l2 = float(carrot @ carrot)
    return 2.0 * float(carrot[1]) / l2 if l2 > 1e-9 else 0.0


def obstacle_distance_from_cost(cost: int, inscribed_radius: float, scaling_factor: float) -> float:
    """Invert Nav2 inflation, cost = 252·exp(-k·(d − r)): d = −ln(cost/252)/k + r (m)."""
    return -math.log(cost / MAX_NON_OBSTACLE) / scaling_factor + inscribed_radius


def regulated_speed(p: RPPParams, curvature: float, pose_cost: int) -> float:
    """Desired speed after the curvature and cost regulations (before approach scaling)."""
    curvature_vel = cost_vel = p.desired_linear_vel
    radius = abs(1.0 / curvature) if curvature != 0.0 else math.inf
    if p.use_regulated_linear_velocity_scaling and radius < p.regulated_linear_scaling_min_radius:
        curvature_vel *= (
            1.0 - abs(radius - p.regulated_linear_scaling_min_radius) / p.regulated_linear_scaling_min_radius
        )
    if p.use_cost_regulated_linear_velocity_scaling and pose_cost not in (NO_INFORMATION, FREE_SPACE):
        d = obstacle_distance_from_cost(pose_cost, p.inscribed_radius, p.inflation_cost_scaling_factor)
        if d < p.cost_scaling_dist:
            cost_vel *= p.cost_scaling_gain * d / p.cost_scaling_dist
    if not (p.use_regulated_linear_velocity_scaling or p.use_cost_regulated_linear_velocity_scaling):
        return p.desired_linear_vel
    return max(min(curvature_vel, cost_vel), p.regulated_linear_scaling_min_speed)


def approach_scaled_speed(p: RPPParams, speed: float, path: FloatArray) -> float:
    """Slow down over the last ``approach_velocity_scaling_dist`` of the (robot-frame) path."""
    if path_length(path) + math.hypot(*path[0, :2]) >= p.approach_velocity_scaling_dist:
        return speed
    scaling = math.hypot(*path[-1, :2]) / p.approach_velocity_scaling_dist
    approach = (
        p.min_approach_linear_velocity
        if speed * scaling < p.min_approach_linear_velocity
        else speed * scaling
    )
    return min(speed, approach)
