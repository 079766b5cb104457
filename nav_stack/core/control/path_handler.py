"""Global path → local path: prune what the robot has passed, cut at the local costmap edge, transform.

The controller server gets a path in the global frame (map) and controls in the local costmap
frame (odom). Each cycle it gives the robot pose in the global frame and the global frame's pose
in the local frame (``T_local_global`` from TF); everything else is here, so the node only looks
up transforms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nav_stack.core.control.base import CostGrid, InvalidPath
from nav_stack.core.geometry import FloatArray, Pose2D, cumulative_lengths, from_frame, nearest_index


@dataclass(frozen=True)
class PathHandlerParams:
    """How far along the path the robot may be searched for (m) (RPP's max_robot_pose_search_dist;
    non-positive or inf searches the whole path)."""

    max_robot_pose_search_dist: float = math.inf


class PathHandler:
    """Keeps the global plan and the index of the pose the robot has reached."""

    def __init__(self, params: PathHandlerParams | None = None) -> None:
        self.params = params or PathHandlerParams()
        self._path: FloatArray = np.zeros((0, 3))
        self._along: FloatArray = np.zeros(0)
        self._index = 0

    def set_plan(self, path: FloatArray) -> None:
        """Take a new global plan (N, 3); INVALID_PATH when it is empty or not finite."""
        path = np.asarray(path, dtype=np.float64)
        if path.ndim != 2 or path.shape[1] != 3 or len(path) == 0:
            raise InvalidPath(f"path must be a non-empty (N, 3) array of poses, got shape {path.shape}")
        if not np.all(np.isfinite(path)):
            raise InvalidPath("path holds NaN or inf")
        self._path = path
        self._along = cumulative_lengths(path)
        self._index = 0

    @property
    def plan(self) -> FloatArray:
        return self._path

    @property
    def goal(self) -> Pose2D:
        """Last pose of the global plan (global frame)."""
        x, y, yaw = self._path[-1]
        return Pose2D(float(x), float(y), float(yaw))

    def _advance(self, robot: Pose2D) -> int:
        limit = self.params.max_robot_pose_search_dist
        stop = len(self._path)
        if 0.0 < limit < math.inf:
            stop = int(np.searchsorted(self._along, self._along[self._index] + limit, side="right"))
        self._index = nearest_index(self._path, robot.x, robot.y, self._index, max(stop, self._index + 1))
        return self._index

    def distance_to_goal(self, robot: Pose2D) -> float:
        """Distance (m) from the robot to its nearest path pose plus the path length beyond it."""
        i = self._advance(robot)
        gap = math.hypot(self._path[i, 0] - robot.x, self._path[i, 1] - robot.y)
        return gap + float(self._along[-1] - self._along[i])

    def local_path(self, robot: Pose2D, local_from_global: Pose2D, grid: CostGrid) -> FloatArray:
        """Poses from the robot's nearest one up to the first that leaves the local costmap, in its frame."""
        i = self._advance(robot)
        local = from_frame(self._path[i:], local_from_global)
        mx, my = grid.spec.world_to_cell(local[:, 0], local[:, 1])
        outside = ~grid.spec.in_bounds(mx, my)
        if outside[0]:
            raise InvalidPath(
                f"the path pose nearest the robot ({local[0, 0]:.2f}, {local[0, 1]:.2f}) lies "
                f"outside the local costmap"
            )
        end = int(np.argmax(outside)) if outside.any() else len(local)
        return local[:end]
