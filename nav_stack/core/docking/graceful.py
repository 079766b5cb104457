"""nav2_graceful_controller's smooth control law (Park & Kuipers, ICRA 2011), the docking controller.

The robot steers onto a family of spirals that end at the target pose with the target's heading. In
egocentric polar coordinates of the target (as seen from the robot):

* r: distance to the target (m);
* phi: the target's heading relative to the line of sight from the robot to it (rad);
* delta: the robot's heading relative to the same line of sight (rad);

the law chooses the curvature (1/m)

    kappa = -1/r · [ k_delta·(delta - atan(-k_phi·phi)) + (1 + k_phi / (1 + (k_phi·phi)²))·sin(delta) ]

and the speed v = v_max / (1 + beta·|kappa|^lambda) (slower on tight curves), capped by
v_max·r/slowdown_radius near the target and clamped to [v_linear_min, v_linear_max]. The turn rate is
w = kappa·v clamped to ±v_angular_max, and v is then lowered to w/kappa so the curvature holds. Backward
motion mirrors the line of sight and negates v. Because v never drops below ``v_linear_min``, the law
never stops by itself: the docking server aims 0.25 m past the dock and stops on "docked".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nav_stack.core.control.base import Twist2D
from nav_stack.core.geometry import Pose2D, normalize_angle

MIN_RANGE = 1e-6  # m: r below this is treated as this (the law's 1/r has no limit at the target)


@dataclass(frozen=True)
class SmoothControlLawParams:
    """The law's knobs (Nav2's ``controller.*`` names; ``lambda_`` is Nav2's ``lambda``), code defaults.

    Units: k_phi, k_delta, beta, lambda dimensionless; m/s, rad/s, m.
    """

    k_phi: float = 3.0
    k_delta: float = 2.0
    beta: float = 0.4
    lambda_: float = 2.0
    v_linear_min: float = 0.1
    v_linear_max: float = 0.25
    v_angular_max: float = 0.75
    slowdown_radius: float = 0.25

    def __post_init__(self) -> None:
        values = (self.k_phi, self.k_delta, self.beta, self.lambda_, self.v_linear_min, self.v_linear_max,
                  self.v_angular_max, self.slowdown_radius)
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"the control law's parameters must be finite: {self}")
        if self.k_phi <= 0.0:
            raise ValueError(f"k_phi must be > 0, got {self.k_phi}")
        if not 0.0 <= self.v_linear_min <= self.v_linear_max:
            raise ValueError(f"need 0 <= v_linear_min <= v_linear_max, got {self.v_linear_min} and "
                             f"{self.v_linear_max}")
        if self.v_angular_max <= 0.0 or self.slowdown_radius <= 0.0:
            raise ValueError(f"v_angular_max and slowdown_radius must be > 0, got {self.v_angular_max} and "
                             f"{self.slowdown_radius}")


def ego_polar(target: Pose2D, current: Pose2D, backward: bool = False) -> tuple[float, float, float]:
    """(r m, phi rad, delta rad) of ``target`` seen from ``current`` (both in one frame)."""
    dx, dy = target.x - current.x, target.y - current.y
    line_of_sight = math.atan2(-dy, dx) + (math.pi if backward else 0.0)
    return (math.hypot(dx, dy), normalize_angle(target.yaw + line_of_sight),
            normalize_angle(current.yaw + line_of_sight))


def curvature(r: float, phi: float, delta: float, params: SmoothControlLawParams) -> float:
    """The law's path curvature (1/m) for the polar coordinates (module docstring)."""
    k_phi = params.k_phi
    proportional = params.k_delta * (delta - math.atan(-k_phi * phi))
    feedback = (1.0 + k_phi / (1.0 + (k_phi * phi) ** 2)) * math.sin(delta)
    return -(proportional + feedback) / max(r, MIN_RANGE)


def velocity_command(target: Pose2D, current: Pose2D, params: SmoothControlLawParams,
                     backward: bool = False) -> Twist2D:
    """The command (m/s, rad/s) that steers ``current`` towards ``target``."""
    r, phi, delta = ego_polar(target, current, backward)
    kappa = curvature(r, phi, delta, params)
    if backward:
        kappa = -kappa
    v = params.v_linear_max / (1.0 + params.beta * abs(kappa) ** params.lambda_)
    v = min(params.v_linear_max * r / params.slowdown_radius, v)
    v = min(max(v, params.v_linear_min), params.v_linear_max)
    if backward:
        v = -v
    w = min(max(kappa * v, -params.v_angular_max), params.v_angular_max)
    if kappa != 0.0:
        v = w / kappa
    return Twist2D(v, w)


def next_pose(dt: float, target: Pose2D, current: Pose2D, params: SmoothControlLawParams,
              backward: bool = False) -> Pose2D:
    """Where ``current`` is after ``dt`` s of the law's command (Nav2's Euler step: move, then turn)."""
    v, w = velocity_command(target, current, params, backward)
    return Pose2D(current.x + v * dt * math.cos(current.yaw), current.y + v * dt * math.sin(current.yaw),
                  normalize_angle(current.yaw + w * dt))
