"""Theta*: any-angle A* with line-of-sight shortcuts to the parent's parent (nav2_theta_star_planner).

Cost of a straight move a→b, as in Nav2's README:
``[w_euc_cost + w_traversal_cost · mean((c / 252)²)] · |ab|`` (|ab| in cells), the mean taken over
the cells the segment crosses; free cells add nothing beyond length. Heuristic:
``min(w_euc_cost, 1) · |n goal|`` (admissible). A segment is usable when every cell it crosses
(its supercover) is passable; a segment through a lattice corner may touch one obstacle's corner
but never squeezes between two diagonal obstacles (the same rule as 8-connected grid moves).
Unlike Nav2 (Lazy Theta*) line of sight is checked eagerly, and the cheaper of "via the current
cell" and "straight from the current cell's parent" is kept.
The planner has no goal tolerance, like Nav2's.
"""

from __future__ import annotations

import heapq
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from nav_stack.core.geometry import FloatArray, Pose2D
from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE, MAX_NON_OBSTACLE, NO_INFORMATION, GridSpec
from nav_stack.core.planning.common import (
    CostArray,
    build_path,
    cell_centres,
    check_costmap,
    graph_from_start,
    locate,
    never,
    search_stopper,
)
from nav_stack.core.planning.errors import PlanErrorCode, PlanningError
from nav_stack.core.planning.grid_search import SearchGraph

_DEADLINE_CHECK_EVERY = 512


@dataclass(frozen=True)
class ThetaStarParams:
    """nav2_theta_star_planner knobs (code defaults) plus our time/iteration caps."""

    how_many_corners: int = 8  # 4- or 8-connected expansion
    w_euc_cost: float = 1.0
    w_traversal_cost: float = 2.0
    allow_unknown: bool = True
    max_planning_time: float = 2.0  # s
    max_iterations: int = 1_000_000

    def __post_init__(self) -> None:
        if self.how_many_corners not in (4, 8):
            raise ValueError(f"ThetaStarParams.how_many_corners must be 4 or 8, got {self.how_many_corners}")
        if not (self.w_euc_cost > 0.0 and self.w_traversal_cost >= 0.0):
            raise ValueError(
                f"ThetaStarParams weights must be w_euc_cost > 0 and w_traversal_cost >= 0, "
                f"got {self.w_euc_cost}, {self.w_traversal_cost}"
            )


def theta_cost_table(allow_unknown: bool) -> list[float]:
    """(c / 252)² per costmap code; unknown charged as 253 when allowed; inf where impassable."""
    table = [(code / MAX_NON_OBSTACLE) ** 2 if code < INSCRIBED_INFLATED_OBSTACLE else math.inf
             for code in range(256)]
    if allow_unknown:
        table[NO_INFORMATION] = (INSCRIBED_INFLATED_OBSTACLE / MAX_NON_OBSTACLE) ** 2
    return table


def cell_distance(dx: int, dy: int) -> float:
    """|(dx, dy)| in cells, as sqrt of the exact integer sum (the compiled search computes the same bits)."""
    return math.sqrt(dx * dx + dy * dy)


ThetaSearch = Callable[["SearchGraph", int, int, "ThetaStarParams", Callable[[], bool]], list[int]]


def segment_mean_cost(graph: SearchGraph, a: int, b: int) -> float:
    """Mean cell cost over the supercover of segment a→b (flat padded indices); inf when blocked."""
    stride, codes, table, blocked = graph.stride, graph.codes, graph.table, graph.blocked
    ay, ax = divmod(a, stride)
    by, bx = divmod(b, stride)
    dx, dy = abs(bx - ax), abs(by - ay)
    sx = 1 if bx > ax else -1
    sy = stride if by > ay else -stride
    idx = a
    total = table[codes[a]]
    count = 1
    ix = iy = 0
    while ix < dx or iy < dy:
        crossing = (2 * ix + 1) * dy - (2 * iy + 1) * dx
        if crossing == 0:  # exactly through a lattice corner: only a gap between two obstacles blocks
            if blocked[idx + sx] and blocked[idx + sy]:
                return math.inf
            idx += sx + sy
            ix += 1
            iy += 1
        elif crossing < 0:
            idx += sx
            ix += 1
        else:
            idx += sy
            iy += 1
        if blocked[idx]:
            return math.inf
        total += table[codes[idx]]
        count += 1
    return total / count


class ThetaStarPlanner:
    """Any-angle planner; the path is densified to ~resolution spacing."""

    def __init__(
        self, params: ThetaStarParams | None = None, clock: Callable[[], float] = time.monotonic,
        search: ThetaSearch | None = None,
    ) -> None:
        """``search``: None for the compiled search (theta_star_jit), or the reference ``search`` of
        this module, which gives the same chains (tests/unit/nav_stack/test_theta_star_jit.py)."""
        from nav_stack.core.planning import theta_star_jit

        self.params = params or ThetaStarParams()
        self._clock = clock
        if search is None:
            theta_star_jit.warm_up()  # compile now, not inside the first plan's max_planning_time
        self._search = search or theta_star_jit.search

    def create_plan(self, start: Pose2D, goal: Pose2D, costs: CostArray, spec: GridSpec,
                    cancel_checker: Callable[[], bool] = never) -> FloatArray:
        check_costmap(costs, spec)
        start_cell = locate(spec, start, "start")
        goal_cell = locate(spec, goal, "goal")
        table = theta_cost_table(self.params.allow_unknown)
        escape_cost = max(cost for cost in table if cost < math.inf)  # the highest passable cost
        graph = graph_from_start(SearchGraph.build(costs, table), costs, spec, start_cell, escape_cost)
        if not graph.passable(*goal_cell):
            raise PlanningError(
                PlanErrorCode.GOAL_OCCUPIED,
                f"goal cell {goal_cell} has cost {costs[goal_cell[1], goal_cell[0]]}",
            )
        stop = search_stopper(self._clock, self.params.max_planning_time, cancel_checker)
        chain = self._search(graph, graph.index(*start_cell), graph.index(*goal_cell), self.params, stop)
        points = cell_centres(spec, [graph.cell(i) for i in chain])
        if len(points) == 1:
            points = np.vstack((points, points))
        points[0] = (start.x, start.y)
        points[-1] = (goal.x, goal.y)
        return build_path(points, goal.yaw, spec.resolution)


def search(graph: SearchGraph, start: int, goal: int, params: ThetaStarParams,
           deadline_passed: Callable[[], bool]) -> list[int]:
    """The reference Theta* search (pure Python): the chain of flat indices from ``start`` to ``goal``.

    Raises PlanningError: TIMEOUT past ``max_iterations`` expansions or once ``deadline_passed()``
    (polled every 512 expansions), NO_VALID_PATH when the goal cannot be reached.
    """
    p = params
    stride = graph.stride
    steps = [-1, 1, -stride, stride]
    if p.how_many_corners == 8:
        steps += [-stride - 1, -stride + 1, stride - 1, stride + 1]
    gy, gx = divmod(goal, stride)
    w_h = min(p.w_euc_cost, 1.0)
    closed = bytearray(graph.blocked)
    g: dict[int, float] = {start: 0.0}
    parent: dict[int, int] = {start: start}
    heap: list[tuple[float, int]] = [(0.0, start)]
    expansions = 0

    def move_cost(a: int, b: int) -> float:
        ay, ax = divmod(a, stride)
        by, bx = divmod(b, stride)
        mean = segment_mean_cost(graph, a, b)
        return (p.w_euc_cost + p.w_traversal_cost * mean) * cell_distance(bx - ax, by - ay)

    while heap:
        _, cur = heapq.heappop(heap)
        if closed[cur]:
            continue
        closed[cur] = 2
        if cur == goal:
            chain = [goal]
            while chain[-1] != start:
                chain.append(parent[chain[-1]])
            return chain[::-1]
        expansions += 1
        if expansions > p.max_iterations:
            raise PlanningError(PlanErrorCode.TIMEOUT, f"iteration cap of {p.max_iterations} reached")
        if expansions % _DEADLINE_CHECK_EVERY == 0 and deadline_passed():
            raise PlanningError(
                PlanErrorCode.TIMEOUT,
                f"max_planning_time {p.max_planning_time} s passed after {expansions} expansions",
            )
        par = parent[cur]
        for step in steps:
            n = cur + step
            if closed[n]:
                continue
            best, best_parent = g[cur] + move_cost(cur, n), cur
            if par != cur:
                via_parent = g[par] + move_cost(par, n)
                if via_parent <= best:
                    best, best_parent = via_parent, par
            if best < g.get(n, math.inf):
                g[n] = best
                parent[n] = best_parent
                ny, nx = divmod(n, stride)
                heapq.heappush(heap, (best + w_h * cell_distance(nx - gx, ny - gy), n))
    raise PlanningError(
        PlanErrorCode.NO_VALID_PATH, f"no path from {graph.cell(start)} to {graph.cell(goal)}"
    )
