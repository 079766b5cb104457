"""Planar pose and path geometry shared by planners, controllers and behaviors.

Poses are ``(x, y, yaw)`` in metres and radians; a path is a float array of shape ``(N, 3)`` (or
``(N, 2)`` where only positions matter). Quaternion helpers take and return plain floats, so the
ROS layer converts geometry_msgs/Quaternion fields without the core knowing message types.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


class Pose2D(NamedTuple):
    """A planar pose: position (m) and heading (rad, counter-clockwise from +x)."""

    x: float
    y: float
    yaw: float


#: The pose of a frame's own origin: the identity of pose composition.
IDENTITY = Pose2D(0.0, 0.0, 0.0)


def normalize_angle(angle: float) -> float:
    """Wrap an angle (rad) to [-π, π)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def normalize_angles(angles: FloatArray) -> FloatArray:
    """Element-wise :func:`normalize_angle` for arrays."""
    return np.asarray((angles + np.pi) % (2.0 * np.pi) - np.pi, dtype=np.float64)


def angle_diff(to: float, frm: float) -> float:
    """Signed shortest rotation (rad) that turns heading ``frm`` into heading ``to``."""
    return normalize_angle(to - frm)


def angle_diffs(to: FloatArray | float, frm: FloatArray | float) -> FloatArray:
    """Element-wise :func:`angle_diff` for arrays (either side may be a scalar), in [-π, π) rad."""
    return normalize_angles(np.asarray(to, dtype=np.float64) - frm)


def yaw_from_quaternion(x: float, y: float, z: float, w: float) -> float:
    """Heading (rad) of a quaternion, the rotation about +z of its planar projection.

    Raises ValueError when the quaternion holds NaN/inf or has (near) zero norm: such an
    orientation cannot be normalised, and silently reading it as yaw 0 would hide a client bug.
    """
    values = (x, y, z, w)
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f"orientation quaternion {values} holds NaN or inf")
    norm = math.sqrt(sum(v * v for v in values))
    if norm < 1e-9:
        raise ValueError(f"orientation quaternion {values} has zero norm and cannot be normalised")
    x, y, z, w = (v / norm for v in values)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def quaternion_from_yaw(yaw: float) -> tuple[float, float, float, float]:
    """Quaternion ``(x, y, z, w)`` of a rotation by ``yaw`` (rad) about +z."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def segment_lengths(points: FloatArray) -> FloatArray:
    """Lengths (m) of the N-1 segments joining consecutive points of an (N, ≥2) array."""
    if len(points) < 2:
        return np.zeros(0)
    d = np.diff(points[:, :2], axis=0)
    return np.asarray(np.hypot(d[:, 0], d[:, 1]), dtype=np.float64)


def cumulative_lengths(points: FloatArray) -> FloatArray:
    """Arc length (m) from the first point to each point; first element 0."""
    return np.concatenate(([0.0], np.cumsum(segment_lengths(points))))


def path_length(points: FloatArray) -> float:
    """Total polyline length (m)."""
    return float(segment_lengths(points).sum())


def nearest_index(points: FloatArray, x: float, y: float, start: int = 0, stop: int | None = None) -> int:
    """Index of the point closest to ``(x, y)`` within ``points[start:stop]``."""
    window = points[start:stop, :2]
    if len(window) == 0:
        raise ValueError(f"empty search window [{start}:{stop}] on a path of {len(points)} poses")
    d2 = (window[:, 0] - x) ** 2 + (window[:, 1] - y) ** 2
    return start + int(np.argmin(d2))


def headings_along(points: FloatArray) -> FloatArray:
    """Yaw (rad) of each point facing the next one; the last point repeats the previous heading."""
    n = len(points)
    if n < 2:
        return np.zeros(n)
    d = np.diff(points[:, :2], axis=0)
    yaw = np.arctan2(d[:, 1], d[:, 0])
    return np.concatenate((yaw, yaw[-1:]))


def to_frame(poses: FloatArray, frame: Pose2D) -> FloatArray:
    """Express ``poses`` (N, 3) given in the parent frame in the child ``frame`` (a pose in the parent)."""
    c, s = math.cos(frame.yaw), math.sin(frame.yaw)
    dx = poses[:, 0] - frame.x
    dy = poses[:, 1] - frame.y
    out = np.empty((len(poses), 3))
    out[:, 0] = c * dx + s * dy
    out[:, 1] = -s * dx + c * dy
    out[:, 2] = normalize_angles(poses[:, 2] - frame.yaw)
    return out


def from_frame(poses: FloatArray, frame: Pose2D) -> FloatArray:
    """Inverse of :func:`to_frame`: poses in ``frame`` expressed in its parent frame."""
    c, s = math.cos(frame.yaw), math.sin(frame.yaw)
    out = np.empty((len(poses), 3))
    out[:, 0] = frame.x + c * poses[:, 0] - s * poses[:, 1]
    out[:, 1] = frame.y + s * poses[:, 0] + c * poses[:, 1]
    out[:, 2] = normalize_angles(poses[:, 2] + frame.yaw)
    return out


def compose(a: Pose2D, b: Pose2D) -> Pose2D:
    """Pose ``b`` (given in frame ``a``) expressed in ``a``'s parent frame."""
    c, s = math.cos(a.yaw), math.sin(a.yaw)
    return Pose2D(a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, normalize_angle(a.yaw + b.yaw))


def yaw_or_nan(x: float, y: float, z: float, w: float) -> float:
    """:func:`yaw_from_quaternion`, but NaN for an orientation that cannot be normalised.

    Lets a node hand any received orientation to a core, which refuses NaN with its own error code.
    """
    try:
        return yaw_from_quaternion(x, y, z, w)
    except ValueError:
        return math.nan
