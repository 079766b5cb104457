"""Planar pose helpers (pure Python): yaw ↔ quaternion, angle wrapping, path shape tests.

Poses are ``(x, y, yaw)`` tuples in m and rad.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

Pose2D = tuple[float, float, float]


def normalize_angle(angle: float) -> float:
    """Wrap an angle (rad) into (-π, π]."""
    wrapped = math.atan2(math.sin(angle), math.cos(angle))
    return math.pi if wrapped == -math.pi else wrapped


def yaw_to_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """(x, y, z, w) of a rotation by ``yaw`` rad about z."""
    return 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)


def quaternion_to_yaw(x: float, y: float, z: float, w: float) -> float:
    """Yaw (rad) of a quaternion."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def path_length(path: Sequence[Pose2D]) -> float:
    """Sum of segment lengths (m)."""
    return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in itertools.pairwise(path))


def is_straight(path: Sequence[Pose2D], lateral_tolerance: float = 0.05) -> bool:
    """True when every point lies within ``lateral_tolerance`` m of the line from first to last point."""
    if len(path) < 2:
        return True
    (x0, y0, _), (x1, y1, _) = path[0], path[-1]
    length = math.hypot(x1 - x0, y1 - y0)
    if length < 1e-9:
        return all(math.hypot(p[0] - x0, p[1] - y0) <= lateral_tolerance for p in path)
    ux, uy = (x1 - x0) / length, (y1 - y0) / length
    return all(abs((p[0] - x0) * uy - (p[1] - y0) * ux) <= lateral_tolerance for p in path)
