"""The "GridBased" planner: NavFn's cost model searched with 8-connected A* or Dijkstra.

NavFn propagates a potential wavefront from the goal and descends its gradient from the robot.
We keep NavFn's observable behaviour (cost translation 50 + 0.8·c, impassable ≥ 253, unknown
charged 253 when ``allow_unknown``, ``use_astar`` switch, ±``tolerance`` square searched for the
reachable cell nearest the goal) but search the 8-connected cell graph with a binary heap from
the start, so the path is the exact cost-optimal cell sequence rather than a gradient trace.

One choice beyond NavFn: among the reachable candidates within ``EQUALLY_NEAR`` of the nearest one,
the plan ends at the one cheapest to reach. A goal inside a round pillar has a ring of candidates at
nearly the same distance, and which of them is nearest follows the lidar marks of the last scan:
NavFn's rule made the 1 Hz replans jump from one side of the pillar to the other while the robot
drove between them (seen: upstream's waypoint (0, 0) took 41 to 130 s of sim time and sometimes
failed). The cheapest candidate is the one the robot is already heading for, so the choice holds.
``max_planning_time`` and ``max_iterations`` are our additions (Smac's knobs) so a plan on a huge
map ends with TIMEOUT instead of blocking the planner server.

A replan to the same goal from a cell of the last plan keeps the rest of that plan without a search
when no change of the costmap could make another path cheaper (replan.py says when and why: the
answer costs what a search's would; on bench_planning's 1.67 M-cell warehouse a kept replan takes
1.3 ms of CPU against 50 to 90 ms for the search).
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.grid import GridSpec
from nav_stack.core.planning.common import (
    CostArray,
    build_path,
    cell_centres,
    check_costmap,
    graph_from_start,
    locate,
    never,
    search_stopper,
    tolerance_candidates,
)
from nav_stack.core.planning.errors import PlanErrorCode, PlanningError
from nav_stack.core.planning.grid_search import (
    COST_FACTOR,
    NEUTRAL_COST,
    SearchGraph,
    SearchResult,
    SearchTimeoutError,
    navfn_cost_table,
)
from nav_stack.core.planning.grid_search_jit import SearchArrays, warm_up
from nav_stack.core.planning.grid_search_jit import search as compiled_search
from nav_stack.core.planning.replan import ReplanMemory

Search = Callable[[SearchGraph, int, int, bool, int, Callable[[], bool]], SearchResult]

#: NavFn's traversal cost of an inscribed cell, charged only while escaping an inscribed band.
ESCAPE_COST = NEUTRAL_COST + COST_FACTOR * 253
#: m: tolerance candidates this much farther from the goal than the nearest reachable one count as
#: equally near; the plan ends at the cheapest of them (two cells of the default 5 cm costmap).
EQUALLY_NEAR = 0.1


@dataclass(frozen=True)
class NavfnParams:
    """NavFn knobs (names and code defaults of nav2_navfn_planner) plus our time/iteration caps."""

    tolerance: float = 0.5  # m, half-side of the square searched around a blocked/unreachable goal
    use_astar: bool = False
    allow_unknown: bool = True
    max_planning_time: float = 2.0  # s
    max_iterations: int = 1_000_000  # node expansions

    def __post_init__(self) -> None:
        if not (self.tolerance >= 0.0 and math.isfinite(self.tolerance)):
            raise ValueError(f"NavfnParams.tolerance must be >= 0 m, got {self.tolerance}")
        if not self.max_planning_time > 0.0:
            raise ValueError(f"NavfnParams.max_planning_time must be > 0 s, got {self.max_planning_time}")
        if self.max_iterations <= 0:
            raise ValueError(f"NavfnParams.max_iterations must be > 0, got {self.max_iterations}")


class NavfnPlanner:
    """Cost-optimal 8-connected grid planner with NavFn's cost model and goal tolerance.

    The prepared search graph is cached and reused while the costmap content is unchanged
    (a costmap updates at ~1 Hz while plans may be requested more often).
    """

    def __init__(
        self, params: NavfnParams | None = None, clock: Callable[[], float] = time.monotonic,
        search: Search = compiled_search,
    ) -> None:
        """``search``: the compiled grid search, or the pure-Python reference (grid_search.search,
        which gives the same plans: the benchmark compares them)."""
        self.params = params or NavfnParams()
        self._clock = clock
        self._search = search
        if search is compiled_search:
            warm_up()  # compile now, not inside the first plan's max_planning_time
            # one set of search arrays for all plans (grid_search_jit.SearchArrays: why)
            self._search = functools.partial(compiled_search, arrays=SearchArrays())
        self._cached_costs: CostArray | None = None
        self._graph: SearchGraph | None = None
        self.memory = ReplanMemory(navfn_cost_table(self.params.allow_unknown))

    def _prepare(self, costs: CostArray) -> SearchGraph:
        if self._graph is None or self._cached_costs is None or not np.array_equal(costs, self._cached_costs):
            self._graph = SearchGraph.build(costs, navfn_cost_table(self.params.allow_unknown))
            self._cached_costs = costs.copy()
        return self._graph

    def create_plan(self, start: Pose2D, goal: Pose2D, costs: CostArray, spec: GridSpec,
                    cancel_checker: Callable[[], bool] = never) -> FloatArray:
        check_costmap(costs, spec)
        start_cell = locate(spec, start, "start")
        goal_cell = locate(spec, goal, "goal")
        rest = self.memory.rest_of_plan(start_cell, goal, spec, costs)
        if rest is not None:
            return _poses(spec, [tuple(c) for c in rest.tolist()], start, goal, goal_cell)
        prepared = self._prepare(costs)
        graph = graph_from_start(prepared, costs, spec, start_cell, ESCAPE_COST)
        if self.params.tolerance > 0.0:
            passable = (
                np.frombuffer(graph.blocked, dtype=np.uint8).reshape(graph.height + 2, graph.width + 2)[
                    1:-1, 1:-1
                ]
                == 0
            )
            candidates = tolerance_candidates(spec, goal, goal_cell, self.params.tolerance, passable)
        else:
            candidates = [goal_cell] if graph.passable(*goal_cell) else []
        if not candidates:
            raise PlanningError(
                PlanErrorCode.GOAL_OCCUPIED,
                f"goal cell {goal_cell} has cost {costs[goal_cell[1], goal_cell[0]]} and no "
                f"free cell lies within tolerance {self.params.tolerance} m",
            )
        near = equally_near(spec, goal, goal_cell, candidates)
        stop = search_stopper(self._clock, self.params.max_planning_time, cancel_checker)
        try:
            result = self._search(
                graph,
                graph.index(*start_cell),
                graph.index(*_search_target(spec, start, near)),
                self.params.use_astar,
                self.params.max_iterations,
                stop,
            )
        except SearchTimeoutError as exc:
            raise PlanningError(PlanErrorCode.TIMEOUT, str(exc)) from exc
        target = self._end_cell(result, graph, near, candidates)
        if target is None:
            raise PlanningError(
                PlanErrorCode.NO_VALID_PATH,
                f"no path from {start_cell} to {goal_cell} (tolerance {self.params.tolerance} m)",
            )
        cells = result.cells_to(graph, target)
        if graph is prepared and graph.cell(target) == goal_cell:  # no escape, no tolerance choice
            along = np.asarray(cells, dtype=np.int64)
            self.memory.remember(goal, spec, costs, along,
                                 result.g[(along[:, 1] + 1) * graph.stride + along[:, 0] + 1])
        else:
            self.memory.forget()
        return _poses(spec, cells, start, goal, goal_cell)

    @staticmethod
    def _end_cell(result: SearchResult, graph: SearchGraph, near: list[tuple[int, int]],
                  candidates: list[tuple[int, int]]) -> int | None:
        """Where the plan ends (flat index): of the ``near`` candidates (the goal cell alone when it is
        passable) the cheapest the search reached; when it reached none of them, the reached candidate
        nearest the goal (NavFn's rule); None when it reached no candidate at all.

        Dijkstra has expanded every cell cheaper than the search's target, so its choice is exact; A*
        (``use_astar``) chooses among the cells it expanded on its way to the target, which
        ``_search_target`` put on the robot's side."""
        def was_reached(cell: tuple[int, int]) -> bool:
            index = graph.index(*cell)
            return index == result.reached or result.was_expanded(index)

        reached_near = [graph.index(*c) for c in near if was_reached(c)]
        if reached_near:
            return min(reached_near, key=lambda index: float(result.g[index]))
        return next((graph.index(*c) for c in candidates if was_reached(c)), None)


def _poses(spec: GridSpec, cells: list[tuple[int, int]], start: Pose2D, goal: Pose2D,
           goal_cell: tuple[int, int]) -> FloatArray:
    """The (N, 3) path through the centres of ``cells``, from the start's own position and ending at
    the goal's own position when the last cell is the goal's."""
    points = cell_centres(spec, cells)
    if len(points) == 1:
        points = np.vstack((points, points))
    points[0] = (start.x, start.y)
    if cells[-1] == goal_cell:
        points[-1] = (goal.x, goal.y)
    return build_path(points, goal.yaw, spec.resolution)


def equally_near(spec: GridSpec, goal: Pose2D, goal_cell: tuple[int, int],
                 candidates: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """The candidates (nearest the goal first) within EQUALLY_NEAR of the goal's distance to the nearest;
    only the goal cell when it is a candidate (passable)."""
    if candidates[0] == goal_cell:
        return [goal_cell]
    xs, ys = np.array(candidates).T
    wx, wy = spec.cell_to_world(xs, ys)
    distance = np.hypot(wx - goal.x, wy - goal.y)
    return [c for c, d in zip(candidates, distance, strict=True) if d <= distance[0] + EQUALLY_NEAR]


def _search_target(spec: GridSpec, start: Pose2D, near: list[tuple[int, int]]) -> tuple[int, int]:
    """The cell the search runs toward: of the equally near candidates, the one nearest the start (the
    heuristic's guess at the cheapest)."""
    xs, ys = np.array(near).T
    wx, wy = spec.cell_to_world(xs, ys)
    return near[int(np.argmin(np.hypot(wx - start.x, wy - start.y)))]
