"""What one MPPI cycle works on: the scene (robot, path, goal, costmap, footprint) and the rollouts.

Both the numpy reference and the compiled kernels read these; nothing here depends on the samples'
number. Poses and paths are in the local costmap's frame (odom), as the controller server gives them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nav_stack.core.control.base import CircleFootprint, CostGrid, Footprint, PolygonFootprint, Twist2D
from nav_stack.core.costmap.inflation_layer import inflation_cost
from nav_stack.core.geometry import FloatArray, Pose2D

#: a (0, 2) outline: the footprint is the centre point (a round robot)
NO_OUTLINE = np.zeros((0, 2))


@dataclass(frozen=True)
class FootprintModel:
    """The footprint as the critics use it (Nav2's FootprintCollisionChecker and inflation facts).

    ``outline``: points (K, 2) in the robot frame whose maximum cost is the footprint's cost; empty
    for a round robot, whose cost is its centre cell's. ``circumscribed_cost``: the inflation cost at
    the circumscribed radius: below it no orientation can touch an obstacle, so the (dearer) footprint
    check is skipped (Nav2's possible_collision_cost; < 1 = unknown, always check).
    ``inscribed_radius`` (m): the costmap's, which the ObstaclesCritic needs to turn costs into
    distances.
    """

    outline: FloatArray = field(default_factory=lambda: NO_OUTLINE.copy())
    circumscribed_cost: float = -1.0
    inscribed_radius: float = 0.22

    @classmethod
    def of(cls, footprint: Footprint, inscribed_radius: float,
           inflation: tuple[float, float] | None) -> FootprintModel:
        """From the controller server's footprint. A polygon's outline samples; a circle's body
        outline when it has one (the robot's real shape), else its centre. ``inflation``:
        (inflation_radius m, cost_scaling_factor) of the local costmap, None without an inflation layer.
        """
        polygon = footprint.body if isinstance(footprint, CircleFootprint) else footprint
        outline = polygon.outline() if isinstance(polygon, PolygonFootprint) else NO_OUTLINE
        circumscribed = float(np.hypot(outline[:, 0], outline[:, 1]).max()) if len(outline) else (
            footprint.radius if isinstance(footprint, CircleFootprint) else inscribed_radius)
        cost = -1.0
        if inflation is not None and inflation[1] > 0.0:
            cost = float(inflation_cost(circumscribed, inscribed_radius, inflation[1]))
        return cls(np.ascontiguousarray(outline, dtype=np.float64), cost, inscribed_radius)


@dataclass(frozen=True)
class Scene:
    """One cycle's inputs apart from the samples.

    ``path``: the pruned local path (N, 3) the critics follow; ``goal``: (x, y, yaw) of the goal the
    goal critics aim at; ``speed``: (vx, vy, wz) measured (vy = 0 from the controller server).
    """

    robot: Pose2D
    speed: tuple[float, float, float]
    path: FloatArray
    goal: FloatArray
    grid: CostGrid
    footprint: FootprintModel

    @classmethod
    def make(cls, robot: Pose2D, velocity: Twist2D, path: FloatArray, goal: FloatArray, grid: CostGrid,
             footprint: FootprintModel) -> Scene:
        return cls(robot, (float(velocity.vx), 0.0, float(velocity.wz)),
                   np.ascontiguousarray(path[:, :3], dtype=np.float64),
                   np.asarray(goal[:3], dtype=np.float64), grid, footprint)

    def goal_within(self, distance: float) -> bool:
        """Nav2's withinPositionGoalTolerance: the robot is closer than ``distance`` (m) to the goal."""
        dx, dy = self.robot.x - float(self.goal[0]), self.robot.y - float(self.goal[1])
        return dx * dx + dy * dy < distance * distance

    def grid_meta(self) -> FloatArray:
        """(origin_x, origin_y, resolution, cos origin_yaw, sin origin_yaw): how the kernels map points."""
        spec = self.grid.spec
        return np.array([spec.origin_x, spec.origin_y, spec.resolution,
                         math.cos(spec.origin_yaw), math.sin(spec.origin_yaw)])


@dataclass
class Rollouts:
    """The sampled batch (B, T): bounded controls c*, the velocities the model turns them into, poses.

    ``vx[:, 0]`` is the measured speed; ``vx[:, j]`` = ``cvx[:, j-1]`` bounded by the acceleration
    limits (Nav2 bounds the controls in place, so the weighted mean of ``cvx`` is feasible).
    ``x, y, yaw[:, j]``: the pose after j + 1 steps of model_dt.
    """

    cvx: FloatArray
    cvy: FloatArray
    cwz: FloatArray
    vx: FloatArray
    vy: FloatArray
    wz: FloatArray
    x: FloatArray
    y: FloatArray
    yaw: FloatArray

    @classmethod
    def empty(cls, batch: int, steps: int) -> Rollouts:
        return cls(*(np.zeros((batch, steps)) for _ in range(9)))
