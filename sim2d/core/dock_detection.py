"""Dock detection standing in for a camera + AprilTag pipeline: the tag's pose in base_link, when seen.

A dock's tag is seen when it lies within the camera's horizontal field of view ``fov`` (rad) and
``min_range``..``max_range`` (m, horizontal distance from the camera), faces the camera (the line of
sight within ``max_view_angle`` of the tag's normal; a tag seen edge-on or from behind the dock is not
detected), and nothing blocks the line of sight: one ray cast with the lidar's ray caster against the
world, the dropped obstacles and the other docks' bodies. The dock's own body does not hide its tag:
the tag is mounted on it.

What is reported is the TAG's pose as a detector gives it, in ``base_link``, so that Nav2's
SimpleChargingDock (opennav_docking getRefinedPose, Jazzy and later) turns it back into the dock's
contact pose. Nav2's rule, with R_off = RPY(rotation_roll, rotation_pitch, rotation_yaw) and
t = (translation_x, translation_y) (sim2d.core.dock.TagMount)::

    yaw_dock      = yaw(R_tag · R_off)                      # roll and pitch dropped
    position_dock = position_tag + Rz(yaw_dock) · t          # t along the DOCK's heading; z set to 0

In SE(3) terms P_dock = P_tag · Rot(R_off) · Trans(t): the translation is applied after the rotation,
in the dock's frame, not in the tag's (P_tag · [R_off | t] would move the dock sideways along the
tag's x axis). So sim2d publishes R_tag = Rz(yaw_dock) · R_offᵀ and position_tag = position_dock −
Rz(yaw_dock) · t, at the tag's height. :func:`nav2_dock_pose` is that rule, for tests and checks.

Noise: Gaussian on the tag's planar position (σ ``position_stddev`` m on x and y of base_link) and on
its heading about the vertical (σ ``yaw_stddev`` rad), drawn from the generator the simulator hands
over, three draws per published detection.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sim2d.core.dock import Dock, TagMount
from sim2d.core.geometry import FloatArray, StaticGeometry, normalize_angle
from sim2d.core.lidar import cast_rays
from sim2d.core.robot import Pose2D
from sim2d.core.spatial import Quaternion, rotation_z, to_quaternion, yaw_of

#: A ray stopped this close (m) before the tag counts as reaching it (a wall right behind the tag).
_OCCLUSION_MARGIN = 0.01


@dataclass(frozen=True)
class DockDetectionParams:
    """The simulated detector (m, rad, Hz). Not in Nav2: Nav2 takes detections from an external
    detector (an AprilTag node) on ``detected_dock_pose``; these figures stand in for that camera.

    Defaults: the TurtleBot4's OAK-D Pro as Nav2's minimal TB4 description mounts and simulates it
    (camera about 0.06 m behind base_link, 1.25 rad horizontal field of view, 10 Hz); the ranges are
    those of a tag about 10 cm wide (below 0.2 m it leaves the image; the docked tb4's camera is
    0.24 m from the tag). Noise of a few millimetres and 0.01 rad, as AprilTag poses at 1 m.

    Attributes:
        rate: detections per second of sim time while a tag is seen (Hz).
        fov: horizontal field of view (rad), centred on the camera's heading.
        min_range, max_range: horizontal camera-to-tag distance (m) within which a tag is detected.
        camera_x, camera_y, camera_yaw: the camera's mount in base_link (m, m, rad).
        max_view_angle: largest angle (rad) between the line of sight and the tag's normal.
        position_stddev, yaw_stddev: Gaussian noise σ on the tag's x, y (m) and heading (rad).
    """

    rate: float = 10.0
    fov: float = 1.25
    min_range: float = 0.2
    max_range: float = 2.0
    camera_x: float = -0.06
    camera_y: float = 0.0
    camera_yaw: float = 0.0
    max_view_angle: float = 1.2
    position_stddev: float = 0.005
    yaw_stddev: float = 0.01

    def __post_init__(self) -> None:
        checks = {"rate": self.rate > 0.0, "fov": 0.0 < self.fov <= 2.0 * math.pi,
                  "min_range": self.min_range >= 0.0, "max_range": self.max_range > self.min_range,
                  "max_view_angle": 0.0 < self.max_view_angle <= math.pi / 2.0,
                  "position_stddev": self.position_stddev >= 0.0, "yaw_stddev": self.yaw_stddev >= 0.0}
        for name, ok in checks.items():
            if not ok:
                raise ValueError(f"dock_detection.{name}: invalid value {getattr(self, name)!r}")


@dataclass(frozen=True)
class TagDetection:
    """A detected tag of ``dock_id``: ``position`` (m) and ``orientation`` (x, y, z, w) in base_link."""

    dock_id: str
    position: tuple[float, float, float]
    orientation: Quaternion


def tag_pose_in_base_link(dock: Dock, robot: Pose2D, base_link_z: float,
                          noise: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> TagDetection:
    """The tag of ``dock`` as seen from base_link at ``robot`` (map), ``base_link_z`` (m) above the floor,
    with ``noise`` (dx, dy, dyaw) (m, m, rad) added to its planar position and heading in base_link."""
    mount = dock.type.tag
    tag_x, tag_y = mount.position(dock.pose)
    c, s = math.cos(robot.yaw), math.sin(robot.yaw)
    dx, dy = tag_x - robot.x, tag_y - robot.y
    heading = normalize_angle(dock.pose.yaw - robot.yaw + noise[2])
    rotation = rotation_z(heading) @ mount.rotation().T
    position = (c * dx + s * dy + noise[0], -s * dx + c * dy + noise[1], mount.height - base_link_z)
    return TagDetection(dock.id, position, to_quaternion(rotation))


def nav2_dock_pose(position: tuple[float, float, float], rotation: FloatArray, mount: TagMount) -> Pose2D:
    """The dock pose Nav2's SimpleChargingDock derives from a tag at ``position`` with ``rotation``
    (3, 3), in the same frame: heading of R_tag · R_off, position moved by t along that heading."""
    yaw = yaw_of(rotation @ mount.rotation())
    c, s = math.cos(yaw), math.sin(yaw)
    tx, ty = mount.translation_x, mount.translation_y
    return Pose2D(position[0] + c * tx - s * ty, position[1] + s * tx + c * ty, yaw)


class DockDetector:
    """Finds the nearest dock whose tag the camera sees and reports its tag with noise from ``rng``."""

    def __init__(self, params: DockDetectionParams, docks: tuple[Dock, ...],
                 rng: np.random.Generator) -> None:
        self.params, self.docks, self.rng = params, docks, rng

    def camera_pose(self, robot: Pose2D) -> Pose2D:
        """The camera's pose in the map frame (m, rad) for base_link at ``robot``."""
        p, c, s = self.params, math.cos(robot.yaw), math.sin(robot.yaw)
        return Pose2D(robot.x + c * p.camera_x - s * p.camera_y, robot.y + s * p.camera_x + c * p.camera_y,
                      normalize_angle(robot.yaw + p.camera_yaw))

    def sees(self, dock: Dock, camera: Pose2D, occluders: StaticGeometry) -> float | None:
        """Horizontal distance (m) from ``camera`` (map) to ``dock``'s tag when the camera detects it,
        else None; ``occluders`` is everything that can hide this tag (not the dock's own body)."""
        p = self.params
        tag_x, tag_y = dock.type.tag.position(dock.pose)
        dx, dy = tag_x - camera.x, tag_y - camera.y
        distance = math.hypot(dx, dy)
        if not p.min_range <= distance <= p.max_range:
            return None
        bearing = math.atan2(dy, dx)
        if abs(normalize_angle(bearing - camera.yaw)) > p.fov / 2.0:
            return None
        # the tag's normal points out of the dock, against the dock's heading; the camera must be on that side
        facing = (dx * math.cos(dock.pose.yaw) + dy * math.sin(dock.pose.yaw)) / max(distance, 1e-12)
        if facing < math.cos(p.max_view_angle):
            return None
        hit = cast_rays((camera.x, camera.y), np.array([bearing]), occluders, distance)[0]
        return distance if hit >= distance - _OCCLUSION_MARGIN else None

    def detect(self, robot: Pose2D, base_link_z: float,
               occluders: tuple[StaticGeometry, ...]) -> TagDetection | None:
        """The nearest seen tag from base_link at ``robot`` (map), or None; ``occluders[i]`` hides dock i."""
        camera = self.camera_pose(robot)
        best: tuple[float, Dock] | None = None
        for dock, geometry in zip(self.docks, occluders, strict=True):
            distance = self.sees(dock, camera, geometry)
            if distance is not None and (best is None or distance < best[0]):
                best = (distance, dock)
        if best is None:
            return None
        p = self.params
        dx, dy = self.rng.normal(0.0, 1.0, 2) * p.position_stddev
        dyaw = float(self.rng.normal(0.0, 1.0)) * p.yaw_stddev
        return tag_pose_in_base_link(best[1], robot, base_link_z, (float(dx), float(dy), dyaw))
