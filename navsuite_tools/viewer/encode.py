"""Numbers from messages → compact JSON payloads for the page (no ROS types here, so it is testable).

Conventions shared with ``static/viewer.js``:

* Poses are ``[x, y, yaw]`` in the display frame (m, m, rad); pose lists and point lists are flat
  (``[x0, y0, yaw0, x1, ...]``, ``[x0, y0, x1, ...]``), rounded to millimetres / milliradians.
* Planar transforms are ``(x, y, yaw)`` tuples mapping points of a message's frame into the display
  frame (tf convention: display ← message frame).
* Grids keep OccupancyGrid's layout (row 0 is the bottom row, at ``origin``, +y up) and its values
  as unsigned bytes, base64-encoded: 0..100 cost/occupancy, 255 unknown (the int8 -1).
"""

from __future__ import annotations

import base64
import hashlib
import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

Planar = tuple[float, float, float]
IDENTITY: Planar = (0.0, 0.0, 0.0)
FloatArray = npt.NDArray[np.float64]


def finite_or_none(value: float) -> float | None:
    """JSON has no NaN/inf: unknown values (BatteryState uses NaN) become null."""
    return value if math.isfinite(value) else None


def transform_xy(points: FloatArray, tf: Planar) -> FloatArray:
    """Map an (N, 2) array of points by the planar transform ``tf``."""
    x, y, yaw = tf
    c, s = math.cos(yaw), math.sin(yaw)
    out = np.empty_like(points)
    out[:, 0] = c * points[:, 0] - s * points[:, 1] + x
    out[:, 1] = s * points[:, 0] + c * points[:, 1] + y
    return out


def transform_poses(poses: FloatArray, tf: Planar) -> FloatArray:
    """Map an (N, 3) array of ``x, y, yaw`` poses by the planar transform ``tf``."""
    out = np.empty_like(poses)
    out[:, :2] = transform_xy(poses[:, :2], tf)
    out[:, 2] = np.arctan2(np.sin(poses[:, 2] + tf[2]), np.cos(poses[:, 2] + tf[2]))
    return out


def decimate(rows: FloatArray, limit: int) -> FloatArray:
    """At most ``limit`` rows spread evenly, keeping the first and the last (a path's goal)."""
    if len(rows) <= limit:
        return rows
    index = np.unique(np.linspace(0, len(rows) - 1, limit).round().astype(np.int64))
    return rows[index]


def flat(rows: FloatArray, decimals: int = 3) -> list[float]:
    """Rows flattened to a rounded list of floats (JSON-ready)."""
    return [float(v) for v in np.round(rows, decimals).ravel()]


def pose_payload(pose: Sequence[float], tf: Planar = IDENTITY) -> list[float]:
    """One ``[x, y, yaw]`` pose mapped into the display frame."""
    return flat(transform_poses(np.asarray([pose], dtype=np.float64), tf))


def poses_payload(poses: FloatArray, tf: Planar, limit: int) -> list[float]:
    """A flat ``[x, y, yaw, ...]`` list of at most ``limit`` poses in the display frame."""
    if len(poses) == 0:
        return []
    return flat(transform_poses(decimate(np.asarray(poses, dtype=np.float64), limit), tf))


def scan_points(ranges: Sequence[float], angle_min: float, angle_increment: float,
                range_min: float, range_max: float, tf: Planar) -> list[float]:
    """Beam end points of a LaserScan in the display frame, as a flat ``[x, y, ...]`` list.

    Only returns inside ``[range_min, range_max]`` are kept (REP 117: +inf means no return, -inf
    means closer than range_min; NaN is an error reading), like RViz's LaserScan display.
    """
    r = np.asarray(ranges, dtype=np.float64)
    angles = angle_min + angle_increment * np.arange(len(r))
    keep = np.isfinite(r) & (r >= range_min) & (r <= range_max)
    local = np.column_stack((r[keep] * np.cos(angles[keep]), r[keep] * np.sin(angles[keep])))
    return flat(transform_xy(local, tf))


def grid_payload(width: int, height: int, resolution: float, origin: Planar, data: bytes,
                 frame: str) -> dict[str, object]:
    """An OccupancyGrid as a payload; ``data`` is the message's int8 cells as raw bytes."""
    if width < 0 or height < 0 or len(data) != width * height:
        raise ValueError(f"grid data has {len(data)} cells, expected width*height = {width}*{height}")
    return {
        "frame": frame,
        "width": width,
        "height": height,
        "resolution": resolution,
        "origin": [round(v, 6) for v in origin],
        "data": base64.b64encode(data).decode("ascii"),
    }


def grid_digest(width: int, height: int, resolution: float, origin: Planar, data: bytes) -> str:
    """A content hash of a grid: an unchanged republished map has the same digest and is not re-sent."""
    h = hashlib.blake2b(digest_size=16)
    h.update(repr((width, height, resolution, tuple(origin))).encode())
    h.update(data)
    return h.hexdigest()
