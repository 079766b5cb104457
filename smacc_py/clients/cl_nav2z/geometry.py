"""Planar pose helpers (pure Python): angle wrapping and path shape tests.

Poses are ``(x, y, yaw)`` tuples in m and rad. The yaw of a message's quaternion, and the reverse, are
ros_tools.geometry's (every package's ROS layer shares them).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

from ros_tools.geometry import yaw_from_quaternion

Pose2D = tuple[float, float, float]


def normalize_angle(angle: float) -> float:
    """Wrap an angle (rad) into (-π, π]."""
    wrapped = math.atan2(math.sin(angle), math.cos(angle))
    return math.pi if wrapped == -math.pi else wrapped


#: ros_tools.geometry.yaw_from_quaternion under the name tests/helpers/smacc_fake_nav.py imports it by.
quaternion_to_yaw = yaw_from_quaternion


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
