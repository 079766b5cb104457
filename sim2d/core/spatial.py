"""3-D rotations for the dock's tag: roll-pitch-yaw matrices and unit quaternions (x, y, z, w).

Why here: a detected tag is a 3-D pose (an AprilTag's frame stands upright on the dock), while the rest
of sim2d is planar. sim2d keeps its own few lines rather than importing nav_stack's (the packages never
import each other), so a convention slip on one side shows up as a disagreement on the ROS topic.

Conventions follow tf2: ``rotation_rpy(roll, pitch, yaw)`` is tf2::Quaternion::setRPY, i.e.
R = Rz(yaw) · Ry(pitch) · Rx(roll) (fixed axes x, then y, then z); quaternions are Hamilton, (x, y, z, w).
"""

from __future__ import annotations

import math

import numpy as np

from sim2d.core.geometry import FloatArray

Quaternion = tuple[float, float, float, float]
"""A unit quaternion (x, y, z, w), the field order of geometry_msgs/Quaternion."""


def rotation_x(angle: float) -> FloatArray:
    """Rotation (3, 3) by ``angle`` (rad) about x."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rotation_y(angle: float) -> FloatArray:
    """Rotation (3, 3) by ``angle`` (rad) about y."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rotation_z(angle: float) -> FloatArray:
    """Rotation (3, 3) by ``angle`` (rad) about z."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rotation_rpy(roll: float, pitch: float, yaw: float) -> FloatArray:
    """Rotation (3, 3) from roll, pitch, yaw (rad) as tf2's setRPY builds it: Rz · Ry · Rx."""
    result: FloatArray = rotation_z(yaw) @ rotation_y(pitch) @ rotation_x(roll)
    return result


def yaw_of(rotation: FloatArray) -> float:
    """Heading (rad) of a rotation's x axis projected on the horizontal plane (tf2::getYaw)."""
    return math.atan2(float(rotation[1, 0]), float(rotation[0, 0]))


def to_quaternion(rotation: FloatArray) -> Quaternion:
    """The unit quaternion (x, y, z, w) of a rotation matrix, with w >= 0.

    Shepperd's method: start from the largest of w², x², y², z² so the division is well conditioned.
    """
    (a, b, c), (d, e, f), (g, h, i) = (tuple(float(v) for v in row) for row in rotation)
    trace = a + e + i
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((h - f) / s, (c - g) / s, (d - b) / s, 0.25 * s)
    elif a > e and a > i:
        s = 2.0 * math.sqrt(1.0 + a - e - i)
        q = (0.25 * s, (b + d) / s, (c + g) / s, (h - f) / s)
    elif e > i:
        s = 2.0 * math.sqrt(1.0 + e - a - i)
        q = ((b + d) / s, 0.25 * s, (f + h) / s, (c - g) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + i - a - e)
        q = ((c + g) / s, (f + h) / s, 0.25 * s, (d - b) / s)
    norm = math.sqrt(sum(v * v for v in q)) * (1.0 if q[3] >= 0.0 else -1.0)
    return q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm


def from_quaternion(q: Quaternion) -> FloatArray:
    """The rotation matrix (3, 3) of a quaternion (x, y, z, w); it need not be normalised."""
    x, y, z, w = q
    n = x * x + y * y + z * z + w * w
    s = 2.0 / n if n > 0.0 else 0.0
    return np.array([
        [1.0 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w)],
        [s * (x * y + z * w), 1.0 - s * (x * x + z * z), s * (y * z - x * w)],
        [s * (x * z - y * w), s * (y * z + x * w), 1.0 - s * (x * x + y * y)],
    ])
