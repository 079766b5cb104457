"""Default spawn poses for ``nav-bringup --robots N``: the world's own spawns, then free space nearby.

Why: a fleet launched by a count has no poses from the user, and robots placed by a formula would
land in walls or on each other. A world file lists hand-picked spawns (turtlebot3_world: the Nav2
launch spawn, the pillar grid, ...); they come first, in order, skipping any that stands within
``separation`` of one already taken. When a world has fewer spawns than robots, the next robot
stands on the free map cell nearest to the first robot's spawn that keeps ``clearance`` from every
occupied or unknown cell and ``separation`` from every robot placed, facing the way the first robot
does: a line of robots along the free space around the start, which is where a user would put them.

Pure: numpy and the map core.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.distance import squared_distance_cells
from nav_stack.core.fleet_spec import FleetSpecError
from nav_stack.core.map_io import OccupancyMap

Pose = tuple[float, float, float]  # x m, y m, yaw rad (map frame)
#: m from a spawn to the nearest occupied or unknown cell: above the largest robot's circumradius
#: (sim2d's waffle, 0.24 m) with room left for the robot to turn on the spot.
SPAWN_CLEARANCE = 0.45
#: m between two robots' spawns: two footprints (0.44 m) and the gap a planner needs between them.
ROBOT_SEPARATION = 1.0


def free_positions(occupancy: OccupancyMap, clearance: float) -> npt.NDArray[np.float64]:
    """(M, 2) map positions (m) of the free cells at least ``clearance`` m from any non-free cell."""
    spec = occupancy.spec
    blocked = occupancy.data != 0
    reach = math.ceil(clearance / spec.resolution)
    squared = squared_distance_cells(blocked, reach)
    keep = (~blocked) & (squared * spec.resolution ** 2 >= clearance ** 2)
    rows, cols = np.nonzero(keep)
    xs, ys = spec.cell_to_world(cols, rows)
    return np.column_stack((xs, ys)).astype(np.float64)


def _far_from(point: tuple[float, float], taken: Sequence[Pose], separation: float) -> bool:
    return all(math.hypot(point[0] - x, point[1] - y) >= separation for x, y, _ in taken)


def spread_spawns(count: int, preferred: Sequence[Pose], free: npt.NDArray[np.float64] | None,
                  separation: float = ROBOT_SEPARATION) -> list[Pose]:
    """``count`` spawn poses: ``preferred`` ones first, then the nearest ``free`` positions.

    Args:
        count: how many robots (at least 1).
        preferred: the world's spawns, in order (the first is the default one-robot spawn).
        free: candidate positions (M, 2) with enough clearance (:func:`free_positions`); None when
            the world has no map, so only ``preferred`` poses can be used.
        separation: m between any two spawns.

    Raises:
        FleetSpecError: when fewer than ``count`` poses fit, naming how many did.
    """
    if count < 1:
        raise FleetSpecError(f"a fleet needs at least one robot, got {count}")
    taken: list[Pose] = []
    for pose in preferred:
        if len(taken) == count:
            break
        if _far_from((pose[0], pose[1]), taken, separation):
            taken.append(pose)
    if len(taken) < count and free is not None and len(free):
        origin = taken[0] if taken else (float(free[0, 0]), float(free[0, 1]), 0.0)
        order = np.argsort(np.hypot(free[:, 0] - origin[0], free[:, 1] - origin[1]), kind="stable")
        for index in order:
            x, y = float(free[index, 0]), float(free[index, 1])
            if _far_from((x, y), taken, separation):
                taken.append((x, y, origin[2]))
                if len(taken) == count:
                    break
    if len(taken) < count:
        raise FleetSpecError(f"only {len(taken)} spawn pose(s) {separation:g} m apart fit in this world for "
                             f"{count} robots; give the poses in a fleet file (--fleet)")
    return taken
