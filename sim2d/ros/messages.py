"""Message builders: core state → ROS messages, with every stamp in sim time; and the one input
that needs more than a field copy (a dropped obstacle from a visualization_msgs/Marker).

Why reusable message objects: at 100× real time the node publishes thousands of messages per wall
second, and filling a preallocated message is several times cheaper than building a new one.
Publishing serialises the message at once, so reusing it afterwards is safe.
"""

from __future__ import annotations

import array
import math

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import PointStamped, PoseStamped, TransformStamped
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import BatteryState, LaserScan
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker

from ros_tools.geometry import set_yaw
from sim2d.core.battery import Battery
from sim2d.core.disturbances import DroppedObstacle
from sim2d.core.dock_detection import TagDetection
from sim2d.core.lidar import LidarParams
from sim2d.core.robot import Pose2D, RobotModel

MAP_FRAME = "map"
ODOM_FRAME = "odom"
BASE_FOOTPRINT = "base_footprint"
BASE_LINK = "base_link"

_UNKNOWN = 1e6  # covariance of unobserved dimensions (z, roll, pitch), as gz and TB3 publish


def stamp(time_ns: int) -> Time:
    """A builtin_interfaces/Time from sim time (ns)."""
    return Time(sec=time_ns // 1_000_000_000, nanosec=time_ns % 1_000_000_000)


def clock(time_ns: int) -> Clock:
    """/clock message."""
    return Clock(clock=stamp(time_ns))


class OdometryBuilder:
    """Fills one nav_msgs/Odometry (frame_id → base_footprint) per call."""

    def __init__(self, frame_id: str) -> None:
        self.msg = Odometry()
        self.msg.header.frame_id = frame_id
        self.msg.child_frame_id = BASE_FOOTPRINT
        self._pose_cov = np.zeros(36)
        self._twist_cov = np.diag([1e-4, _UNKNOWN, _UNKNOWN, _UNKNOWN, _UNKNOWN, 1e-3]).ravel()

    def build(self, time_ns: int, pose: Pose2D, v: float, w: float, var_xy: float,
              var_yaw: float) -> Odometry:
        """Pose (m, rad) with covariance ``var_xy`` (m²) / ``var_yaw`` (rad²); body twist (m/s, rad/s)."""
        msg = self.msg
        msg.header.stamp = stamp(time_ns)
        msg.pose.pose.position.x, msg.pose.pose.position.y = pose.x, pose.y
        set_yaw(msg.pose.pose.orientation, pose.yaw)
        cov = self._pose_cov
        cov[0] = cov[7] = max(var_xy, 1e-6)
        cov[14] = cov[21] = cov[28] = _UNKNOWN
        cov[35] = max(var_yaw, 1e-6)
        msg.pose.covariance = cov
        msg.twist.twist.linear.x, msg.twist.twist.angular.z = v, w
        msg.twist.covariance = self._twist_cov
        return msg


class TfBuilder:
    """odom → base_footprint on /tf."""

    def __init__(self) -> None:
        self.transform = TransformStamped()
        self.transform.header.frame_id = ODOM_FRAME
        self.transform.child_frame_id = BASE_FOOTPRINT
        self.msg = TFMessage(transforms=[self.transform])

    def build(self, time_ns: int, pose: Pose2D) -> TFMessage:
        t = self.transform
        t.header.stamp = stamp(time_ns)
        t.transform.translation.x, t.transform.translation.y = pose.x, pose.y
        set_yaw(t.transform.rotation, pose.yaw)
        self.msg.transforms = [t]
        return self.msg


def static_transforms(robot: RobotModel, time_ns: int) -> TFMessage:
    """base_footprint → base_link (z) → the robot's scan frame (URDF mount and yaw) for /tf_static."""
    chain = [(BASE_FOOTPRINT, BASE_LINK, (0.0, 0.0, robot.base_link_z), 0.0),
             (BASE_LINK, robot.scan_frame, robot.scan_offset, robot.scan_yaw)]
    transforms = []
    for parent, child, (x, y, z), yaw in chain:
        t = TransformStamped()
        t.header.stamp = stamp(time_ns)
        t.header.frame_id, t.child_frame_id = parent, child
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = x, y, z
        set_yaw(t.transform.rotation, yaw)
        transforms.append(t)
    return TFMessage(transforms=transforms)


class ScanBuilder:
    """sensor_msgs/LaserScan in the robot's scan frame from the core's ranges (REP 117 ±inf kept)."""

    def __init__(self, params: LidarParams, frame_id: str) -> None:
        msg = LaserScan()
        msg.header.frame_id = frame_id
        msg.angle_min, msg.angle_max = params.angle_min, params.angle_max
        msg.angle_increment = params.angle_increment
        msg.time_increment = 0.0   # all beams at one instant: no motion distortion is simulated
        msg.scan_time = 1.0 / params.rate
        msg.range_min, msg.range_max = params.range_min, params.range_max
        self.msg = msg

    def build(self, time_ns: int, ranges: np.ndarray) -> LaserScan:
        self.msg.header.stamp = stamp(time_ns)
        values = array.array("f")
        values.frombytes(ranges.astype(np.float32).tobytes())
        self.msg.ranges = values
        return self.msg


def battery_state(time_ns: int, battery: Battery) -> BatteryState:
    """sensor_msgs/BatteryState (percentage 0..1, LiPo, charging on a charger at rest).

    ``current`` (A) is positive while charging (Nav2's SimpleChargingDock: charging when above its
    charging_threshold, 0.5 A) and negative while discharging (sim2d/core/battery.py).
    """
    msg = BatteryState()
    msg.header.stamp = stamp(time_ns)
    msg.header.frame_id = BASE_LINK
    msg.voltage = battery.voltage
    msg.percentage = battery.charge
    msg.capacity = msg.design_capacity = battery.params.capacity_ah
    msg.charge = battery.charge * battery.params.capacity_ah
    msg.current = battery.current
    msg.temperature = math.nan
    if battery.charging:
        msg.power_supply_status = BatteryState.POWER_SUPPLY_STATUS_FULL if battery.charge >= 1.0 \
            else BatteryState.POWER_SUPPLY_STATUS_CHARGING
    else:
        msg.power_supply_status = BatteryState.POWER_SUPPLY_STATUS_DISCHARGING
    msg.power_supply_health = BatteryState.POWER_SUPPLY_HEALTH_GOOD if battery.charge > 0.0 \
        else BatteryState.POWER_SUPPLY_HEALTH_DEAD
    msg.power_supply_technology = BatteryState.POWER_SUPPLY_TECHNOLOGY_LIPO
    msg.present = True
    return msg


def detected_dock_pose(time_ns: int, detection: TagDetection) -> PoseStamped:
    """The tag's pose in base_link, stamped with the sim time of the detection (``detected_dock_pose``)."""
    msg = PoseStamped()
    msg.header.stamp = stamp(time_ns)
    msg.header.frame_id = BASE_LINK
    position, orientation = msg.pose.position, msg.pose.orientation
    position.x, position.y, position.z = detection.position
    orientation.x, orientation.y, orientation.z, orientation.w = detection.orientation
    return msg


def collision_point(time_ns: int, x: float, y: float) -> PointStamped:
    """Contact point of a new collision, map frame."""
    msg = PointStamped()
    msg.header.stamp = stamp(time_ns)
    msg.header.frame_id = MAP_FRAME
    msg.point.x, msg.point.y = x, y
    return msg


def obstacle_from_marker(marker: Marker) -> DroppedObstacle:
    """The obstacle a CYLINDER marker describes: centre ``pose.position`` (x, y) in ``map``, radius
    ``scale.x / 2`` (RViz's cylinder: scale.x and scale.y are the diameters; they must be equal).

    Why a Marker: it is the standard message for "a cylinder of this size at this pose", the one RViz
    users already write, so no custom interface is needed (Gazebo's /spawn_entity takes an SDF instead).

    Raises:
        ValueError: naming what the marker gets wrong (action, type, frame, size).
    """
    if marker.action != Marker.ADD:
        raise ValueError(f"action {marker.action}: only ADD ({Marker.ADD}) drops an obstacle")
    if marker.type != Marker.CYLINDER:
        raise ValueError(f"type {marker.type}: only CYLINDER ({Marker.CYLINDER}) is supported")
    if marker.header.frame_id not in ("", MAP_FRAME):
        raise ValueError(f"frame {marker.header.frame_id!r} is not {MAP_FRAME!r}")
    if marker.scale.x != marker.scale.y:
        raise ValueError(f"scale.x {marker.scale.x} != scale.y {marker.scale.y}: only round cylinders")
    return DroppedObstacle(marker.pose.position.x, marker.pose.position.y, 0.5 * marker.scale.x)
