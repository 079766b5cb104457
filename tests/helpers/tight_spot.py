"""A waffle beside a pillar, with contact: a costmap drawn the way the lidar draws it, and a
kinematic step that refuses any motion which would push the robot's box into the round pillar; and
turtlebot3_world's static costmap, where the seed's tight spots are.

Why a helper: the controller's collision checks see the pillar as 5 cm cells, while the simulator
collides the exact shapes. The tight spots where the two disagree (the battery patrol's location3)
need both views at once, without ROS, to reproduce in a unit test. The contact model is the
simplest that jams: a blocked step does not happen at all, and odometry then measures no motion.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np

from nav_stack.core.control import CostGrid, Twist2D
from nav_stack.core.costmap import CostmapParams, InflationLayer, LayeredCostmap, StaticLayer
from nav_stack.core.costmap.params import InflationLayerParams
from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec
from nav_stack.core.map_io import load_map

REPO = Path(__file__).resolve().parents[2]

#: turtlebot3_world's pillar beside location3: centre (m) and radius (m)
PILLAR, PILLAR_RADIUS = (-1.1, -1.1), 0.15
#: sim2d's waffle collision box in base_footprint (m)
WAFFLE_BOX = ((-0.197, -0.133), (0.069, -0.133), (0.069, 0.133), (-0.197, 0.133))


def lidar_costmap(origin_shift: tuple[float, float] = (0.0, 0.0)) -> CostGrid:
    """A 3 × 3 m local costmap round location3 (0.05 m cells, the TB3 inflation): the pillar's
    outline marked cell by cell, as scan hits mark it. ``origin_shift`` (m) moves the cell borders
    against the pillar, which changes how much larger than the pillar the cells draw it."""
    spec = GridSpec(60, 60, 0.05, -2.9 + origin_shift[0], -2.6 + origin_shift[1])
    occupancy = np.zeros(spec.shape, dtype=np.int8)
    angles = np.linspace(0.0, 2.0 * math.pi, 720)
    mx, my = spec.world_to_cell(PILLAR[0] + PILLAR_RADIUS * np.cos(angles),
                                PILLAR[1] + PILLAR_RADIUS * np.sin(angles))
    occupancy[my, mx] = 100
    params = CostmapParams(robot_radius=0.22)
    inflation = InflationLayer(InflationLayerParams(inflation_radius=0.7, cost_scaling_factor=3.0))
    costmap = LayeredCostmap(params, [StaticLayer(params), inflation])
    costmap.set_map(occupancy, spec)
    costmap.update(Pose2D(0.0, 0.0, 0.0))
    return CostGrid(costmap.costs, costmap.spec)


def box_clearance(pose: Pose2D) -> float:
    """Distance (m) from the waffle's box at ``pose`` to the pillar; negative once they overlap."""
    c, s = math.cos(pose.yaw), math.sin(pose.yaw)
    corners = np.array([(pose.x + c * x - s * y, pose.y + s * x + c * y) for x, y in WAFFLE_BOX])
    centre = np.array(PILLAR)
    nearest = math.inf
    for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True):
        t = float(np.clip(np.dot(centre - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0))
        nearest = min(nearest, float(np.linalg.norm(a + t * (b - a) - centre)))
    return nearest - PILLAR_RADIUS


def step_with_contact(pose: Pose2D, cmd: Twist2D, dt: float) -> tuple[Pose2D, Twist2D]:
    """The pose after ``dt`` s of ``cmd`` (unicycle), and the velocity odometry measures: the
    command, or no motion at all when the box would enter the pillar."""
    yaw = pose.yaw + cmd.wz * dt / 2
    moved = Pose2D(pose.x + cmd.vx * math.cos(yaw) * dt, pose.y + cmd.vx * math.sin(yaw) * dt,
                   pose.yaw + cmd.wz * dt)
    if box_clearance(moved) < 0.0:
        return pose, Twist2D(0.0, 0.0)
    return moved, cmd


@functools.cache
def tb3_world_grid() -> CostGrid:
    """turtlebot3_world's static global costmap (static + inflation layers, the yaml's values)."""
    occupancy = load_map(REPO / "maps" / "turtlebot3_world.yaml")
    params = CostmapParams(robot_radius=0.22)
    costmap = LayeredCostmap(params, [StaticLayer(params), InflationLayer()])
    costmap.set_map(occupancy.data, occupancy.spec)
    costmap.update(Pose2D(0.0, 0.0, 0.0))
    return CostGrid(costmap.costs, costmap.spec)
