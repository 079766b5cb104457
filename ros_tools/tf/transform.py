"""Rigid transforms as (translation, unit quaternion) pairs: composition, inversion, interpolation.

Why a module of our own: tf2 and tf2_ros are not published as pip wheels, so the suite carries the
small amount of math a transform buffer needs. Quaternions are (x, y, z, w) like
geometry_msgs/Quaternion; translations are metres; times are seconds (float) of the ROS clock in use.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Transform:
    """Pose of a child frame expressed in its parent frame (tf convention: parent ← child).

    Applying it to a point given in the child frame yields the point in the parent frame.
    """

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    qx: float = 0.0
    qy: float = 0.0
    qz: float = 0.0
    qw: float = 1.0

    @classmethod
    def from_xy_yaw(cls, x: float, y: float, yaw: float, z: float = 0.0) -> Transform:
        """A planar transform: translation (x, y[, z]) m and rotation ``yaw`` rad about +z."""
        return cls(x, y, z, 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))

    @property
    def yaw(self) -> float:
        """Rotation about +z in rad (−π, π], exact for planar transforms."""
        return math.atan2(
            2.0 * (self.qw * self.qz + self.qx * self.qy),
            1.0 - 2.0 * (self.qy * self.qy + self.qz * self.qz),
        )

    def rotate(self, vx: float, vy: float, vz: float) -> tuple[float, float, float]:
        """Rotate a vector by this transform's quaternion (v' = q v q*)."""
        qx, qy, qz, qw = self.qx, self.qy, self.qz, self.qw
        # t = 2 q_vec × v ; v' = v + w t + q_vec × t
        tx = 2.0 * (qy * vz - qz * vy)
        ty = 2.0 * (qz * vx - qx * vz)
        tz = 2.0 * (qx * vy - qy * vx)
        return (
            vx + qw * tx + (qy * tz - qz * ty),
            vy + qw * ty + (qz * tx - qx * tz),
            vz + qw * tz + (qx * ty - qy * tx),
        )

    def apply(self, px: float, py: float, pz: float = 0.0) -> tuple[float, float, float]:
        """Map a point from the child frame into the parent frame."""
        rx, ry, rz = self.rotate(px, py, pz)
        return (rx + self.x, ry + self.y, rz + self.z)

    def __mul__(self, other: Transform) -> Transform:
        """Compose: ``a * b`` maps b's child frame into a's parent frame (a: A←B, b: B←C ⇒ A←C)."""
        x, y, z = self.apply(other.x, other.y, other.z)
        aw, ax, ay, az = self.qw, self.qx, self.qy, self.qz
        bw, bx, by, bz = other.qw, other.qx, other.qy, other.qz
        return Transform(
            x, y, z,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        )

    def inverse(self) -> Transform:
        """The transform in the other direction (child ← parent)."""
        conj = Transform(0.0, 0.0, 0.0, -self.qx, -self.qy, -self.qz, self.qw)
        x, y, z = conj.rotate(-self.x, -self.y, -self.z)
        return Transform(x, y, z, conj.qx, conj.qy, conj.qz, conj.qw)


def interpolate(a: Transform, b: Transform, ratio: float) -> Transform:
    """Linear interpolation of translation and spherical interpolation (slerp) of rotation.

    ``ratio`` 0 gives ``a`` and 1 gives ``b``; tf2 interpolates the same way between two stamps.
    """
    dot = a.qx * b.qx + a.qy * b.qy + a.qz * b.qz + a.qw * b.qw
    bq = (b.qx, b.qy, b.qz, b.qw)
    if dot < 0.0:  # take the short way round
        dot, bq = -dot, (-b.qx, -b.qy, -b.qz, -b.qw)
    if dot > 0.9995:  # nearly parallel: normalised lerp is accurate and avoids division by ~0
        wa, wb = 1.0 - ratio, ratio
    else:
        theta = math.acos(min(1.0, dot))
        sin_theta = math.sin(theta)
        wa = math.sin((1.0 - ratio) * theta) / sin_theta
        wb = math.sin(ratio * theta) / sin_theta
    q = [wa * qa + wb * qb for qa, qb in zip((a.qx, a.qy, a.qz, a.qw), bq, strict=True)]
    norm = math.sqrt(sum(c * c for c in q)) or 1.0
    return Transform(
        a.x + (b.x - a.x) * ratio,
        a.y + (b.y - a.y) * ratio,
        a.z + (b.z - a.z) * ratio,
        q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm,
    )
