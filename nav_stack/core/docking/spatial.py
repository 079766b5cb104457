"""3-D poses (position + unit quaternion) for dock detections, which arrive as full 6-DOF poses.

Why here and not in nav_stack.core.geometry: only docking needs roll and pitch. A detector reports a
tag's pose with its own axis convention (AprilTag: z out of the tag's face), and the dock plugin
rotates that into the robot's convention before it keeps the heading alone. Quaternions are
``(x, y, z, w)`` like geometry_msgs/Quaternion; angles in rad, positions in m.
"""

from __future__ import annotations

import math
from typing import NamedTuple

Quaternion = tuple[float, float, float, float]
IDENTITY: Quaternion = (0.0, 0.0, 0.0, 1.0)


class Pose3D(NamedTuple):
    """A pose in 3-D: position (m) and orientation (unit quaternion x, y, z, w)."""

    x: float
    y: float
    z: float
    qx: float = 0.0
    qy: float = 0.0
    qz: float = 0.0
    qw: float = 1.0

    @property
    def orientation(self) -> Quaternion:
        return (self.qx, self.qy, self.qz, self.qw)

    def with_orientation(self, q: Quaternion) -> Pose3D:
        return Pose3D(self.x, self.y, self.z, *q)


def multiply(a: Quaternion, b: Quaternion) -> Quaternion:
    """Hamilton product ``a * b``: rotate by ``b`` in ``a``'s frame (b first, then a)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def conjugate(q: Quaternion) -> Quaternion:
    """The inverse rotation of a unit quaternion."""
    return (-q[0], -q[1], -q[2], q[3])


def about_axis(axis: str, angle: float) -> Quaternion:
    """Rotation by ``angle`` (rad) about the x, y or z axis."""
    s, c = math.sin(angle / 2.0), math.cos(angle / 2.0)
    return {"x": (s, 0.0, 0.0, c), "y": (0.0, s, 0.0, c), "z": (0.0, 0.0, s, c)}[axis]


def normalized(q: Quaternion) -> Quaternion:
    """``q`` scaled to unit norm; ValueError for NaN/inf or a (near) zero quaternion."""
    norm = math.sqrt(sum(v * v for v in q))
    if not math.isfinite(norm) or norm < 1e-9:
        raise ValueError(f"quaternion {q} cannot be normalised")
    return (q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm)


def rotate(q: Quaternion, v: tuple[float, float, float]) -> tuple[float, float, float]:
    """Vector ``v`` rotated by ``q``."""
    x, y, z, _ = multiply(multiply(q, (v[0], v[1], v[2], 0.0)), conjugate(q))
    return (x, y, z)


def slerp(a: Quaternion, b: Quaternion, t: float) -> Quaternion:
    """Spherical interpolation from ``a`` (t = 0) to ``b`` (t = 1), the short way round."""
    dot = sum(p * q for p, q in zip(a, b, strict=True))
    if dot < 0.0:
        b, dot = (-b[0], -b[1], -b[2], -b[3]), -dot
    if dot > 0.9995:  # nearly the same rotation: a normalised lerp is accurate
        return normalized(tuple(p + t * (q - p) for p, q in zip(a, b, strict=True)))  # type: ignore[arg-type]
    theta = math.acos(min(1.0, dot))
    wa, wb = math.sin((1.0 - t) * theta) / math.sin(theta), math.sin(t * theta) / math.sin(theta)
    return normalized(tuple(wa * p + wb * q for p, q in zip(a, b, strict=True)))  # type: ignore[arg-type]


def compose(a: Pose3D, b: Pose3D) -> Pose3D:
    """Pose ``b`` (given in frame ``a``) expressed in ``a``'s parent frame."""
    dx, dy, dz = rotate(a.orientation, (b.x, b.y, b.z))
    return Pose3D(a.x + dx, a.y + dy, a.z + dz, *multiply(a.orientation, b.orientation))


def inverse(a: Pose3D) -> Pose3D:
    """The pose of ``a``'s parent frame expressed in ``a``."""
    q = conjugate(a.orientation)
    x, y, z = rotate(q, (-a.x, -a.y, -a.z))
    return Pose3D(x, y, z, *q)
