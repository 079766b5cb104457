"""The messages amcl publishes and reads, built from the filter's plain numbers.

Why a module of its own: the node schedules (scans, TF, timers) and this turns its numbers into
Nav2's message layouts (and the localization health into diagnostic_msgs); both are easier to read
apart. Units: m, rad, s.
"""

from __future__ import annotations

import numpy as np
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav2_msgs.msg import Particle, ParticleCloud
from rclpy.time import Time

from nav_stack.core.localization.health import HealthMonitor, LocalizationState
from nav_stack.ros.common.conversions import pose_from_2d

#: Where (x, y, yaw) covariance entries sit in a 6×6 row-major (x, y, z, roll, pitch, yaw) one.
COVARIANCE_INDEX = {0: (0, 0), 1: (0, 1), 6: (1, 0), 7: (1, 1), 35: (2, 2)}
DIAGNOSTICS_TOPIC = "/diagnostics"
#: The DiagnosticStatus name of the localization health check ("<node>: <check>", as diagnostic_updater).
LOCALIZATION_STATUS = "amcl: localization"
LOCALIZED = "localized"  # the status message while the estimate can be trusted


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


def health_msg(monitor: HealthMonitor, stamp: float) -> DiagnosticArray:
    """/diagnostics: one ``amcl: localization`` status, OK or WARN with the cause as its message.

    The values are those of the latest filter update (none before the first one).
    """
    degraded = monitor.state is LocalizationState.DEGRADED
    status = DiagnosticStatus(name=LOCALIZATION_STATUS,
                              level=DiagnosticStatus.WARN if degraded else DiagnosticStatus.OK,
                              message=monitor.cause if degraded else LOCALIZED)
    sample = monitor.sample
    if sample is not None:
        status.values = [
            KeyValue(key="valid beams",
                     value=f"{sample.returns} of {sample.beams} within {sample.range_max:.1f} m"),
            KeyValue(key="matched ratio", value=f"{sample.matched_ratio:.2f}"),
            KeyValue(key="position std (m)", value=f"{sample.position_std:.3f}"),
            KeyValue(key="yaw std (rad)", value=f"{sample.yaw_std:.3f}"),
        ]
    msg = DiagnosticArray(status=[status])
    msg.header.stamp = time_msg(stamp)
    return msg
