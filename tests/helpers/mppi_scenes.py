"""Small synthetic local costmaps and paths for the MPPI unit tests (no ROS).

A 3 m × 3 m rolling window at 0.05 m (the TB3 local costmap) around a point, lethal boxes inflated
as Nav2's inflation layer does (robot radius 0.22 m, inflation radius 0.7 m, scaling 3.0), straight
or turning paths with headings, and a kinematic stepper that moves the robot by a command.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np

from nav_stack.core.control import CostGrid, Twist2D
from nav_stack.core.costmap.inflation_layer import inflation_cost
from nav_stack.core.geometry import Pose2D, headings_along
from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec

INSCRIBED_RADIUS = 0.22
INFLATION = (0.7, 3.0)  # inflation_radius m, cost_scaling_factor


def window(cx: float = 0.0, cy: float = 0.0, size: float = 3.0, resolution: float = 0.05) -> GridSpec:
    """The rolling window of ``size`` m centred on (cx, cy)."""
    cells = round(size / resolution)
    return GridSpec(cells, cells, resolution, cx - size / 2, cy - size / 2)


def costmap(spec: GridSpec, boxes: Sequence[tuple[float, float, float, float]] = ()) -> CostGrid:
    """Lethal axis-aligned boxes (x0, y0, x1, y1 in m) inflated like Nav2's inflation layer: the
    distance of each cell's centre to the nearest lethal cell centre sets its cost."""
    my, mx = np.mgrid[0 : spec.height, 0 : spec.width]
    wx, wy = spec.cell_to_world(mx, my)
    d = np.full(spec.shape, np.inf)
    for x0, y0, x1, y1 in boxes:
        inside = (wx >= x0) & (wx <= x1) & (wy >= y0) & (wy <= y1)
        if not inside.any():  # off this window: the box's cells are the window's extension
            cols = np.arange(math.ceil((x0 - spec.origin_x) / spec.resolution - 0.5),
                             math.floor((x1 - spec.origin_x) / spec.resolution - 0.5) + 1)
            rows = np.arange(math.ceil((y0 - spec.origin_y) / spec.resolution - 0.5),
                             math.floor((y1 - spec.origin_y) / spec.resolution - 0.5) + 1)
            if not len(cols) or not len(rows):
                continue
            cx, cy = spec.cell_to_world(cols, rows)
        else:
            cx, cy = wx[inside], wy[inside]
        nx = np.clip(wx, cx.min(), cx.max())
        ny = np.clip(wy, cy.min(), cy.max())
        nx = cx.min() + np.round((nx - cx.min()) / spec.resolution) * spec.resolution
        ny = cy.min() + np.round((ny - cy.min()) / spec.resolution) * spec.resolution
        d = np.minimum(d, np.hypot(wx - nx, wy - ny))
    costs = inflation_cost(np.where(np.isfinite(d), d, 99.0), INSCRIBED_RADIUS, INFLATION[1])
    costs[d > INFLATION[0]] = 0
    costs[d < 1e-9] = LETHAL_OBSTACLE
    return CostGrid(costs.astype(np.uint8), spec)


def straight_path(start: tuple[float, float], yaw: float, length: float, step: float = 0.05) -> np.ndarray:
    """Poses every ``step`` m along a line from ``start`` heading ``yaw``."""
    s = np.arange(0.0, length + 1e-9, step)
    xy = np.column_stack([start[0] + s * math.cos(yaw), start[1] + s * math.sin(yaw)])
    return np.column_stack([xy, np.full(len(s), yaw)])


def polyline(points: list[tuple[float, float]], step: float = 0.05) -> np.ndarray:
    """Poses every ``step`` m along the polyline, headings along it."""
    out = [np.asarray(points[0], dtype=float)]
    for start, end in itertools.pairwise(points):
        a, b = np.asarray(start, float), np.asarray(end, float)
        n = max(1, round(float(np.hypot(*(b - a))) / step))
        out.extend(a + (b - a) * k / n for k in range(1, n + 1))
    xy = np.array(out)
    return np.column_stack([xy, headings_along(xy)])


def in_window(path: np.ndarray, grid: CostGrid) -> np.ndarray:
    """The path from its first pose up to the first one off the grid (the controller server's cut)."""
    mx, my = grid.spec.world_to_cell(path[:, 0], path[:, 1])
    outside = ~grid.spec.in_bounds(mx, my)
    return path[: int(np.argmax(outside))] if outside.any() else path


def nearest_on(path: np.ndarray, robot: Pose2D) -> np.ndarray:
    """The path from the pose nearest the robot on."""
    return path[int(np.argmin(np.hypot(path[:, 0] - robot.x, path[:, 1] - robot.y))):]


def step(robot: Pose2D, cmd: Twist2D, dt: float = 0.05, vy: float = 0.0) -> Pose2D:
    """The pose after ``dt`` s of ``cmd`` (unicycle, plus a lateral speed for omni robots)."""
    yaw = robot.yaw
    x = robot.x + (cmd.vx * math.cos(yaw) - vy * math.sin(yaw)) * dt
    y = robot.y + (cmd.vx * math.sin(yaw) + vy * math.cos(yaw)) * dt
    return Pose2D(x, y, yaw + cmd.wz * dt)
