"""Translations between ROS messages and the core's plain types (poses, paths, grids).

The core speaks (x, y, yaw) tuples, (N, 3) float arrays, numpy grids and GridSpec; nodes call these
functions at their edges so no message type leaks into an algorithm.
"""

from __future__ import annotations

import array
import math
from typing import Any

import numpy as np
from builtin_interfaces.msg import Duration as DurationMsg
from geometry_msgs.msg import Point, Pose, PoseStamped, Quaternion
from nav2_msgs.msg import Costmap
from nav_msgs.msg import OccupancyGrid, Path

from nav_stack.core.geometry import Pose2D, quaternion_from_yaw, yaw_from_quaternion
from nav_stack.core.grid import GridSpec


def yaw_to_quaternion(yaw: float) -> Quaternion:
    x, y, z, w = quaternion_from_yaw(yaw)
    return Quaternion(x=x, y=y, z=z, w=w)


def pose_to_2d(pose: Pose) -> Pose2D:
    """(x, y, yaw) of a geometry_msgs/Pose; ValueError on NaN position or a non-normalisable quaternion."""
    p, q = pose.position, pose.orientation
    if not (math.isfinite(p.x) and math.isfinite(p.y)):
        raise ValueError(f"position ({p.x}, {p.y}) is not finite")
    return Pose2D(p.x, p.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))


def pose_from_2d(x: float, y: float, yaw: float) -> Pose:
    pose = Pose()
    pose.position.x, pose.position.y = float(x), float(y)
    pose.orientation = yaw_to_quaternion(float(yaw))
    return pose


def pose_stamped(x: float, y: float, yaw: float, frame: str, stamp: object) -> PoseStamped:
    msg = PoseStamped()
    msg.header.frame_id = frame
    msg.header.stamp = stamp
    msg.pose = pose_from_2d(x, y, yaw)
    return msg


def _bare(cls: Any) -> Any:
    """An instance of a generated message class without running its ``__init__``; the caller sets
    every field slot. Why: ``__init__`` builds a default for each nested field even when one is given
    (PoseStamped() makes a Header, a Time, a Pose, a Point and a Quaternion, 15-20 us)."""
    msg = cls.__new__(cls)
    msg._check_fields = False
    return msg


def path_from_array(poses: np.ndarray, frame: str, stamp: Any) -> Path:
    """The nav_msgs/Path of (N, 3) poses (x, y in m, yaw in rad) in ``frame``, every pose stamped with
    the path's header, as Nav2's planners stamp them.

    Why not the messages' constructors: a warehouse plan has about a thousand poses (3 cm cells) and
    building each PoseStamped field by field took 14 ms per plan; this fills the generated classes'
    slots directly (tests/integration/nav_stack/test_conversions_path.py compares the result with a
    field-by-field build, in memory and on the wire). The poses share one Header object, a fresh one
    per path: a message is serialised when sent, so sharing is invisible to a subscriber, and no
    earlier message is changed.
    """
    msg = Path()
    msg.header.frame_id, msg.header.stamp = frame, stamp
    header = msg.header
    values = np.asarray(poses, dtype=np.float64)[:, :3]
    half = (values[:, 2] / 2.0).tolist()
    # math's sin and cos, as quaternion_from_yaw: numpy's vectorised ones may differ in the last bit
    zs, ws = list(map(math.sin, half)), list(map(math.cos, half))
    out = []
    for x, y, z, w in zip(values[:, 0].tolist(), values[:, 1].tolist(), zs, ws, strict=True):
        point, quaternion, pose, stamped = _bare(Point), _bare(Quaternion), _bare(Pose), _bare(PoseStamped)
        point._x, point._y, point._z = x, y, 0.0
        quaternion._x, quaternion._y, quaternion._z, quaternion._w = 0.0, 0.0, z, w
        pose._position, pose._orientation = point, quaternion
        stamped._header, stamped._pose = header, pose
        out.append(stamped)
    msg.poses = out
    return msg


def path_to_array(path: Path, invalid_yaw: float = 0.0) -> np.ndarray:
    """(N, 3) array of (x, y, yaw) from a nav_msgs/Path; a yaw whose quaternion cannot be normalised
    (NaN, inf or zero norm, see yaw_from_quaternion) becomes ``invalid_yaw``: 0 for the readers that
    follow a path, NaN for a core that refuses such poses with its own error code.

    Why not a loop over yaw_from_quaternion: each received path (the planner's result in the
    bt_navigator, the FollowPath goal in the controller) has about a thousand poses on a warehouse
    map. The slots are read in one pass and the arithmetic is vectorised with the same operations in
    the same order, so every value equals the per-pose function's (the test compares them bit for bit).
    """
    rows = []
    for stamped in path.poses:
        pose = stamped._pose
        p, q = pose._position, pose._orientation
        rows.append((p._x, p._y, q._x, q._y, q._z, q._w))
    if not rows:
        return np.zeros((0, 3))
    values = np.array(rows, dtype=np.float64)
    x, y, z, w = values[:, 2], values[:, 3], values[:, 4], values[:, 5]
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        norm = np.sqrt(x * x + y * y + z * z + w * w)
        valid = np.isfinite(values[:, 2:]).all(axis=1) & (norm >= 1e-9)
        x, y, z, w = x / norm, y / norm, z / norm, w / norm
        sine, cosine = 2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z)
    out = np.empty((len(rows), 3))
    out[:, :2] = values[:, :2]
    out[:, 2] = np.where(valid, list(map(math.atan2, sine.tolist(), cosine.tolist())), invalid_yaw)
    return out


def spec_from_info(info: object) -> GridSpec:
    """GridSpec of a nav_msgs/MapMetaData or nav2_msgs/CostmapMetaData."""
    width = getattr(info, "width", None) or getattr(info, "size_x")  # noqa: B009
    height = getattr(info, "height", None) or getattr(info, "size_y")  # noqa: B009
    origin = info.origin  # type: ignore[attr-defined]
    q = origin.orientation
    yaw = yaw_from_quaternion(q.x, q.y, q.z, q.w) if (q.x, q.y, q.z, q.w) != (0.0, 0.0, 0.0, 0.0) else 0.0
    return GridSpec(int(width), int(height), float(info.resolution),  # type: ignore[attr-defined]
                    origin.position.x, origin.position.y, yaw)


def grid_from_occupancy(msg: OccupancyGrid) -> tuple[np.ndarray, GridSpec]:
    """int8 array [row=y, col=x] (0..100, −1 unknown) and its GridSpec from an OccupancyGrid."""
    spec = spec_from_info(msg.info)
    data = np.frombuffer(msg.data, dtype=np.int8).reshape(spec.shape).copy()
    return data, spec


def occupancy_msg(data: np.ndarray, spec: GridSpec, frame: str, stamp: object) -> OccupancyGrid:
    msg = OccupancyGrid()
    msg.header.frame_id = frame
    msg.header.stamp = stamp
    msg.info.map_load_time = stamp
    msg.info.resolution = float(spec.resolution)
    msg.info.width, msg.info.height = spec.width, spec.height
    msg.info.origin = pose_from_2d(spec.origin_x, spec.origin_y, spec.origin_yaw)
    # array.array from bytes is ~40x faster than a list for a 384x384 map.
    msg.data = array.array("b", np.ascontiguousarray(data, dtype=np.int8).tobytes())
    return msg


def costmap_msg(
    costs: np.ndarray, spec: GridSpec, frame: str, stamp: object, layer: str = "master"
) -> Costmap:
    """nav2_msgs/Costmap (raw 0..255 costs) of a uint8 grid."""
    msg = Costmap()
    msg.header.frame_id = frame
    msg.header.stamp = stamp
    msg.metadata.map_load_time = stamp
    msg.metadata.update_time = stamp
    msg.metadata.layer = layer
    msg.metadata.resolution = float(spec.resolution)
    msg.metadata.size_x, msg.metadata.size_y = spec.width, spec.height
    msg.metadata.origin = pose_from_2d(spec.origin_x, spec.origin_y, spec.origin_yaw)
    msg.data = array.array("B", np.ascontiguousarray(costs, dtype=np.uint8).tobytes())
    return msg


def duration_msg(seconds: float) -> DurationMsg:
    seconds = max(0.0, float(seconds))
    whole = int(seconds)
    return DurationMsg(sec=whole, nanosec=round((seconds - whole) * 1e9) % 1_000_000_000)


def duration_to_seconds(msg: DurationMsg) -> float:
    return msg.sec + msg.nanosec * 1e-9
