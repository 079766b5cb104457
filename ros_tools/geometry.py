"""Planar orientation on geometry_msgs/Quaternion: the yaw of a message's orientation, and the reverse.

Why here: the ROS layers of sim2d, nav_stack and smacc_py, and ros_tools' own viewer, reports and
scenario drivers, all read the heading of a pose message and write one back. They may not import each
other, and ros_tools is what they share. The cores keep their own pure-float copies (import-linter's
Rule 1 keeps them away from ros_tools).

Any object with float fields ``x``, ``y``, ``z`` and ``w`` serves (a geometry_msgs/Quaternion, or the
``rotation`` of a geometry_msgs/Transform); this module imports no message package. Angles are
radians, counter-clockwise about +z.
"""

from __future__ import annotations

import math
from typing import Protocol


class QuaternionFields(Protocol):
    """What a geometry_msgs/Quaternion offers: the four components, x, y, z (vector part) and w."""

    x: float
    y: float
    z: float
    w: float


def yaw_from_quaternion(x: float, y: float, z: float, w: float) -> float:
    """Heading (rad, in [-π, π]) of the quaternion ``(x, y, z, w)``: the rotation about +z of its
    x axis projected on the ground plane. Exact for planar rotations; no normalisation or NaN check
    (nav_stack.core.geometry's version rejects those for the servers that must report them)."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def yaw_of(orientation: QuaternionFields) -> float:
    """Heading (rad) of a geometry_msgs/Quaternion (see :func:`yaw_from_quaternion`)."""
    return yaw_from_quaternion(orientation.x, orientation.y, orientation.z, orientation.w)


def set_yaw(orientation: QuaternionFields, yaw: float) -> None:
    """Make ``orientation`` (a geometry_msgs/Quaternion, changed in place) the rotation by ``yaw``
    rad about +z. In place, so that a message a publisher reuses every tick is not rebuilt."""
    orientation.x, orientation.y = 0.0, 0.0
    orientation.z, orientation.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
