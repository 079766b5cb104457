"""The smoothed path's collision check: the robot footprint placed at every pose, on the costmap.

Nav2's smoother_server asks nav2_costmap_2d's CostmapTopicCollisionChecker, pose by pose, whether the
published footprint at that pose is collision free: its cost (the highest cell under the outline) must
stay below LETHAL_OBSTACLE, and a pose off the grid is a collision. The footprints of
nav_stack.core.control.base give the same answer: a PolygonFootprint collides on lethal or unknown
cells (off-grid cells read as unknown); a CircleFootprint (the stand-in until a footprint is
published) on inscribed cells, where the disc reaches a lethal one.
"""

from __future__ import annotations

import numpy as np

from nav_stack.core.control.base import CostGrid, Footprint
from nav_stack.core.geometry import FloatArray


def first_collision(footprint: Footprint, grid: CostGrid, poses: FloatArray) -> int | None:
    """Index of the first pose of ``poses`` (N, 3), in the grid's frame, where the footprint collides;
    None when every pose is free."""
    if len(poses) == 0:
        return None
    hits = footprint.collides(footprint.cost(grid, poses[:, 0], poses[:, 1], poses[:, 2]))
    return int(np.argmax(hits)) if hits.any() else None
