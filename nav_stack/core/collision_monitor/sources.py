"""Observation sources as the monitor reads them: sensor data → points (N, 2) in the base frame.

Why here and not in the node: which returns count, where they land and when data is too old to
trust are the safety decisions; the node only copies messages into arrays and asks TF for the
transforms. A :class:`Rigid` maps sensor-frame points into the base frame (with base shift
correction, into the base frame *now*: :func:`shift_corrected`).

Nav2 Jazzy's rules:

* a scan return counts when ``range_min <= r <= range_max`` (NaN and ±inf never do); the beam of
  index i points at ``angle_min + i·angle_increment`` in the sensor's x-y plane;
* a point cloud point counts when its height **in the base frame** lies in
  ``[min_height, max_height]``; a scan has no height filter (Jazzy's nav2_params.yaml sets
  ``min_height``/``max_height`` on its scan source: they are read and have no effect);
* data older than ``source_timeout`` (sim time, stamp to now) is not valid; a timeout of 0 turns
  this check off. An invalid source, or one that never published, or one TF cannot place, makes
  the monitor stop the robot (see :mod:`.monitor`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from nav_stack.core.geometry import FloatArray


class Rigid(NamedTuple):
    """A rigid transform parent ← child: ``p_parent = rotation · p_child + translation`` (m)."""

    rotation: FloatArray  # (3, 3)
    translation: FloatArray  # (3,)

    def apply(self, points: FloatArray) -> FloatArray:
        """Child-frame points (N, 3) mapped into the parent frame → (N, 3)."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        return np.asarray(pts @ self.rotation.T + self.translation, dtype=np.float64)

    def inverse(self) -> Rigid:
        """The transform child ← parent."""
        rt = self.rotation.T
        return Rigid(rt, -rt @ self.translation)

    def __matmul__(self, other: Rigid) -> Rigid:
        """``a @ b``: b's child frame into a's parent frame (a: A←B, b: B←C gives A←C)."""
        return Rigid(self.rotation @ other.rotation, self.rotation @ other.translation + self.translation)


def shift_corrected(sensor_in_fixed_then: Rigid, base_in_fixed_now: Rigid) -> Rigid:
    """Base-frame-*now* ← sensor-frame-*at-the-stamp*, through a fixed frame (odom).

    Why: a scan taken 0.2 s ago at 0.26 m/s sees the world from 5 cm behind where the robot is
    now; read in the current base frame as if taken now, every obstacle would look 5 cm further
    away than it is. Going through the fixed frame places the old data where it is now relative
    to the robot (tf2's lookupTransform with a fixed frame, as Nav2's base_shift_correction does).
    """
    return base_in_fixed_now.inverse() @ sensor_in_fixed_then


def scan_points(ranges: npt.ArrayLike, angle_min: float, angle_increment: float, range_min: float,
                range_max: float) -> FloatArray:
    """The valid returns of a planar scan as points (N, 3) in the sensor frame (z = 0)."""
    r = np.asarray(ranges, dtype=np.float64)
    angles = angle_min + angle_increment * np.arange(len(r), dtype=np.float64)
    with np.errstate(invalid="ignore"):
        valid = (r >= range_min) & (r <= range_max)
    r, angles = r[valid], angles[valid]
    return np.column_stack([r * np.cos(angles), r * np.sin(angles), np.zeros(len(r))])


def within_height(points_in_base: FloatArray, min_height: float, max_height: float) -> FloatArray:
    """The (x, y) (N, 2) of base-frame points (N, 3) whose z lies in ``[min_height, max_height]``."""
    z = points_in_base[:, 2]
    keep = (z >= min_height) & (z <= max_height)
    return np.asarray(points_in_base[keep, :2], dtype=np.float64)


def source_valid(stamp: float, now: float, source_timeout: float) -> bool:
    """False when data stamped ``stamp`` is more than ``source_timeout`` s older than ``now`` (both
    s of the node clock); a timeout of 0 accepts any age (Nav2's sourceValid).

    The age is compared in whole nanoseconds, as Nav2 compares rclcpp durations: in float seconds,
    102.55 - 100.55 exceeds 2.0 and data exactly ``source_timeout`` old would stop the robot.
    """
    return source_timeout == 0.0 or round((now - stamp) * 1e9) <= round(source_timeout * 1e9)


def rigid_from_quaternion(x: float, y: float, z: float, qx: float, qy: float, qz: float,
                          qw: float) -> Rigid:
    """A Rigid from a translation (m) and a quaternion (x, y, z, w), normalised first."""
    q = np.array([qx, qy, qz, qw], dtype=np.float64)
    norm = float(np.linalg.norm(q))
    if not np.isfinite(norm) or norm < 1e-12:
        raise ValueError(f"quaternion {q.tolist()} cannot be normalised")
    a, b, c, w = q / norm
    rotation = np.array([
        [1.0 - 2.0 * (b * b + c * c), 2.0 * (a * b - c * w), 2.0 * (a * c + b * w)],
        [2.0 * (a * b + c * w), 1.0 - 2.0 * (a * a + c * c), 2.0 * (b * c - a * w)],
        [2.0 * (a * c - b * w), 2.0 * (b * c + a * w), 1.0 - 2.0 * (a * a + b * b)],
    ])
    return Rigid(rotation, np.array([x, y, z], dtype=np.float64))
