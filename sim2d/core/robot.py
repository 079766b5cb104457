"""Robot models (TurtleBot3 waffle and burger, TurtleBot4) and the differential-drive kinematics.

TurtleBot3 figures (reference/nav2.md §6): wheel radius/separation and speed limits from the ROBOTIS
specs, acceleration limits from the gz DiffDrive plugin (linear 1.0 m/s²) and Nav2's minimal TB3 sim
(angular 2.0 rad/s²), the collision footprint from the URDF collision box, the base_scan mount from
the URDF. base_link sits 0.010 m above base_footprint; x and y coincide.

TurtleBot4 figures: next to TB4 below, each with its source. Its Create 3 base is round, so its
footprint is a regular polygon around its radius: a box around it would reach 0.24 m at the corners
and refuse spawns and turns on the spot that the round robot makes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim2d.core.geometry import normalize_angle, regular_polygon
from sim2d.core.lidar import LDS_01, RPLIDAR_A1, LidarParams

#: A round footprint is this many-sided regular polygon (pymunk collides convex polygons), drawn
#: around the circle so that it covers all of it: at most 2 % (r·(1/cos(π/16) − 1)) beyond the radius.
ROUND_FOOTPRINT_SIDES = 16


@dataclass(frozen=True)
class RobotModel:
    """A differential-drive robot with one planar lidar.

    Attributes:
        name: the name ``--robot`` takes (a key of ROBOTS).
        wheel_radius, wheel_separation: m.
        max_linear_velocity (m/s), max_angular_velocity (rad/s): commands beyond are clamped.
        max_linear_acceleration (m/s²), max_angular_acceleration (rad/s²): both speeding up and braking.
        lidar: the sensor's default figures; explicit ``lidar.*`` parameters override them.
        scan_offset: base_link → scan frame translation (x, y, z) (m).
        scan_yaw: base_link → scan frame rotation about z (rad); beam angles are in the scan frame.
        scan_frame: the scan's frame_id (the URDF link of the lidar).
        footprint_length, footprint_width: collision box (m), for a box-shaped robot.
        footprint_radius: collision circle (m), for a round robot; give this or the box, not both.
        footprint_offset_x: the footprint's centre along x in base_link (m).
        base_link_z: base_footprint → base_link height (m).
    """

    name: str
    wheel_radius: float
    wheel_separation: float
    max_linear_velocity: float
    max_angular_velocity: float
    max_linear_acceleration: float
    max_angular_acceleration: float
    lidar: LidarParams
    scan_offset: tuple[float, float, float]
    scan_yaw: float = 0.0
    scan_frame: str = "base_scan"
    footprint_length: float = 0.0
    footprint_width: float = 0.0
    footprint_radius: float = 0.0
    footprint_offset_x: float = 0.0
    base_link_z: float = 0.010

    def __post_init__(self) -> None:
        box = self.footprint_length > 0.0 and self.footprint_width > 0.0
        if box == (self.footprint_radius > 0.0):
            raise ValueError(f"robot {self.name}: give either footprint_radius or footprint_length and "
                             f"footprint_width (all > 0), got radius {self.footprint_radius}, "
                             f"box {self.footprint_length} x {self.footprint_width}")

    def footprint(self) -> list[tuple[float, float]]:
        """Collision outline (m) in base_footprint, counter-clockwise: the box's corners, or the
        ROUND_FOOTPRINT_SIDES-gon around the circle."""
        cx = self.footprint_offset_x
        if self.footprint_radius > 0.0:
            sides = ROUND_FOOTPRINT_SIDES
            corner = self.footprint_radius / math.cos(math.pi / sides)   # every edge touches the circle
            polygon = regular_polygon((cx, 0.0), corner, sides, rotation=math.pi / sides)  # an edge faces +x
            return [(float(x), float(y)) for x, y in polygon]
        hx, hy = self.footprint_length / 2.0, self.footprint_width / 2.0
        return [(cx - hx, -hy), (cx + hx, -hy), (cx + hx, hy), (cx - hx, hy)]

    def bounding_radius(self) -> float:
        """Distance (m) from base_footprint to the farthest footprint point: the reach at any yaw."""
        return max(math.hypot(x, y) for x, y in self.footprint())


WAFFLE = RobotModel("waffle", wheel_radius=0.033, wheel_separation=0.287, max_linear_velocity=0.26,
                    max_angular_velocity=1.82, max_linear_acceleration=1.0, max_angular_acceleration=2.0,
                    lidar=LDS_01, scan_offset=(-0.064, 0.0, 0.122),
                    footprint_length=0.266, footprint_width=0.266, footprint_offset_x=-0.064)
BURGER = RobotModel("burger", wheel_radius=0.033, wheel_separation=0.160, max_linear_velocity=0.22,
                    max_angular_velocity=2.84, max_linear_acceleration=1.0, max_angular_acceleration=2.0,
                    lidar=LDS_01, scan_offset=(-0.032, 0.0, 0.172),
                    footprint_length=0.140, footprint_width=0.140, footprint_offset_x=-0.032)
TB4 = RobotModel(
    "tb4",
    # Nav2's minimal TB4 sim (nav2_minimal_tb4_description create3.urdf.xacro, its gz DiffDrive):
    # 0.233 m between the wheels, 0.03575 m radius (the TB4 manual: 72 mm wheels).
    wheel_radius=0.03575, wheel_separation=0.233,
    # Create 3 docs (safety overrides): 0.306 m/s with the default safety profile (0.46 m/s without);
    # TurtleBot 4 manual (hardware specifications): 1.90 rad/s.
    max_linear_velocity=0.306, max_angular_velocity=1.90,
    # Create 3 docs: wheel_accel_limit 900 mm/s² (default and maximum); angular: Nav2's TB4 sim
    # DiffDrive, 3 rad/s² (the wheels alone would allow 2 × 0.9 / 0.233 = 7.7 rad/s²).
    max_linear_acceleration=0.9, max_angular_acceleration=3.0,
    # RPLIDAR A1M8 (TB4 manual) on the shell: base_link → shell_link z 0.0942 (0.03 + 0.0642), then
    # shell_link → rplidar_link (-0.04, 0, 0.098715) turned +π/2 about z (nav2_minimal_tb4_description
    # turtlebot4.urdf.xacro); the sim's lidar frame and scan frame_id are rplidar_link.
    lidar=RPLIDAR_A1, scan_offset=(-0.04, 0.0, 0.1929), scan_yaw=math.pi / 2, scan_frame="rplidar_link",
    # Round: the TB4 manual gives 342 x 339 mm (L x W), so a 0.171 m radius about the wheel axis
    # (the URDF's body cylinder is 0.164 m without the bumper); Nav2's robot_radius for it is 0.175.
    footprint_radius=0.171,
    # base_footprint coincides with base_link (the URDF's base_footprint_joint is at its origin).
    base_link_z=0.0,
)
ROBOTS = {model.name: model for model in (WAFFLE, BURGER, TB4)}


def robot_model(name: str) -> RobotModel:
    """The model called ``name``; a ValueError lists the known ones."""
    if name not in ROBOTS:
        raise ValueError(f"robot: unknown model {name!r} (known: {', '.join(sorted(ROBOTS))})")
    return ROBOTS[name]


@dataclass(frozen=True)
class Pose2D:
    """A planar pose: x, y (m) and yaw (rad) in a named frame chosen by the owner."""

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0


def _approach(current: float, target: float, max_delta: float) -> float:
    """Move ``current`` towards ``target`` by at most ``max_delta``."""
    return current + max(-max_delta, min(max_delta, target - current))


def limit_velocity(model: RobotModel, v: float, w: float, target_v: float, target_w: float,
                   dt: float) -> tuple[float, float]:
    """New body velocity (m/s, rad/s) after ``dt`` (s): target clamped to speed limits, then accel limits."""
    target_v = max(-model.max_linear_velocity, min(model.max_linear_velocity, target_v))
    target_w = max(-model.max_angular_velocity, min(model.max_angular_velocity, target_w))
    return (_approach(v, target_v, model.max_linear_acceleration * dt),
            _approach(w, target_w, model.max_angular_acceleration * dt))


def integrate(pose: Pose2D, v: float, w: float, dt: float) -> Pose2D:
    """Exact unicycle motion with constant (v, w) for ``dt`` (s): a straight line or a circular arc."""
    if abs(w) < 1e-9:
        return Pose2D(pose.x + v * dt * math.cos(pose.yaw), pose.y + v * dt * math.sin(pose.yaw), pose.yaw)
    yaw_end = pose.yaw + w * dt
    radius = v / w
    return Pose2D(pose.x + radius * (math.sin(yaw_end) - math.sin(pose.yaw)),
                  pose.y - radius * (math.cos(yaw_end) - math.cos(pose.yaw)),
                  normalize_angle(yaw_end))
