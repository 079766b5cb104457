"""The messages amcl publishes and reads, built from the filter's plain numbers.

Why a module of its own: the node schedules (scans, TF, timers) and this turns its numbers into
Nav2's message layouts; both are easier to read apart. Units: m, rad, s.
"""

from __future__ import annotations

import numpy as np
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.msg import Particle, ParticleCloud
from rclpy.time import Time

from nav_stack.ros.conversions import pose_from_2d

#: Where (x, y, yaw) covariance entries sit in a 6×6 row-major (x, y, z, roll, pitch, yaw) one.
COVARIANCE_INDEX = {0: (0, 0), 1: (0, 1), 6: (1, 0), 7: (1, 1), 35: (2, 2)}


def time_msg(seconds: float) -> object:
    """builtin_interfaces/Time of ``seconds``."""
    return Time(nanoseconds=round(seconds * 1e9)).to_msg()


def covariance_3x3(covariance: object) -> np.ndarray:
    """(x, y, yaw) covariance from a 6×6 row-major pose covariance (x, y, z, roll, pitch, yaw)."""
    c = np.asarray(covariance, dtype=np.float64)
    return np.array([[c[0], c[1], 0.0], [c[6], c[7], 0.0], [0.0, 0.0, c[35]]])


def estimate_msg(x: float, y: float, yaw: float, covariance: np.ndarray, frame: str,
                 stamp: float) -> PoseWithCovarianceStamped:
    """``amcl_pose``: the estimate with its (x, y, yaw) covariance placed as Nav2 places it."""
    msg = PoseWithCovarianceStamped()
    msg.header.frame_id = frame
    msg.header.stamp = time_msg(stamp)
    msg.pose.pose = pose_from_2d(x, y, yaw)
    packed = [0.0] * 36
    for index, (row, col) in COVARIANCE_INDEX.items():
        packed[index] = float(covariance[row, col])
    msg.pose.covariance = packed
    return msg


def particle_cloud_msg(particles: np.ndarray, weights: np.ndarray, frame: str,
                       stamp: object) -> ParticleCloud:
    """``particle_cloud`` (nav2_msgs/ParticleCloud) of (N, 3) particles and their N weights."""
    msg = ParticleCloud()
    msg.header.frame_id = frame
    msg.header.stamp = stamp
    msg.particles = [Particle(pose=pose_from_2d(x, y, yaw), weight=float(w))
                     for (x, y, yaw), w in zip(particles.tolist(), weights.tolist(), strict=True)]
    return msg
