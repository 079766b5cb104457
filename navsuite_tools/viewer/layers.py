"""Which topics the viewer draws, and how each message becomes a page payload.

Besides the fixed topics of ``LAYERS``, the collision monitor's zones are found by who publishes them
(``POLYGON_PUBLISHER``): their topics are whatever each zone's ``polygon_pub_topic`` says (Jazzy's
default: the zone's name), so the node gathers every PolygonStamped topic that node publishes into
one ``collision_polygons`` layer (``polygons``).

Each :class:`LayerSpec` names a layer key (what the page calls it), a default topic, the message
types accepted on it (the first one present on the graph wins) and a converter. Converters run
lazily, when a browser stream needs the layer (see ``hub``), so they may do real work: TF lookups,
decimation, base64. They receive the message and a :class:`DisplayFrames` and return JSON-ready data.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from navsuite_tools.viewer import encode
from navsuite_tools.viewer.encode import Planar
from ros_tools.geometry import yaw_of
from ros_tools.tf.buffer import ExtrapolationError, TransformBuffer

#: GoalStatus codes (action_msgs/GoalStatus) → names the page shows.
GOAL_STATUS = {0: "UNKNOWN", 1: "ACCEPTED", 2: "EXECUTING", 3: "CANCELING", 4: "SUCCEEDED",
               5: "CANCELED", 6: "ABORTED"}
#: visualization_msgs/Marker types that mark a place (arrow, cube, sphere, cylinder); text is skipped.
_PLACE_MARKERS = {0, 1, 2, 3}
_SPHERE = 2  # Marker.SPHERE: one dot at pose.position
_POINT_LISTS = {7, 8}  # Marker.SPHERE_LIST, Marker.POINTS: dots at points[]


class DisplayFrames:
    """Planar transforms from any frame into the display frame, from a TF buffer (RViz's Fixed Frame)."""

    def __init__(self, buffer: TransformBuffer, frame: str) -> None:
        self.buffer = buffer
        self.frame = frame

    def planar(self, frame_id: str, stamp: Any = None) -> Planar:
        """display ← ``frame_id`` at ``stamp`` (a Time message; zero or None = latest).

        If the stamp lies outside the buffered history (a message newer than the last /tf), the
        latest transform is used, as a viewer would rather draw slightly stale than nothing.
        Raises TransformError (with tf2's message) when the frames are not connected.
        """
        frame_id = frame_id.lstrip("/")
        if not frame_id or frame_id == self.frame:
            return encode.IDENTITY
        seconds = stamp.sec + stamp.nanosec * 1e-9 if stamp is not None else 0.0
        try:
            tf = self.buffer.lookup(self.frame, frame_id, seconds or None)
        except ExtrapolationError:
            tf = self.buffer.lookup(self.frame, frame_id, None)
        return (tf.x, tf.y, tf.yaw)


def _xyyaw(pose: Any) -> tuple[float, float, float]:
    return (pose.position.x, pose.position.y, yaw_of(pose.orientation))


def _pose_array(poses: Sequence[Any]) -> np.ndarray:
    return np.array([_xyyaw(p) for p in poses], dtype=np.float64).reshape(-1, 3)


# ---------------------------------------------------------------- converters (msg, frames, limit) → data
def grid(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    info = msg.info
    origin = encode.pose_payload(_xyyaw(info.origin), frames.planar(msg.header.frame_id))
    data = bytes(np.asarray(msg.data, dtype=np.int8).view(np.uint8))
    return encode.grid_payload(info.width, info.height, info.resolution, tuple(origin), data,  # type: ignore[arg-type]
                               msg.header.frame_id)


def grid_digest(msg: Any) -> str:
    info = msg.info
    return encode.grid_digest(info.width, info.height, info.resolution, _xyyaw(info.origin),
                              bytes(np.asarray(msg.data, dtype=np.int8).view(np.uint8))) + msg.header.frame_id


def scan(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    tf = frames.planar(msg.header.frame_id, msg.header.stamp)
    points = encode.scan_points(msg.ranges, msg.angle_min, msg.angle_increment, msg.range_min,
                                msg.range_max, tf)
    return {"points": points, "origin": [round(v, 3) for v in tf]}


def odometry(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    tf = frames.planar(msg.header.frame_id, msg.header.stamp)
    return {"pose": encode.pose_payload(_xyyaw(msg.pose.pose), tf)}


def pose_with_covariance(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    tf = frames.planar(msg.header.frame_id, msg.header.stamp)
    c = msg.pose.covariance
    return {"pose": encode.pose_payload(_xyyaw(msg.pose.pose), tf),
            "covariance": [round(float(c[i]), 6) for i in (0, 1, 7, 35)]}  # xx, xy, yy, yaw-yaw


def pose_stamped(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    tf = frames.planar(msg.header.frame_id, msg.header.stamp)
    return {"pose": encode.pose_payload(_xyyaw(msg.pose), tf)}


def particles(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    """nav2_msgs/ParticleCloud (``particles[].pose``) or geometry_msgs/PoseArray (``poses``)."""
    tf = frames.planar(msg.header.frame_id, msg.header.stamp)
    poses = [p.pose for p in msg.particles] if hasattr(msg, "particles") else list(msg.poses)
    return {"poses": encode.poses_payload(_pose_array(poses), tf, limit), "count": len(poses)}


def path(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    tf = frames.planar(msg.header.frame_id, msg.header.stamp)
    poses = [p.pose for p in msg.poses]
    return {"poses": encode.poses_payload(_pose_array(poses), tf, limit), "count": len(poses)}


def waypoints(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    """geometry_msgs/PoseArray, nav_msgs/Path or the MarkerArray Nav2's RViz panel publishes."""
    if hasattr(msg, "markers"):
        marks = [m for m in msg.markers if m.action == 0 and m.type in _PLACE_MARKERS]
        if not marks:
            return {"poses": []}
        tf = frames.planar(marks[0].header.frame_id, None)
        return {"poses": encode.poses_payload(_pose_array([m.pose for m in marks]), tf, limit)}
    if hasattr(msg, "poses") and msg.poses and hasattr(msg.poses[0], "pose"):
        return path(msg, frames, limit)
    tf = frames.planar(msg.header.frame_id, msg.header.stamp)
    return {"poses": encode.poses_payload(_pose_array(list(msg.poses)), tf, limit)}


def footprint(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    tf = frames.planar(msg.header.frame_id, msg.header.stamp)
    pts = np.array([(p.x, p.y) for p in msg.polygon.points], dtype=np.float64).reshape(-1, 2)
    return {"points": encode.flat(encode.transform_xy(pts, tf))}


def _hex(color: Any) -> str:
    """A std_msgs/ColorRGBA (0..1) as ``#rrggbb``."""
    return "#" + "".join(f"{round(255 * min(max(v, 0.0), 1.0)):02x}" for v in (color.r, color.g, color.b))


def marker_dots(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    """A MarkerArray of SPHERE markers (MPPI's ``/trajectories``) or POINTS/SPHERE_LIST markers
    (collision_monitor's ``collision_points_marker``) as dots: one group per namespace with its first
    marker's colour, thinned evenly so that all groups together send at most ``limit`` dots.

    Why groups: MPPI's optimal trajectory and its candidates are told apart by namespace and colour,
    and each collision-monitor source has its own namespace. DELETE markers and other types are
    skipped; a marker's frame is placed with the newest transform (sphere markers carry stamp 0).
    """
    groups: dict[str, tuple[Any, list[tuple[float, float]], str]] = {}
    for marker in msg.markers:
        if marker.action != 0:
            continue
        if marker.type == _SPHERE:
            xy = [(marker.pose.position.x, marker.pose.position.y)]
        elif marker.type in _POINT_LISTS:
            xy = [(p.x, p.y) for p in marker.points]
        else:
            continue
        if marker.ns not in groups:
            groups[marker.ns] = (marker.header.frame_id, [], _hex(marker.color))
        groups[marker.ns][1].extend(xy)
    total = sum(len(points) for _frame, points, _colour in groups.values())
    share = min(1.0, limit / total) if total else 1.0
    out = []
    for ns, (frame_id, points, colour) in groups.items():
        rows = np.array(points, dtype=np.float64).reshape(-1, 2)
        rows = encode.decimate(rows, max(1, round(len(rows) * share)))
        out.append({"ns": ns, "color": colour,
                    "points": encode.flat(encode.transform_xy(rows, frames.planar(frame_id, None)))})
    return {"groups": out, "count": total}


def polygons(msgs: dict[str, Any], frames: DisplayFrames, limit: int) -> dict[str, object]:
    """The latest PolygonStamped of each collision-monitor zone topic: ``{topic: [x, y, ...]}``."""
    return {"polygons": {topic: footprint(msg, frames, limit)["points"]
                         for topic, msg in sorted(msgs.items())}}


def battery(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    known = encode.finite_or_none
    return {"percentage": known(msg.percentage), "voltage": known(msg.voltage), "charge": known(msg.charge),
            "status": int(msg.power_supply_status)}


def goal_status(msg: Any, frames: DisplayFrames, limit: int) -> dict[str, object]:
    """action_msgs/GoalStatusArray of navigate_to_pose: the newest goal's status."""
    if not msg.status_list:
        return {"status": None}
    newest = max(msg.status_list, key=lambda s: (s.goal_info.stamp.sec, s.goal_info.stamp.nanosec))
    return {"status": GOAL_STATUS.get(newest.status, str(newest.status)), "goals": len(msg.status_list)}


Converter = Callable[[Any, DisplayFrames, int], object]


@dataclass(frozen=True)
class LayerSpec:
    """A layer fed by one topic: ``types`` are ROS type names, ``digest`` skips unchanged content."""

    key: str
    topic: str
    types: tuple[str, ...]
    convert: Converter
    digest: Callable[[Any], str] | None = None


GRID = ("nav_msgs/msg/OccupancyGrid",)
#: The collision-monitor zones: PolygonStamped topics published by this node, drawn as one layer.
POLYGON_PUBLISHER, POLYGON_TYPE, POLYGON_LAYER = "collision_monitor", "geometry_msgs/msg/PolygonStamped", \
    "collision_polygons"
LAYERS: tuple[LayerSpec, ...] = (
    LayerSpec("map", "/map", GRID, grid, grid_digest),
    LayerSpec("global_costmap", "/global_costmap/costmap", GRID, grid, grid_digest),
    LayerSpec("local_costmap", "/local_costmap/costmap", GRID, grid, grid_digest),
    LayerSpec("scan", "/scan", ("sensor_msgs/msg/LaserScan",), scan),
    LayerSpec("truth", "/ground_truth", ("nav_msgs/msg/Odometry",), odometry),
    LayerSpec("amcl", "/amcl_pose", ("geometry_msgs/msg/PoseWithCovarianceStamped",), pose_with_covariance),
    LayerSpec("particles", "/particle_cloud", ("nav2_msgs/msg/ParticleCloud", "geometry_msgs/msg/PoseArray"),
              particles),
    LayerSpec("plan", "/plan", ("nav_msgs/msg/Path",), path),
    LayerSpec("local_plan", "/local_plan", ("nav_msgs/msg/Path",), path),
    LayerSpec("goal", "/goal_pose", ("geometry_msgs/msg/PoseStamped",), pose_stamped),
    LayerSpec("waypoints", "/waypoints", ("geometry_msgs/msg/PoseArray", "nav_msgs/msg/Path",
                                          "visualization_msgs/msg/MarkerArray"), waypoints),
    LayerSpec("footprint", "/local_costmap/published_footprint", ("geometry_msgs/msg/PolygonStamped",),
              footprint),
    LayerSpec("trajectories", "/trajectories", ("visualization_msgs/msg/MarkerArray",), marker_dots),
    LayerSpec("collision_points", "/collision_monitor/collision_points_marker",
              ("visualization_msgs/msg/MarkerArray",), marker_dots),
    LayerSpec("battery", "/battery_state", ("sensor_msgs/msg/BatteryState",), battery),
    LayerSpec("nav_status", "/navigate_to_pose/_action/status", ("action_msgs/msg/GoalStatusArray",),
              goal_status),
)
