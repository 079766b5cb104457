"""The part of the path MPPI's critics see (Nav2's mppi PathHandler after the controller server's pruning).

The controller server hands over the path from the pose nearest the robot to the costmap's edge,
in the costmap frame. MPPI keeps ``prune_distance`` of it (Nav2's first_after_integrated_distance)
and, with ``enforce_path_inversion``, only the part up to the first cusp where the path reverses
(a Smac plan's direction change) until the robot stands at that cusp within
``inversion_xy_tolerance`` and ``inversion_yaw_tolerance``; then the rest, up to the next cusp.
"""

from __future__ import annotations

import math

import numpy as np

from nav_stack.core.control.mppi.params import MPPIParams
from nav_stack.core.geometry import FloatArray, Pose2D, angle_diff, cumulative_lengths

#: m: a path pose this close to a cusp already passed is that cusp
SAME_POSE = 1e-6


def prune(path: FloatArray, distance: float) -> FloatArray:
    """The poses up to, not including, the first one more than ``distance`` (m) along the path."""
    beyond = np.nonzero(cumulative_lengths(path) > distance)[0]
    return path[: beyond[0]] if len(beyond) else path


def first_inversion(path: FloatArray) -> int:
    """How many poses lead up to and include the first cusp (the pose where the direction of travel
    turns by more than 90°); ``len(path)`` without one (Nav2's findFirstPathInversion)."""
    if len(path) < 3:
        return len(path)
    d = np.diff(path[:, :2], axis=0)
    turns = np.nonzero((d[:-1] * d[1:]).sum(axis=1) < 0.0)[0]
    return int(turns[0]) + 2 if len(turns) else len(path)


class LocalPath:
    """Cuts each cycle's path for the critics, remembering the cusps the robot has reached."""

    def __init__(self) -> None:
        self._passed: list[tuple[float, float]] = []

    def reset(self) -> None:
        self._passed.clear()

    def cut(self, path: FloatArray, robot: Pose2D, p: MPPIParams) -> tuple[FloatArray, FloatArray]:
        """(the path the critics see this cycle, the goal the goal critics aim at): the server's
        path end, or the next cusp with ``enforce_path_inversion`` (later Nav2's getCriticGoal)."""
        if p.enforce_path_inversion:
            path = self._up_to_inversion(path, robot, p)
        return prune(path, p.prune_distance), path[-1]

    def _up_to_inversion(self, path: FloatArray, robot: Pose2D, p: MPPIParams) -> FloatArray:
        while True:
            end = first_inversion(path)
            if end == len(path):
                return path
            cusp = path[end - 1]
            passed = any(math.dist(c, cusp[:2]) < SAME_POSE for c in self._passed)
            reached = (math.hypot(robot.x - cusp[0], robot.y - cusp[1]) <= p.inversion_xy_tolerance
                       and abs(angle_diff(robot.yaw, float(cusp[2]))) <= p.inversion_yaw_tolerance)
            if not (passed or reached):
                return path[:end]
            if reached and not passed:
                self._passed.append((float(cusp[0]), float(cusp[1])))
            path = path[end:]
