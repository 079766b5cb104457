"""Shared pieces of the recovery behaviors: results, error codes, parameters, collision look-ahead.

A behavior is a small state machine driven by the behavior_server node at ``cycle_frequency``:
``start(goal, pose, now)`` validates the goal (returning a failed result or None when accepted),
then ``step(pose, now, grid)`` returns a velocity command while running and a
:class:`BehaviorResult` once finished. The node publishes commands, publishes zero velocity
when a result arrives, and copies the result into the action result.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np

from nav_stack.core.control.base import CircleFootprint, CostGrid, Footprint, Twist2D, constant_twist_poses
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import LETHAL_OBSTACLE


class SpinErrorCode(enum.IntEnum):
    NONE = 0
    UNKNOWN = 700
    TIMEOUT = 701
    TF_ERROR = 702
    COLLISION_AHEAD = 703


class BackUpErrorCode(enum.IntEnum):
    NONE = 0
    UNKNOWN = 710
    TIMEOUT = 711
    TF_ERROR = 712
    INVALID_INPUT = 713
    COLLISION_AHEAD = 714


class DriveOnHeadingErrorCode(enum.IntEnum):
    NONE = 0
    UNKNOWN = 720
    TIMEOUT = 721
    TF_ERROR = 722
    COLLISION_AHEAD = 723
    INVALID_INPUT = 724


@dataclass(frozen=True)
class BehaviorResult:
    """Outcome of a behavior: Jazzy error code (0 = success), message, elapsed time (s)."""

    error_code: int
    error_msg: str
    total_elapsed_time: float

    @property
    def succeeded(self) -> bool:
        return self.error_code == 0


@dataclass(frozen=True)
class BehaviorParams:
    """behavior_server knobs (Jazzy nav2_params.yaml values)."""

    cycle_frequency: float = 10.0  # Hz
    simulate_ahead_time: float = 2.0  # s of commanded motion checked for collisions
    max_rotational_vel: float = 1.0  # rad/s
    min_rotational_vel: float = 0.4  # rad/s
    rotational_acc_lim: float = 3.2  # rad/s²

    def __post_init__(self) -> None:
        if not (self.cycle_frequency > 0 and self.simulate_ahead_time >= 0):
            raise ValueError(
                f"BehaviorParams need cycle_frequency > 0 and simulate_ahead_time >= 0, got {self}"
            )
        if not 0 < self.min_rotational_vel <= self.max_rotational_vel or self.rotational_acc_lim <= 0:
            raise ValueError(f"BehaviorParams rotational limits invalid: {self}")


class CollisionLookahead:
    """Simulates a constant command ahead, one cycle per sample, and checks the footprint for
    lethal cost (≥ 254, unknown included), as Nav2's behaviors do on the local costmap."""

    def __init__(self, params: BehaviorParams, footprint: Footprint | None = None) -> None:
        self.params = params
        self.footprint: Footprint = footprint or CircleFootprint()

    def collision_ahead(
        self,
        pose: Pose2D,
        cmd: Twist2D,
        grid: CostGrid,
        max_distance: float = math.inf,
        max_rotation: float = math.inf,
    ) -> bool:
        """True if the footprint hits lethal cost before ``simulate_ahead_time``, the distance
        ``max_distance`` (m) or the rotation ``max_rotation`` (rad) is covered."""
        p = self.params
        t = np.arange(int(p.cycle_frequency * p.simulate_ahead_time) + 1) / p.cycle_frequency
        x, y, yaw = constant_twist_poses(pose, cmd, t)
        keep = (np.hypot(x - pose.x, y - pose.y) < max_distance) & (np.abs(cmd.wz * t) < max_rotation)
        if not keep.any():
            return False
        cost = self.footprint.cost(grid, x[keep], y[keep], yaw[keep])
        return bool((cost >= LETHAL_OBSTACLE).any())
