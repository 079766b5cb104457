"""Grid geometry and Nav2 cost values shared by maps, costmaps, planners and controllers.

A grid is a row-major numpy array indexed ``[my, mx]`` (row = y cell, column = x cell), the layout
of nav_msgs/OccupancyGrid and nav2_msgs/Costmap data: cell (0, 0) is the lower-left corner at
``origin`` and rows grow towards +y. Coordinates are in metres in the grid's frame; the origin may
carry a yaw (map_server yaml allows it), applied as a rotation about the origin point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

# Nav2 costmap_2d cost values (nav2_costmap_2d/cost_values.hpp).
FREE_SPACE = 0
MAX_NON_OBSTACLE = 252
INSCRIBED_INFLATED_OBSTACLE = 253
LETHAL_OBSTACLE = 254
NO_INFORMATION = 255

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


@dataclass(frozen=True)
class GridSpec:
    """Where a grid lies in its frame.

    Attributes:
        width: number of columns (cells along x).
        height: number of rows (cells along y).
        resolution: cell edge length in metres.
        origin_x, origin_y: frame coordinates (m) of the lower-left corner of cell (0, 0).
        origin_yaw: rotation (rad) of the grid about its origin; 0 for almost every map.
    """

    width: int
    height: int
    resolution: float
    origin_x: float = 0.0
    origin_y: float = 0.0
    origin_yaw: float = 0.0

    def __post_init__(self) -> None:
        if self.width <= 0 or self.height <= 0:
            raise ValueError(f"grid size must be positive, got {self.width} x {self.height}")
        if not (self.resolution > 0.0 and math.isfinite(self.resolution)):
            raise ValueError(f"grid resolution must be a positive number of metres, got {self.resolution}")

    @property
    def shape(self) -> tuple[int, int]:
        """numpy shape ``(height, width)`` of an array holding this grid."""
        return (self.height, self.width)

    @property
    def size_m(self) -> tuple[float, float]:
        """Extent ``(x, y)`` in metres."""
        return (self.width * self.resolution, self.height * self.resolution)

    def world_to_cell(self, x: FloatArray | float, y: FloatArray | float) -> tuple[IntArray, IntArray]:
        """Cell indices ``(mx, my)`` containing the frame points; may lie outside the grid."""
        dx = np.asarray(x, dtype=np.float64) - self.origin_x
        dy = np.asarray(y, dtype=np.float64) - self.origin_y
        if self.origin_yaw != 0.0:
            c, s = math.cos(self.origin_yaw), math.sin(self.origin_yaw)
            dx, dy = c * dx + s * dy, -s * dx + c * dy
        mx = np.floor(dx / self.resolution).astype(np.int64)
        my = np.floor(dy / self.resolution).astype(np.int64)
        return mx, my

    def cell_to_world(self, mx: IntArray | int, my: IntArray | int) -> tuple[FloatArray, FloatArray]:
        """Frame coordinates (m) of the centres of cells ``(mx, my)``."""
        gx = (np.asarray(mx, dtype=np.float64) + 0.5) * self.resolution
        gy = (np.asarray(my, dtype=np.float64) + 0.5) * self.resolution
        if self.origin_yaw != 0.0:
            c, s = math.cos(self.origin_yaw), math.sin(self.origin_yaw)
            gx, gy = c * gx - s * gy, s * gx + c * gy
        return gx + self.origin_x, gy + self.origin_y

    def in_bounds(self, mx: IntArray | int, my: IntArray | int) -> npt.NDArray[np.bool_]:
        """True where ``(mx, my)`` is a cell of this grid."""
        mx_a, my_a = np.asarray(mx), np.asarray(my)
        return (mx_a >= 0) & (mx_a < self.width) & (my_a >= 0) & (my_a < self.height)

    def contains_point(self, x: float, y: float) -> bool:
        """True when the frame point lies on the grid."""
        mx, my = self.world_to_cell(x, y)
        return bool(self.in_bounds(mx, my))


def occupancy_from_cost(costs: npt.NDArray[np.uint8]) -> npt.NDArray[np.int8]:
    """Translate Nav2 costs (0..255) to OccupancyGrid values (0..100, -1 unknown) as Nav2 publishes them.

    0 → 0, 253 → 99, 254 → 100, 255 → -1, and 1..252 → 1 + 97·(c − 1)/251 (integer division).
    """
    c = costs.astype(np.int32)
    out = 1 + (97 * (c - 1)) // 251
    out = np.where(c == FREE_SPACE, 0, out)
    out = np.where(c == INSCRIBED_INFLATED_OBSTACLE, 99, out)
    out = np.where(c == LETHAL_OBSTACLE, 100, out)
    out = np.where(c == NO_INFORMATION, -1, out)
    return out.astype(np.int8)
