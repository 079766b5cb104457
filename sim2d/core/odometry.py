"""Wheel odometry with drift: the pose the robot believes, integrated from slipping wheels.

Model: each physics step moves the robot by a true chord of length d (m) and rotation θ (rad);
the odometry sees the chord lengthened by N(0, σ_d²) and θ' = θ + N(0, σ_θ²), with variances that
grow linearly with the motion (a random walk, so the statistics do not depend on the physics step):

    σ_d² = trans_from_trans² · |d| + trans_from_rot² · |θ|
    σ_θ² = rot_from_rot² · |θ| + rot_from_trans² · |d|

So after a straight metre the along-track error has σ = trans_from_trans (m) and the heading error
σ = rot_from_trans (rad). Defaults (2 cm and ≈3° per metre) make a localizer necessary; ``ideal``
gives perfect odometry, like Gazebo's diff drive (odometry_source WORLD).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sim2d.core.geometry import normalize_angle
from sim2d.core.robot import Pose2D


@dataclass(frozen=True)
class OdometryParams:
    """Drift coefficients (units m/√m, m/√rad, rad/√rad, rad/√m), publish rate (Hz) and ideal switch."""

    ideal: bool = False
    trans_from_trans: float = 0.02
    trans_from_rot: float = 0.005
    rot_from_rot: float = 0.02
    rot_from_trans: float = 0.05
    rate: float = 30.0

    def __post_init__(self) -> None:
        for name in ("trans_from_trans", "trans_from_rot", "rot_from_rot", "rot_from_trans"):
            if getattr(self, name) < 0.0:
                raise ValueError(f"odometry.{name}: must be >= 0, got {getattr(self, name)}")
        if self.rate <= 0.0:
            raise ValueError(f"odometry.rate: must be > 0, got {self.rate}")


class Odometry:
    """Integrates noisy motion increments into a pose in the odom frame (starts at the origin)."""

    _BLOCK = 4096  # normal draws fetched at once: one generator call per block, not per step

    def __init__(self, params: OdometryParams, rng: np.random.Generator) -> None:
        self.params = params
        self.rng = rng
        self._normals = np.zeros(0)
        self._next = 0
        self.reset()

    def reset(self) -> None:
        """Back to the odom origin with zero accumulated variance."""
        self.pose = Pose2D()
        self.variance_trans = 0.0  # accumulated along-track variance (m²), reported as covariance
        self.variance_rot = 0.0    # accumulated heading variance (rad²)

    def _draw(self) -> float:
        if self._next >= len(self._normals):
            self._normals = self.rng.standard_normal(self._BLOCK)
            self._next = 0
        value = float(self._normals[self._next])
        self._next += 1
        return value

    def update(self, dx: float, dy: float, dyaw: float) -> None:
        """Add one true motion increment (dx, dy) (m), dyaw (rad), expressed in the previous body frame.

        Ideal odometry composes the increment exactly; otherwise noise is added along the chord and
        to the rotation with the variances of the module docstring.
        """
        if dx == 0.0 and dy == 0.0 and dyaw == 0.0:
            return
        p = self.params
        if not p.ideal:
            distance, rotation = math.hypot(dx, dy), abs(dyaw)
            var_d = p.trans_from_trans ** 2 * distance + p.trans_from_rot ** 2 * rotation
            var_r = p.rot_from_rot ** 2 * rotation + p.rot_from_trans ** 2 * distance
            slip = math.sqrt(var_d) * self._draw()
            dx += slip * math.cos(0.5 * dyaw)
            dy += slip * math.sin(0.5 * dyaw)
            dyaw += math.sqrt(var_r) * self._draw()
            self.variance_trans += var_d
            self.variance_rot += var_r
        c, s = math.cos(self.pose.yaw), math.sin(self.pose.yaw)
        self.pose = Pose2D(self.pose.x + c * dx - s * dy, self.pose.y + s * dx + c * dy,
                           normalize_angle(self.pose.yaw + dyaw))
