"""Planar poses through TF: the robot pose and poses of other frames expressed in a server's frame.

Why: every server asks the same two questions ("where is the robot in frame F?" and "what is this
PoseStamped in frame F?") and must turn any TF failure into its own TF_ERROR code with tf2's
message. :class:`FrameError` carries that message; servers catch it and fill ``error_msg``.
"""

from __future__ import annotations

import math

from geometry_msgs.msg import PoseStamped
from rclpy.node import Node

from nav_stack.core.geometry import Pose2D, compose, yaw_or_nan
from ros_tools.tf import Transform, TransformError
from ros_tools.tf.ros import TransformListener


class FrameError(Exception):
    """A pose could not be expressed in the requested frame (no transform, unknown frame, ...)."""


def pose_of(transform: Transform) -> Pose2D:
    """The planar pose (x, y, yaw) of a child frame in its parent, from a parent ← child transform."""
    return Pose2D(transform.x, transform.y, transform.yaw)


class Frames:
    """A TF listener (one per process, shared by its servers) plus the planar lookups they need."""

    def __init__(self, node: Node, robot_base_frame: str = "base_link") -> None:
        self.robot_base_frame = robot_base_frame
        self.listener = TransformListener.shared(node)

    def frame_pose(self, target: str, source: str) -> Pose2D:
        """Latest pose of frame ``source`` in frame ``target``; FrameError when TF cannot tell."""
        try:
            return pose_of(self.listener.lookup(target, source))
        except TransformError as error:
            raise FrameError(f"no transform from '{source}' to '{target}': {error}") from error

    def robot_pose(self, frame: str) -> Pose2D:
        """Latest robot base pose in ``frame``."""
        return self.frame_pose(frame, self.robot_base_frame)

    def to_frame(self, msg: PoseStamped, frame: str) -> Pose2D:
        """A PoseStamped expressed in ``frame``; the yaw is NaN when the quaternion cannot be normalised
        (the planner core refuses NaN with its own message), the frame must be named and known."""
        p, q = msg.pose.position, msg.pose.orientation
        local = Pose2D(p.x, p.y, yaw_or_nan(q.x, q.y, q.z, q.w))
        source = msg.header.frame_id.lstrip("/")
        if not source:
            raise FrameError("the pose has an empty header.frame_id")
        if source == frame:
            return local
        parent = self.frame_pose(frame, source)
        moved = compose(parent, Pose2D(local.x, local.y, 0.0 if math.isnan(local.yaw) else local.yaw))
        return Pose2D(moved.x, moved.y, math.nan if math.isnan(local.yaw) else moved.yaw)

    def destroy(self) -> None:
        self.listener.destroy()
