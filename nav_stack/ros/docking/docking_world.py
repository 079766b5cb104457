"""The docking sequences' world on ROS: poses through TF and the local costmap for the collision check.

Implements nav_stack.core.docking.world.DockingWorld. Poses come from the process's shared TF listener
(latest transforms); a detection is transformed at its own stamp, since the camera saw the dock then.
With ``controller.use_collision_detection`` the local costmap arrives as nav2_msgs/Costmap on
``controller.costmap_topic`` and the robot outline as PolygonStamped on ``controller.footprint_topic``
(transient local, as the costmap node publishes them); the outline is brought into the robot frame
through TF, and until one arrives the robot is a 0.22 m circle (as behavior_server assumes).
``controller.footprint`` (not in Nav2), when set, is the outline instead of the published one.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from geometry_msgs.msg import PolygonStamped
from nav2_msgs.msg import Costmap
from rclpy.node import Node

from nav_stack.core.control import CircleFootprint, CostGrid, PolygonFootprint
from nav_stack.core.docking import Detection, DockingControllerParams, FrameUnavailable, Obstacles, Pose3D
from nav_stack.core.geometry import Pose2D, compose, to_frame
from nav_stack.ros.common.conversions import spec_from_info
from nav_stack.ros.common.frames import FrameError, Frames
from nav_stack.ros.common.qos import LATCHED
from nav_stack.ros.costmap.costmap_params import parse_footprint
from ros_tools.tf import Transform, TransformError


def cost_grid(msg: Costmap) -> CostGrid:
    """The CostGrid of a nav2_msgs/Costmap (raw 0..255 costs)."""
    spec = spec_from_info(msg.metadata)
    return CostGrid(np.frombuffer(msg.data, dtype=np.uint8).reshape(spec.shape).copy(), spec)


class RosDockingWorld:
    """TF lookups and the local costmap for the docking sequences."""

    def __init__(self, node: Node, frames: Frames, controller: DockingControllerParams) -> None:
        self.node, self.frames = node, frames
        self._grid: tuple[CostGrid, str] | None = None
        self._footprint_msg: PolygonStamped | None = None
        self._footprint: tuple[PolygonStamped, Any] | None = None  # (message, its outline in the robot frame)
        self._subs = []
        points = parse_footprint(controller.footprint, node.get_name(), "controller.footprint")
        if points and len(points) < 3:
            raise ValueError(f"{node.get_name()}: controller.footprint needs >= 3 points, got "
                             f"{controller.footprint!r}")
        self._outline = PolygonFootprint(points) if points else None
        if controller.use_collision_detection:
            self._subs = [
                node.create_subscription(Costmap, controller.costmap_topic, self._on_costmap, LATCHED),
                node.create_subscription(PolygonStamped, controller.footprint_topic, self._on_footprint,
                                         LATCHED),
            ]

    # -- DockingWorld --------------------------------------------------------------------------------
    def robot_pose(self, frame: str) -> Pose2D:
        try:
            return self.frames.robot_pose(frame)
        except FrameError as error:
            raise FrameUnavailable(str(error)) from error

    def transform(self, pose: Pose2D, source: str, target: str) -> Pose2D:
        if source == target:
            return pose
        try:
            return compose(self.frames.frame_pose(target, source), pose)
        except FrameError as error:
            raise FrameUnavailable(str(error)) from error

    def detection_in(self, detection: Detection, frame: str) -> Pose3D:
        try:
            transform = self.frames.listener.lookup(frame, detection.frame, detection.stamp)
        except TransformError as error:
            raise FrameUnavailable(str(error)) from error
        p = detection.pose
        moved = transform * Transform(p.x, p.y, p.z, p.qx, p.qy, p.qz, p.qw)
        return Pose3D(moved.x, moved.y, moved.z, moved.qx, moved.qy, moved.qz, moved.qw)

    def obstacles(self) -> Obstacles | None:
        if self._grid is None:
            return None
        grid, frame = self._grid
        return Obstacles(grid, self._robot_outline(), frame)

    # -- inputs ----------------------------------------------------------------------------------------
    def _on_costmap(self, msg: Costmap) -> None:
        self._grid = (cost_grid(msg), msg.header.frame_id.lstrip("/"))

    def _on_footprint(self, msg: PolygonStamped) -> None:
        self._footprint_msg = msg

    def _robot_outline(self) -> Any:
        """controller.footprint, else the last published footprint in the robot frame (converted once
        per message)."""
        if self._outline is not None:
            return self._outline
        msg = self._footprint_msg
        if msg is None or len(msg.polygon.points) < 3:
            return CircleFootprint()
        if self._footprint is not None and self._footprint[0] is msg:
            return self._footprint[1]
        try:
            robot = self.frames.robot_pose(msg.header.frame_id)
        except FrameError:
            return CircleFootprint()
        local = to_frame(np.array([(p.x, p.y, 0.0) for p in msg.polygon.points]), robot)
        outline = PolygonFootprint(tuple((float(x), float(y)) for x, y in local[:, :2]))
        self._footprint = (msg, outline)
        return outline

    def destroy(self) -> None:
        for sub in self._subs:
            self.node.destroy_subscription(sub)
        self._subs = []
