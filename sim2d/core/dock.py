"""Charging docks: the dock models (types), a dock placed in a world, its solid body and its contacts.

A world declares each dock by its CONTACT pose (map frame): where base_link stands, heading into the
dock, when the robot is docked. It is the pose Nav2's docking_server keeps for the dock in its
database, and the pose its SimpleChargingDock recovers from a tag detection (sim2d/core/dock_detection.py).
The robot drives forward (+x) into the dock. The dock's type supplies the rest:

- body: a box ``body_depth`` × ``body_width`` (m) ahead of the contact pose, centred on its x axis.
  Its face stands ``clearance`` beyond the docked robot's front, so a docked robot touches nothing;
  the robot's front is its footprint's reach along +x over every heading within the yaw tolerance,
  so the face's distance depends on the robot model (0.184 m for tb4, 0.092 m for the waffle). The
  body is a static obstacle: the lidar sees it, and driving into it is a collision like any wall.
- contacts: the battery charges while base_link is within ``contact_tolerance`` (m) and
  ``contact_yaw_tolerance`` (rad) of the contact pose and the robot is at rest (sim2d/core/battery.py).
- tag: where the AprilTag sits, as Nav2 SimpleChargingDock's ``external_detection_*`` offsets
  (:class:`TagMount`).

Why 0.05 m of contact tolerance rather than a tighter figure: Nav2's SimpleChargingDock calls the
robot docked once it is within ``docking_threshold`` (0.05 m) of the dock pose and the docking server
stops it there (about 4 cm short after braking); with a tighter tolerance that robot would never charge
and DockRobot would fail after ``wait_charge_timeout``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from sim2d.core.geometry import FloatArray, normalize_angle
from sim2d.core.robot import Pose2D, RobotModel
from sim2d.core.spatial import rotation_rpy

#: Headings sampled over ±yaw tolerance when measuring the footprint's forward reach: the reach of a
#: polygon is smooth in the heading, so 41 samples miss its maximum by well under a micrometre.
_REACH_SAMPLES = 41


@dataclass(frozen=True)
class TagMount:
    """Where the dock's tag sits, in Nav2 SimpleChargingDock's terms (m, rad).

    Nav2 turns a detected tag pose into the dock pose by rotating the tag's orientation by
    RPY(rotation_roll, rotation_pitch, rotation_yaw), keeping only the heading, then moving the tag's
    position by (translation_x, translation_y) along that heading (sim2d/core/dock_detection.py).
    The defaults are nav2_bringup's Jazzy nav2_params.yaml (external_detection_translation_x -0.18,
    _y 0, rotation_roll -1.57, _pitch -1.57, _yaw 0): the tag 0.18 m ahead of the contact pose,
    its z axis pointing into the dock, x to the dock's left, y up. The file's 1.57 is not exactly π/2
    (0.0008 rad short); sim2d uses 1.57 too, so the docking server's composition gives back a level
    dock frame. (opennav_docking's C++ defaults differ: -0.20, roll -1.57, pitch +1.57.)

    Attributes:
        height: the tag centre's height above the floor (m). Not in Nav2: its rule drops z (the dock
            pose gets z = 0); it only sets the z of the published tag pose.
    """

    translation_x: float = -0.18
    translation_y: float = 0.0
    rotation_roll: float = -1.57
    rotation_pitch: float = -1.57
    rotation_yaw: float = 0.0
    height: float = 0.1

    def rotation(self) -> FloatArray:
        """The offset's rotation R_off (3, 3): dock orientation = tag orientation · R_off."""
        return rotation_rpy(self.rotation_roll, self.rotation_pitch, self.rotation_yaw)

    def position(self, contact: Pose2D) -> tuple[float, float]:
        """The tag centre (x, y) (m) in the frame of ``contact``: the contact pose moved by minus the
        translation along the contact heading."""
        c, s = math.cos(contact.yaw), math.sin(contact.yaw)
        tx, ty = self.translation_x, self.translation_y
        return contact.x - (c * tx - s * ty), contact.y - (s * tx + c * ty)


@dataclass(frozen=True)
class DockType:
    """A dock model: its body (m), its contacts' reach (m, rad) and its tag.

    Attributes:
        name: the ``type`` a world's dock entry names.
        body_depth, body_width: the solid box ahead of the contact pose, along and across its x (m).
        clearance: gap between the docked robot's front and the body's face (m).
        contact_tolerance, contact_yaw_tolerance: how far base_link may be from the contact pose (m)
            and its heading from the contact heading (rad) while the contacts charge.
        tag: the tag's mounting.
    """

    name: str
    body_depth: float
    body_width: float
    clearance: float
    contact_tolerance: float = 0.05
    contact_yaw_tolerance: float = 0.1
    tag: TagMount = field(default_factory=TagMount)

    def __post_init__(self) -> None:
        for name in ("body_depth", "body_width", "clearance", "contact_tolerance", "contact_yaw_tolerance"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"dock type {self.name}: {name} must be > 0, got {getattr(self, name)}")


#: The iRobot Create 3 standard dock (TurtleBot4): its collision box in irobot_create_description's
#: standard_dock.urdf.xacro is 0.04 m deep and 0.13 m wide; in that package's TB4 sim a docked robot's
#: base_link is 0.157 m from the dock link, whose box starts 0.025 m further: its face 0.182 m from
#: base_link, 0.011 m beyond the 0.171 m round bumper. Hence the 0.01 m clearance.
CREATE3_DOCK = DockType("create3_dock", body_depth=0.04, body_width=0.13, clearance=0.01)
DOCK_TYPES: dict[str, DockType] = {CREATE3_DOCK.name: CREATE3_DOCK}


@dataclass(frozen=True)
class Dock:
    """A dock of a world: its id, type and contact pose (map frame), and its contact tolerances
    (m, rad; the type's unless the world file overrides them)."""

    id: str
    type: DockType
    pose: Pose2D
    contact_tolerance: float
    contact_yaw_tolerance: float

    def in_contact(self, pose: Pose2D) -> bool:
        """True when base_link at ``pose`` (map) is on the contacts: within both tolerances."""
        near = math.hypot(pose.x - self.pose.x, pose.y - self.pose.y) <= self.contact_tolerance
        return near and abs(normalize_angle(pose.yaw - self.pose.yaw)) <= self.contact_yaw_tolerance

    def staging_pose(self, offset: float = 0.7) -> Pose2D:
        """The pose ``offset`` m in front of the contact pose, same heading: Nav2's staging pose with
        staging_x_offset = -offset (its default -0.7), where the approach starts."""
        c, s = math.cos(self.pose.yaw), math.sin(self.pose.yaw)
        return Pose2D(self.pose.x - offset * c, self.pose.y - offset * s, self.pose.yaw)

    def face_distance(self, robot: RobotModel) -> float:
        """Distance (m) from the contact pose to the body's face along the dock's x for ``robot``."""
        return forward_reach(robot, self.contact_yaw_tolerance) + self.type.clearance

    def body(self, robot: RobotModel) -> FloatArray:
        """The body's corners (4, 2) (m, map frame), counter-clockwise, for ``robot``'s footprint."""
        near = self.face_distance(robot)
        far = near + self.type.body_depth
        half = self.type.body_width / 2.0
        local = np.array([[near, -half], [far, -half], [far, half], [near, half]])
        c, s = math.cos(self.pose.yaw), math.sin(self.pose.yaw)
        rotation = np.array([[c, -s], [s, c]])
        corners: FloatArray = local @ rotation.T + np.array([self.pose.x, self.pose.y])
        return corners


def forward_reach(robot: RobotModel, yaw_tolerance: float) -> float:
    """How far (m) the footprint reaches ahead of base_link (along the heading it should have) when
    the robot is turned by up to ±``yaw_tolerance`` (rad): the robot's front on the dock."""
    footprint = np.array(robot.footprint())
    yaws = np.linspace(-yaw_tolerance, yaw_tolerance, _REACH_SAMPLES)
    reach = np.cos(yaws)[:, None] * footprint[None, :, 0] - np.sin(yaws)[:, None] * footprint[None, :, 1]
    return float(reach.max())


def dock_in_contact(docks: tuple[Dock, ...], pose: Pose2D) -> Dock | None:
    """The first dock whose contacts ``pose`` (map) is on, or None."""
    return next((dock for dock in docks if dock.in_contact(pose)), None)
