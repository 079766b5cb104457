"""theta_star.search compiled with numba: the same chains, for the same reasons as grid_search_jit.

The loop, the supercover walk of segment_mean_cost and the cost formulas are theta_star.py's on
arrays; distances are sqrt of exact integer sums in both, so every f is bit-identical and the
(f, index) heap of grid_search_jit pops the same sequence. The loop runs in slices of 512
expansions; the caller checks the deadline between them, as the reference does in its loop.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import numpy.typing as npt
from numba import njit

from nav_stack.core.planning.errors import PlanErrorCode, PlanningError
from nav_stack.core.planning.grid_search import _CLOSED_EXPANDED, SearchGraph
from nav_stack.core.planning.grid_search_jit import EXHAUSTED, REACHED, SLICE_DONE, SearchArrays, _pop, _push
from nav_stack.core.planning.theta_star import _DEADLINE_CHECK_EVERY, ThetaStarParams


@njit(cache=True)
def _segment_mean_cost(codes: npt.NDArray[np.uint8], table: npt.NDArray[np.float64],
                       blocked: npt.NDArray[np.uint8], stride: int, a: int, b: int) -> float:
    """theta_star.segment_mean_cost on arrays: mean cost over the supercover of a→b, inf if blocked."""
    ay, ax = a // stride, a % stride
    by, bx = b // stride, b % stride
    dx, dy = abs(bx - ax), abs(by - ay)
    sx = 1 if bx > ax else -1
    sy = stride if by > ay else -stride
    idx = a
    total = table[codes[a]]
    count = 1
    ix = iy = 0
    while ix < dx or iy < dy:
        crossing = (2 * ix + 1) * dy - (2 * iy + 1) * dx
        if crossing == 0:
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
    return float(total / count)


@njit(cache=True)
def _move_cost(codes: npt.NDArray[np.uint8], table: npt.NDArray[np.float64], blocked: npt.NDArray[np.uint8],
               stride: int, a: int, b: int, w_euc: float, w_trav: float) -> float:
    mean = _segment_mean_cost(codes, table, blocked, stride, a, b)
    dx, dy = b % stride - a % stride, b // stride - a // stride
    return (w_euc + w_trav * mean) * math.sqrt(dx * dx + dy * dy)


@njit(cache=True)
def _expand(codes: npt.NDArray[np.uint8], table: npt.NDArray[np.float64], blocked: npt.NDArray[np.uint8],
            closed: npt.NDArray[np.uint8], g: npt.NDArray[np.float64], parent: npt.NDArray[np.int64],
            keys: npt.NDArray[np.float64], items: npt.NDArray[np.int64], size: int, goal: int, stride: int,
            corners: int, w_euc: float, w_trav: float, budget: int) -> tuple[int, int, int]:
    """Up to ``budget`` expansions of theta_star.search's loop: (REACHED, SLICE_DONE or EXHAUSTED,
    heap size, expansions)."""
    steps = (-1, 1, -stride, stride, -stride - 1, -stride + 1, stride - 1, stride + 1)
    gy, gx = goal // stride, goal % stride
    w_h = min(w_euc, 1.0)
    expansions = 0
    while size > 0:
        if expansions >= budget:
            return SLICE_DONE, size, expansions
        cur, size = _pop(keys, items, size)
        if closed[cur]:
            continue
        closed[cur] = _CLOSED_EXPANDED
        if cur == goal:
            return REACHED, size, expansions
        expansions += 1
        par = parent[cur]
        for k in range(corners):
            n = cur + steps[k]
            if closed[n]:
                continue
            best = g[cur] + _move_cost(codes, table, blocked, stride, cur, n, w_euc, w_trav)
            best_parent = cur
            if par != cur:
                via_parent = g[par] + _move_cost(codes, table, blocked, stride, par, n, w_euc, w_trav)
                if via_parent <= best:
                    best, best_parent = via_parent, par
            if best < g[n]:
                g[n] = best
                parent[n] = best_parent
                dx, dy = n % stride - gx, n // stride - gy
                size = _push(keys, items, size, best + w_h * math.sqrt(dx * dx + dy * dy), n)
    return EXHAUSTED, size, expansions


def warm_up() -> None:
    """Compile (or load from the cache) the search now, on a 3 x 3 grid."""
    graph = SearchGraph.build(np.zeros((3, 3), dtype=np.uint8), [0.0] * 256)
    search(graph, graph.index(0, 0), graph.index(2, 2), ThetaStarParams(), lambda: False)


def search(graph: SearchGraph, start: int, goal: int, params: ThetaStarParams,
           deadline_passed: Callable[[], bool]) -> list[int]:
    """theta_star.search, compiled: the same arguments, chain and PlanningErrors."""
    a = SearchArrays()  # fresh arrays: this loop does not list the cells it reaches for a reuse
    a.start(graph, start)
    a.parent[start] = start
    expansions = 0
    while True:
        budget = min(_DEADLINE_CHECK_EVERY, params.max_iterations + 1 - expansions)
        a.make_room(8 * budget)
        status, a.size, done = _expand(a.codes, a.table, a.blocked, a.closed, a.g, a.parent, a.keys, a.items,
                                       a.size, goal, graph.stride, params.how_many_corners, params.w_euc_cost,
                                       params.w_traversal_cost, budget)
        expansions += done
        if status == REACHED:
            chain = [goal]
            while chain[-1] != start:
                chain.append(int(a.parent[chain[-1]]))
            return chain[::-1]
        if status == EXHAUSTED:
            raise PlanningError(PlanErrorCode.NO_VALID_PATH,
                                f"no path from {graph.cell(start)} to {graph.cell(goal)}")
        if expansions > params.max_iterations:
            raise PlanningError(PlanErrorCode.TIMEOUT, f"iteration cap of {params.max_iterations} reached")
        if deadline_passed():
            raise PlanningError(
                PlanErrorCode.TIMEOUT,
                f"max_planning_time {params.max_planning_time} s passed after {expansions} expansions",
            )
