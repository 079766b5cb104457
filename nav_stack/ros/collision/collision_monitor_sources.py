"""The collision monitor's inputs: observation sources (LaserScan, PointCloud2) and zone shapes
received on topics (a dynamic polygon, the costmap's published footprint).

Each source keeps its latest message (sensor-data QoS, as Nav2 subscribes) and, when the monitor
processes a command, turns it into points (N, 2) in ``base_frame_id`` through TF. With
``base_shift_correction`` the transform goes from the sensor frame at the data's stamp, through
``odom_frame_id``, to the base frame at the command's time (nav_stack.core.collision_monitor.sources
.shift_corrected); without it, the latest sensor → base transform is used, as Nav2 does.

tf2's lookup with a timeout (Nav2 passes ``transform_tolerance``) blocks until the transform arrives;
a callback here may not block, so a lookup that would need data up to ``transform_tolerance`` newer
than what TF holds takes the newest transform instead. Older than that, the source is invalid.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from geometry_msgs.msg import PolygonStamped
from rclpy.node import Node
from sensor_msgs.msg import LaserScan, PointCloud2, PointField

from nav_stack.core.collision_monitor import (
    Rigid,
    SourceParams,
    Zone,
    rigid_from_quaternion,
    scan_points,
    shift_corrected,
    source_valid,
    within_height,
)
from nav_stack.core.geometry import FloatArray
from nav_stack.ros.common.qos import DEFAULT, LATCHED, SENSOR
from ros_tools.tf import ExtrapolationError, Transform, TransformError
from ros_tools.tf.ros import TransformListener, stamp_to_seconds

_FLOAT_TYPES = {PointField.FLOAT32: "f4", PointField.FLOAT64: "f8"}


def rigid(transform: Transform) -> Rigid:
    """ros_tools' Transform as the core's Rigid."""
    t = transform
    return rigid_from_quaternion(t.x, t.y, t.z, t.qx, t.qy, t.qz, t.qw)


def lookup_within(listener: TransformListener, target: str, source: str, time: float,
                  tolerance: float) -> Transform:
    """``target ← source`` at ``time`` (s), or the newest one if it is at most ``tolerance`` s older
    than ``time``; raises TransformError otherwise (see the module docstring)."""
    try:
        return listener.lookup(target, source, time)
    except ExtrapolationError:
        listener.lookup(target, source, time - tolerance)  # raises when TF lags more than that
        return listener.lookup(target, source, None)


def cloud_xyz(msg: PointCloud2) -> FloatArray:
    """The finite x, y, z (N, 3) of a PointCloud2 with float ``x``, ``y`` and ``z`` fields."""
    fields = {f.name: f for f in msg.fields}
    missing = [axis for axis in "xyz" if axis not in fields or fields[axis].datatype not in _FLOAT_TYPES]
    if missing:
        raise ValueError(f"a point cloud needs float32/float64 fields x, y, z; missing or not float: "
                         f"{', '.join(missing)}")
    order = ">" if msg.is_bigendian else "<"
    dtype = np.dtype({"names": ["x", "y", "z"],
                      "formats": [order + _FLOAT_TYPES[fields[a].datatype] for a in "xyz"],
                      "offsets": [fields[a].offset for a in "xyz"], "itemsize": msg.point_step})
    raw = np.frombuffer(bytes(msg.data), dtype=np.uint8)
    rows = raw[: msg.height * msg.row_step].reshape(msg.height, msg.row_step)[:, : msg.width * msg.point_step]
    points = np.ascontiguousarray(rows).view(dtype).ravel()
    xyz = np.column_stack([points["x"], points["y"], points["z"]]).astype(np.float64)
    return np.asarray(xyz[np.all(np.isfinite(xyz), axis=1)], dtype=np.float64)


class SourceFrames:
    """The transforms the sources need, as the node's frame parameters define them."""

    def __init__(self, listener: TransformListener, base_frame: str, odom_frame: str, tolerance: float,
                 base_shift_correction: bool) -> None:
        self.listener = listener
        self.base_frame, self.odom_frame = base_frame, odom_frame
        self.tolerance, self.base_shift_correction = tolerance, base_shift_correction

    def sensor_to_base(self, sensor_frame: str, stamp: float, now: float) -> Rigid:
        """Base (at ``now``) ← sensor (at ``stamp``); TransformError when TF cannot tell."""
        if not sensor_frame:
            raise TransformError("the data has an empty header.frame_id")
        if not self.base_shift_correction:
            return rigid(self.listener.lookup(self.base_frame, sensor_frame, None))
        then = lookup_within(self.listener, self.odom_frame, sensor_frame, stamp, self.tolerance)
        base_now = lookup_within(self.listener, self.odom_frame, self.base_frame, now, self.tolerance)
        return shift_corrected(rigid(then), rigid(base_now))


class ObservationSource:
    """One ``observation_sources`` entry: its subscription, latest data, and points on demand."""

    def __init__(self, node: Node, name: str, params: SourceParams, frames: SourceFrames) -> None:
        self.name, self.params, self.frames = name, params, frames
        self.reason = ""  # why the last points() call had no valid data
        #: what kind of fault ``reason`` is ("no data", "stale", "transform"): a new kind is worth a
        #: warning at once, a repeat of the same kind only after the throttle period
        self.reason_kind = ""
        self._latest: Any = None  # (stamp s, frame, sensor-frame points (N, 3))
        kind = LaserScan if params.type == "scan" else PointCloud2
        self._sub = node.create_subscription(kind, params.topic, self._on_data, SENSOR)
        self._node = node

    def _on_data(self, msg: LaserScan | PointCloud2) -> None:
        try:
            if isinstance(msg, LaserScan):
                pts = scan_points(msg.ranges, msg.angle_min, msg.angle_increment, msg.range_min,
                                  msg.range_max)
            else:
                pts = cloud_xyz(msg)
        except ValueError as error:
            self._node.get_logger().warning(f"[{self.name}]: dropping data: {error}",
                                            throttle_duration_sec=5.0)
            return
        self._latest = (stamp_to_seconds(msg.header.stamp), msg.header.frame_id, pts)

    def points(self, now: float) -> FloatArray | None:
        """The data as points (N, 2) in the base frame, or None (``reason`` says why) when the source
        never published, its data is older than ``source_timeout``, or TF cannot place it."""
        if self._latest is None:
            self.reason, self.reason_kind = f"no data received yet on '{self.params.topic}'", "no data"
            return None
        stamp, frame, pts = self._latest
        if not source_valid(stamp, now, self.params.source_timeout):
            self.reason = (f"latest data is {now - stamp:.3f} s old (source_timeout "
                           f"{self.params.source_timeout} s)")
            self.reason_kind = "stale"
            return None
        try:
            to_base = self.frames.sensor_to_base(frame, stamp, now)
        except TransformError as error:
            self.reason = f"cannot transform '{frame}' to '{self.frames.base_frame}': {error}"
            self.reason_kind = "transform"
            return None
        in_base = to_base.apply(pts)
        if self.params.type == "scan":
            return np.asarray(in_base[:, :2], dtype=np.float64)
        return within_height(in_base, self.params.min_height, self.params.max_height)

    def destroy(self) -> None:
        self._node.destroy_subscription(self._sub)


class ZoneShapeInput:
    """A zone whose outline comes from a PolygonStamped topic: ``polygon_sub_topic`` (a dynamic
    zone) or ``footprint_topic`` (an approach zone: the costmap's published footprint).

    Each processed command re-expresses the latest outline in the base frame with the newest TF, so
    a polygon given in another frame (the footprint in odom) follows the robot (Nav2's
    updatePolygon and FootprintSubscriber::getFootprintInRobotFrame).
    """

    def __init__(self, node: Node, zone: Zone, listener: TransformListener, base_frame: str) -> None:
        self.zone, self.listener, self.base_frame = zone, listener, base_frame
        p = zone.params
        footprint = p.action_type == "approach"
        topic = p.footprint_topic if footprint else p.polygon_sub_topic
        qos = LATCHED if p.polygon_subscribe_transient_local and not footprint else DEFAULT
        self._msg: PolygonStamped | None = None
        self._node = node
        self._sub = node.create_subscription(PolygonStamped, topic, self._on_polygon, qos)

    def _on_polygon(self, msg: PolygonStamped) -> None:
        self._msg = msg
        self.update()

    def update(self) -> None:
        """Set the zone's shape from the latest outline in the base frame (kept on failure)."""
        msg = self._msg
        if msg is None:
            return
        frame = msg.header.frame_id or self.base_frame
        try:
            to_base = rigid(self.listener.lookup(self.base_frame, frame, None))
            pts = to_base.apply(np.array([(p.x, p.y, 0.0) for p in msg.polygon.points]).reshape(-1, 3))
            self.zone.set_shape(pts[:, :2])
        except (TransformError, ValueError) as error:
            self._node.get_logger().warning(f"[{self.zone.name}]: polygon not updated: {error}",
                                            throttle_duration_sec=5.0)

    def destroy(self) -> None:
        self._node.destroy_subscription(self._sub)
