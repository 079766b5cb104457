"""``CpAmcl``: sets AMCL's initial pose by publishing ``initialpose`` (PoseWithCovarianceStamped, QoS 10)."""

from __future__ import annotations

from geometry_msgs.msg import PoseWithCovarianceStamped

from smacc_py.clients.cl_nav2z.cp_pose import make_pose_stamped
from smacc_py.core import ISmaccComponent
from smacc_py.ros.context import ros_context

# Covariance of sm_nav2_gazebo_test_1's initial pose: σ² x = y = 0.25 m², yaw = 0.06 rad².
DEFAULT_COVARIANCE = (0.25, 0.25, 0.06)


class CpAmcl(ISmaccComponent):
    """Publisher of the initial pose, in ``frame_id`` (map)."""

    def __init__(self, topic: str = "initialpose", frame_id: str = "map") -> None:
        self.topic, self.frame_id = topic, frame_id
        self.published: list[tuple[float, float, float]] = []

    def on_initialize(self) -> None:
        self._pub = ros_context(self.sm).node.create_publisher(PoseWithCovarianceStamped, self.topic, 10)

    def set_initial_pose(
        self, x: float, y: float, yaw: float, covariance: tuple[float, float, float] = DEFAULT_COVARIANCE
    ) -> None:
        """Publish (x, y in m, yaw in rad) with variances (x, y in m², yaw in rad²), stamped now (machine
        clock)."""
        pose = make_pose_stamped(self.frame_id, x, y, yaw, stamp=self.sm.now())
        msg = PoseWithCovarianceStamped(header=pose.header)
        msg.pose.pose = pose.pose
        cov = [0.0] * 36
        cov[0], cov[7], cov[35] = covariance
        msg.pose.covariance = cov
        self._pub.publish(msg)
        self.published.append((float(x), float(y), float(yaw)))
