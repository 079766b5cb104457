"""``CpPose``: the robot pose from TF (``frame`` in ``reference_frame``), like SMACC2's cl_nav2z::CpPose.

An ISmaccUpdatable: the runtime's polling loop refreshes it (20 Hz by default); behaviors that need
the freshest pose call ``refresh()``. The shared TransformListener of the machine feeds it.
"""

from __future__ import annotations

import logging
import threading

from geometry_msgs.msg import PoseStamped
from std_msgs.msg import Header

from ros_tools.geometry import set_yaw
from ros_tools.tf import TransformError
from smacc_py.clients.cl_nav2z.geometry import Pose2D
from smacc_py.core import ISmaccComponent, ISmaccUpdatable
from smacc_py.ros.context import ros_context

_log = logging.getLogger("smacc_py")


class CpPose(ISmaccComponent, ISmaccUpdatable):
    """Robot pose (x, y in m, yaw in rad) of ``frame`` in ``reference_frame``; None until TF has it."""

    def __init__(self, frame: str = "base_link", reference_frame: str = "odom") -> None:
        self.frame = frame.lstrip("/")
        self.reference_frame = reference_frame.lstrip("/")
        self._lock = threading.Lock()
        self._pose: Pose2D | None = None
        self.last_error = ""

    def on_initialize(self) -> None:
        self._listener = ros_context(self.sm).tf_listener()

    def update(self) -> None:
        self.refresh()

    def refresh(self) -> Pose2D | None:
        """Look the transform up now; returns the pose, or None (``last_error`` says why)."""
        try:
            transform = self._listener.lookup(self.reference_frame, self.frame)
        except TransformError as error:
            self.last_error = str(error)
            return None
        pose = (transform.x, transform.y, transform.yaw)
        with self._lock:
            self._pose = pose
        return pose

    @property
    def pose(self) -> Pose2D | None:
        """The last pose looked up, or None."""
        with self._lock:
            return self._pose

    @property
    def is_valid(self) -> bool:
        """True once a pose was found."""
        return self.pose is not None

    def to_pose_stamped(self) -> PoseStamped:
        """The last pose as a PoseStamped in ``reference_frame`` (ValueError when there is none yet)."""
        pose = self.pose
        if pose is None:
            raise ValueError(
                f"CpPose: no transform {self.reference_frame} <- {self.frame} yet: {self.last_error}"
            )
        return make_pose_stamped(self.reference_frame, *pose, stamp=self.sm.now())


def make_header(frame_id: str, stamp: float = 0.0) -> Header:
    """A Header in ``frame_id`` stamped ``stamp`` s (0: latest). cl_nav2z stamps with the machine clock
    (``sm.now()``, the node clock under the ROS runtime), so its messages carry sim time when it is on."""
    header = Header(frame_id=frame_id)
    header.stamp.sec = int(stamp)
    header.stamp.nanosec = int((stamp - int(stamp)) * 1e9)
    return header


def make_pose_stamped(frame_id: str, x: float, y: float, yaw: float, stamp: float = 0.0) -> PoseStamped:
    """A PoseStamped at (x, y, yaw) in ``frame_id``; ``stamp`` in s (0: latest)."""
    msg = PoseStamped()
    msg.header = make_header(frame_id, stamp)
    msg.pose.position.x, msg.pose.position.y = float(x), float(y)
    set_yaw(msg.pose.orientation, yaw)
    return msg
