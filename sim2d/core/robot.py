"""TurtleBot3 robot models and the differential-drive kinematics that move them.

Figures (reference/nav2.md §6): wheel radius/separation and speed limits from the ROBOTIS specs,
acceleration limits from the gz DiffDrive plugin (linear 1.0 m/s²) and Nav2's minimal TB3 sim
(angular 2.0 rad/s²), the collision footprint from the URDF collision box, the base_scan mount
from the URDF. base_link sits 0.010 m above base_footprint; x and y coincide.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim2d.core.geometry import normalize_angle


@dataclass(frozen=True)
class RobotModel:
    """A differential-drive robot.

    Attributes:
        name: "waffle" or "burger".
        wheel_radius, wheel_separation: m.
        max_linear_velocity (m/s), max_angular_velocity (rad/s): commands beyond are clamped.
        max_linear_acceleration (m/s²), max_angular_acceleration (rad/s²): both speeding up and braking.
        footprint_length, footprint_width: collision box (m), centred at footprint_offset_x (m) in base_link.
        scan_offset: base_link → base_scan translation (x, y, z) (m).
        base_link_z: base_footprint → base_link height (m).
    """

    name: str
    wheel_radius: float
    wheel_separation: float
    max_linear_velocity: float
    max_angular_velocity: float
    max_linear_acceleration: float
    max_angular_acceleration: float
    footprint_length: float
    footprint_width: float
    footprint_offset_x: float
    scan_offset: tuple[float, float, float]
    base_link_z: float = 0.010

    def footprint(self) -> list[tuple[float, float]]:
        """Collision box corners (m) in base_footprint, counter-clockwise."""
        hx, hy, cx = self.footprint_length / 2.0, self.footprint_width / 2.0, self.footprint_offset_x
        return [(cx - hx, -hy), (cx + hx, -hy), (cx + hx, hy), (cx - hx, hy)]


WAFFLE = RobotModel("waffle", 0.033, 0.287, 0.26, 1.82, 1.0, 2.0, 0.266, 0.266, -0.064, (-0.064, 0.0, 0.122))
BURGER = RobotModel("burger", 0.033, 0.160, 0.22, 2.84, 1.0, 2.0, 0.140, 0.140, -0.032, (-0.032, 0.0, 0.172))
ROBOTS = {model.name: model for model in (WAFFLE, BURGER)}


def robot_model(name: str) -> RobotModel:
    """The model called ``name``; a ValueError lists the known ones."""
    if name not in ROBOTS:
        raise ValueError(f"robot: unknown model {name!r} (known: {', '.join(sorted(ROBOTS))})")
    return ROBOTS[name]


@dataclass(frozen=True)
class Pose2D:
    """A planar pose: x, y (m) and yaw (rad) in a named frame chosen by the owner."""

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0


def _approach(current: float, target: float, max_delta: float) -> float:
    """Move ``current`` towards ``target`` by at most ``max_delta``."""
    return current + max(-max_delta, min(max_delta, target - current))


def limit_velocity(model: RobotModel, v: float, w: float, target_v: float, target_w: float,
                   dt: float) -> tuple[float, float]:
    """New body velocity (m/s, rad/s) after ``dt`` (s): target clamped to speed limits, then accel limits."""
    target_v = max(-model.max_linear_velocity, min(model.max_linear_velocity, target_v))
    target_w = max(-model.max_angular_velocity, min(model.max_angular_velocity, target_w))
    return (_approach(v, target_v, model.max_linear_acceleration * dt),
            _approach(w, target_w, model.max_angular_acceleration * dt))


def integrate(pose: Pose2D, v: float, w: float, dt: float) -> Pose2D:
    """Exact unicycle motion with constant (v, w) for ``dt`` (s): a straight line or a circular arc."""
    if abs(w) < 1e-9:
        return Pose2D(pose.x + v * dt * math.cos(pose.yaw), pose.y + v * dt * math.sin(pose.yaw), pose.yaw)
    yaw_end = pose.yaw + w * dt
    radius = v / w
    return Pose2D(pose.x + radius * (math.sin(yaw_end) - math.sin(pose.yaw)),
                  pose.y - radius * (math.cos(yaw_end) - math.cos(pose.yaw)),
                  normalize_angle(yaw_end))
