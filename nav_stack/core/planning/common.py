"""What every global planner shares: the plugin protocol, start/goal checks and path assembly."""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np
import numpy.typing as npt

from nav_stack.core.geometry import FloatArray, Pose2D, headings_along
from nav_stack.core.grid import LETHAL_OBSTACLE, GridSpec
from nav_stack.core.planning.errors import PlanErrorCode, PlanningCancelled, PlanningError
from nav_stack.core.planning.grid_search import SearchGraph, open_escape

#: m: how far from the start a robot inside an inscribed band may plan through it to get out.
ESCAPE_RADIUS = 0.5

CostArray = npt.NDArray[np.uint8]


def never() -> bool:
    """The cancel checker of a plan nobody can cancel."""
    return False


class GlobalPlanner(Protocol):
    """A planner plugin: poses and the costmap in, an (N, 3) path in the costmap frame out.

    Implementations raise :class:`PlanningError` with a ComputePathToPose code on failure, and
    :class:`PlanningCancelled` once ``cancel_checker()`` is true (Nav2 Jazzy's ``cancel_checker``).
    """

    def create_plan(self, start: Pose2D, goal: Pose2D, costs: CostArray, spec: GridSpec,
                    cancel_checker: Callable[[], bool] = never) -> FloatArray: ...


def search_stopper(clock: Callable[[], float], max_planning_time: float,
                   cancel_checker: Callable[[], bool]) -> Callable[[], bool]:
    """What a search polls every few thousand expansions: raises PlanningCancelled once
    ``cancel_checker()`` is true, and answers whether ``max_planning_time`` (s on ``clock``) has
    passed since this call (the search then stops with TIMEOUT)."""
    deadline = clock() + max_planning_time

    def stop() -> bool:
        if cancel_checker():
            raise PlanningCancelled("the goal was cancelled while its plan was searched")
        return clock() > deadline

    return stop


def check_costmap(costs: CostArray, spec: GridSpec) -> None:
    """Refuse a costmap whose array does not match its spec (a wiring bug, not a planning failure)."""
    if costs.shape != spec.shape or costs.dtype != np.uint8:
        raise ValueError(f"costmap array {costs.shape} {costs.dtype} does not match spec {spec.shape} uint8")


def locate(spec: GridSpec, pose: Pose2D, what: str) -> tuple[int, int]:
    """Cell (mx, my) of the start or goal; START/GOAL_OUTSIDE_MAP when it is off the grid."""
    code = PlanErrorCode.START_OUTSIDE_MAP if what == "start" else PlanErrorCode.GOAL_OUTSIDE_MAP
    mx, my = spec.world_to_cell(pose.x, pose.y)
    if not spec.in_bounds(mx, my):
        raise PlanningError(
            code,
            f"{what} ({pose.x:.3f}, {pose.y:.3f}) is outside the "
            f"{spec.width}x{spec.height} costmap at origin "
            f"({spec.origin_x:.3f}, {spec.origin_y:.3f})",
        )
    return int(mx), int(my)


def tolerance_candidates(
    spec: GridSpec,
    goal: Pose2D,
    goal_cell: tuple[int, int],
    tolerance: float,
    passable: npt.NDArray[np.bool_],
) -> list[tuple[int, int]]:
    """Passable cells within ±tolerance (m, square window as NavFn) of the goal, nearest first."""
    reach = int(tolerance / spec.resolution)
    gx, gy = goal_cell
    x0, x1 = max(gx - reach, 0), min(gx + reach, spec.width - 1)
    y0, y1 = max(gy - reach, 0), min(gy + reach, spec.height - 1)
    ys, xs = np.nonzero(passable[y0 : y1 + 1, x0 : x1 + 1])
    xs, ys = xs + x0, ys + y0
    wx, wy = spec.cell_to_world(xs, ys)
    d2 = (wx - goal.x) ** 2 + (wy - goal.y) ** 2
    d2[(xs == gx) & (ys == gy)] = -1.0  # the goal's own cell wins ties (goal on a cell border)
    order = np.argsort(d2, kind="stable")
    return [(int(xs[i]), int(ys[i])) for i in order]


def build_path(points: FloatArray, goal_yaw: float, spacing: float) -> FloatArray:
    """(N, 3) poses through ``points`` (N, 2): segments longer than 1.5·spacing are subdivided,
    each pose faces the next one, and the last pose takes the goal's yaw."""
    if len(points) == 1:
        return np.array([[points[0, 0], points[0, 1], goal_yaw]])
    # One array operation over all segments (a grid path has thousands of one-cell segments, and a
    # loop over them took 13 ms of a 2000 x 2000 plan): segment i contributes n_i poses at
    # a_i + (k / n_i)·(b_i − a_i), k = 0 … n_i − 1, then the last point closes the path.
    a, delta = points[:-1], np.diff(points, axis=0)
    n = np.maximum(1, np.ceil(np.hypot(delta[:, 0], delta[:, 1]) / spacing - 0.5)).astype(np.int64)
    segment = np.repeat(np.arange(len(n)), n)
    k = np.arange(len(segment)) - np.repeat(np.cumsum(n) - n, n)
    t = (k / n[segment])[:, None]
    xy = np.vstack((a[segment] + t * delta[segment], points[-1:]))
    path = np.column_stack((xy, headings_along(xy)))
    path[-1, 2] = goal_yaw
    return path


def cell_centres(spec: GridSpec, cells: list[tuple[int, int]]) -> FloatArray:
    """World coordinates (N, 2) of cell centres."""
    arr = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    x, y = spec.cell_to_world(arr[:, 0], arr[:, 1])
    return np.column_stack((x, y))


def graph_from_start(
    graph: SearchGraph, costs: CostArray, spec: GridSpec, start_cell: tuple[int, int], escape_cost: float
) -> SearchGraph:
    """The graph to search from ``start_cell``: ``graph`` itself, or a copy that lets the robot escape.

    START_OCCUPIED only when the robot's cell is lethal (it is in collision). A start in the
    inscribed band or in disallowed unknown space plans out of it (see grid_search.open_escape).
    """
    if graph.passable(*start_cell):
        return graph
    cost = int(costs[start_cell[1], start_cell[0]])
    if cost == LETHAL_OBSTACLE:
        raise PlanningError(
            PlanErrorCode.START_OCCUPIED,
            f"start cell {start_cell} is lethal (cost {cost}): the robot is in collision",
        )
    radius = max(1, round(ESCAPE_RADIUS / spec.resolution))
    return open_escape(graph, costs, start_cell, radius, escape_cost)
