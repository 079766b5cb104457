"""Where the robot can stand and how far it has to drive there, on an occupancy grid.

Why a path distance: the nearest frontier as the crow flies may lie behind a wall; exploration
ranks frontiers by the length (m) of the shortest 8-connected path through cells with enough
clearance for the robot. The search itself is the planners' Dijkstra (planning.grid_search, in its
compiled form) run to exhaustion with unit cell costs, so there is one grid search in the code base.
"""

from __future__ import annotations

import math

import numpy as np

from nav_stack.core.costmap.distance import squared_distance_cells
from nav_stack.core.exploration.frontiers import BoolArray, Occupancy, free_mask
from nav_stack.core.grid import FloatArray, GridSpec
from nav_stack.core.planning.grid_search import SearchGraph
from nav_stack.core.planning.grid_search_jit import search

# path_distances searches a two-code grid: a traversable cell costs one step, a wall is impassable.
_STEP, _WALL = 0, 1
_STEP_TABLE = [1.0] + [math.inf] * 255


def clear_of(mask: BoolArray, spec: GridSpec, radius: float) -> BoolArray:
    """Cells whose clearance (m, centre to the nearest ``mask`` cell's edge) is ``radius`` or more."""
    reach = math.ceil(radius / spec.resolution) + 1
    d2 = squared_distance_cells(mask, reach)
    clearance = np.sqrt(d2.astype(np.float64)) * spec.resolution - 0.5 * spec.resolution
    return np.asarray(clearance >= radius, dtype=np.bool_)


def traversable_mask(
    occupancy: Occupancy, spec: GridSpec, robot_radius: float, occupied_threshold: int
) -> BoolArray:
    """Free cells with a clearance (m, centre to nearest occupied cell edge) of ``robot_radius`` or more."""
    occupied = occupancy >= occupied_threshold
    return free_mask(occupancy, occupied_threshold) & clear_of(occupied, spec, robot_radius)


def path_distances(traversable: BoolArray, spec: GridSpec, start: tuple[int, int]) -> FloatArray:
    """Shortest 8-connected path length (m) from cell ``start`` = (mx, my) to each traversable cell, else inf.

    The start cell is always usable, so a robot standing too close to a wall can still leave it.
    """
    mx, my = start
    if not bool(spec.in_bounds(mx, my)):
        raise ValueError(f"start cell ({mx}, {my}) lies outside the {spec.width} x {spec.height} grid")
    codes = np.where(traversable, _STEP, _WALL).astype(np.uint8)
    codes[my, mx] = _STEP
    graph = SearchGraph.build(codes, _STEP_TABLE)
    result = search(
        graph,
        graph.index(mx, my),
        -1,
        use_astar=False,
        max_iterations=codes.size + 1,
        deadline_passed=lambda: False,
    )
    inner = result.g.reshape(spec.height + 2, spec.width + 2)[1:-1, 1:-1]  # drop the padding border
    return inner * spec.resolution
