"""The grid search of grid_search.py compiled with numba: the same expansions, 20-100x faster.

Why numba: the search is a tight loop over flat arrays (a binary heap, costs, parents) that Python
runs at about a microsecond per operation, so a Dijkstra over a 2000 x 2000 map took seconds
against Nav2's 50 ms budget. numba compiles this very Python (kept readable, next to the reference
in grid_search.py) to machine code on first use and caches it in ``__pycache__``, with no build
step, which a C++ extension would need, and no second implementation in another language.

Same search, same result: the heap orders entries by (f, index) as Python's heapq orders the
reference's tuples, f is computed with the same operations in the same order, and a min-heap pops
the same sequence whatever its internal layout (entries equal in both key and index are the same
node, and the second pop of a node is skipped). tests/unit/nav_stack/test_grid_search_jit.py
checks identical paths and costs on random maps.

The compiled loop cannot call back into Python, so it runs in slices of DEADLINE_CHECK_EVERY
expansions and the caller checks the deadline between slices, as the reference does in its loop.
A planner passes one :class:`SearchArrays` to all its searches: the 4-million-cell arrays of a
2000 x 2000 map are kept between plans, and only the cells the last plan reached are reset.

A slice runs without the GIL (``nogil``): it touches only its arrays, and the planner server runs
it on its worker thread, so the executor thread goes on serving the controller and the costmaps on
the other core instead of waiting for the slice, and the search no longer waits for the executor's
Python to hand the GIL back (which stretched plans past the 50 ms budget on a busy process).

Compiling takes seconds (about 4 s on two cores; loading the cached code about 1 s), which must not
count against the first plan's ``max_planning_time``: planners call :func:`warm_up` when they are
built, during the planner server's configure.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import numpy.typing as npt
from numba import njit

from nav_stack.core.planning.grid_search import (
    _CLOSED_EXPANDED,
    _DEADLINE_CHECK_EVERY,
    _SQRT2,
    _TIE_BREAK,
    NEUTRAL_COST,
    SearchGraph,
    SearchResult,
    SearchTimeoutError,
)

REACHED, SLICE_DONE, EXHAUSTED = 0, 1, 2  # what one slice of expansions ended with


@njit(cache=True)
def _push(keys: npt.NDArray[np.float64], items: npt.NDArray[np.int64], size: int, key: float,
          item: int) -> int:
    """Add (key, item) to the binary heap in keys[:size], items[:size]; the new size."""
    pos = size
    while pos > 0:
        up = (pos - 1) >> 1
        if keys[up] < key or (keys[up] == key and items[up] <= item):
            break
        keys[pos], items[pos] = keys[up], items[up]
        pos = up
    keys[pos], items[pos] = key, item
    return size + 1


@njit(cache=True)
def _pop(keys: npt.NDArray[np.float64], items: npt.NDArray[np.int64], size: int) -> tuple[int, int]:
    """Remove the smallest (key, item) of the heap; returns (item, new size)."""
    top = items[0]
    size -= 1
    key, item = keys[size], items[size]
    pos = 0
    while True:
        child = 2 * pos + 1
        if child >= size:
            break
        right = child + 1
        if right < size and (keys[right] < keys[child]
                             or (keys[right] == keys[child] and items[right] < items[child])):
            child = right
        if key < keys[child] or (key == keys[child] and item <= items[child]):
            break
        keys[pos], items[pos] = keys[child], items[child]
        pos = child
    if size > 0:
        keys[pos], items[pos] = key, item
    return top, size


@njit(cache=True, nogil=True)
def _expand(codes: npt.NDArray[np.uint8], table: npt.NDArray[np.float64], closed: npt.NDArray[np.uint8],
            g: npt.NDArray[np.float64], parent: npt.NDArray[np.int64], touched: npt.NDArray[np.int32],
            n_touched: int, keys: npt.NDArray[np.float64], items: npt.NDArray[np.int64], size: int,
            goal: int, stride: int, h_straight: float, budget: int) -> tuple[int, int, int, int]:
    """Expand up to ``budget`` nodes; returns (REACHED | SLICE_DONE | EXHAUSTED, heap size, expansions,
    touched count).

    The loop body is the reference's (grid_search.search), on arrays: g = inf marks "not reached".
    Every cell reached for the first time is listed in ``touched`` so the next search resets only
    those cells instead of the whole grid.
    """
    offsets = (-stride - 1, -stride, -stride + 1, -1, 1, stride - 1, stride, stride + 1)
    lengths = (_SQRT2, 1.0, _SQRT2, 1.0, 1.0, _SQRT2, 1.0, _SQRT2)
    step_x = (-1, 0, 1, -1, 1, -1, 0, 1)  # the offsets as (x, y) steps: no division per neighbour
    step_y = (-1, -1, -1, 0, 0, 1, 1, 1)
    h_diag = (_SQRT2 - 2.0) * h_straight
    gy, gx = goal // stride, goal % stride
    expansions = 0
    while size > 0:
        if expansions >= budget:  # checked before a pop, so the next slice resumes exactly here
            return SLICE_DONE, size, expansions, n_touched
        cur, size = _pop(keys, items, size)
        if closed[cur]:
            continue
        closed[cur] = _CLOSED_EXPANDED
        if cur == goal:
            return REACHED, size, expansions, n_touched
        expansions += 1
        g_cur = g[cur]
        cy, cx = cur // stride, cur % stride
        for k in range(8):
            n = cur + offsets[k]
            if closed[n]:
                continue
            ng = g_cur + table[codes[n]] * lengths[k]
            g_n = g[n]
            if ng < g_n:
                if g_n == math.inf:
                    touched[n_touched] = n
                    n_touched += 1
                g[n] = ng
                parent[n] = cur
                f = ng
                if h_straight != 0.0:  # A*; Dijkstra (NavFn's default) orders by g alone
                    ny, nx = cy + step_y[k], cx + step_x[k]
                    dx = nx - gx if nx > gx else gx - nx
                    dy = ny - gy if ny > gy else gy - ny
                    f = ng + (dx + dy) * h_straight + (dx if dx < dy else dy) * h_diag
                size = _push(keys, items, size, f, n)
    return EXHAUSTED, size, expansions, n_touched


class SearchArrays:
    """What a compiled search works on, kept between searches of one planner.

    The graph's codes, cost table and blocked cells as arrays, the closed marks, g (inf: not
    reached), parent links (-1: none), the cells reached so far (``touched``) and the binary heap
    (``keys``, ``items``, ``size``). Shared by grid and Theta* searches.

    Why kept: on a 2000 x 2000 map g and parent are 32 MB each. Allocating and filling them for every
    plan, then faulting their pages in during the search, cost 10 to 15 ms of a 50 ms budget;
    :meth:`start` instead resets only the cells the previous search reached. A
    :class:`SearchResult` built on these arrays is valid until the next :meth:`start`.
    """

    def __init__(self) -> None:
        self.cells = 0
        self.closed = np.empty(0, dtype=np.uint8)
        self.g = np.empty(0)
        self.parent = np.empty(0, dtype=np.int64)
        self.touched = np.empty(0, dtype=np.int32)
        self.n_touched = 0
        self.keys, self.items = np.empty(1 << 16), np.empty(1 << 16, dtype=np.int64)
        self.size = 0
        self.codes = np.empty(0, dtype=np.uint8)
        self.table = np.empty(0)
        self.blocked = np.empty(0, dtype=np.uint8)

    def start(self, graph: SearchGraph, start: int) -> None:
        """Prepare a search of ``graph`` from flat index ``start``."""
        cells = len(graph.codes)
        if cells != self.cells:  # a new map size: fresh arrays (already "not reached" everywhere)
            self.cells = cells
            self.closed = np.empty(cells, dtype=np.uint8)
            self.g = np.full(cells, math.inf)
            self.parent = np.full(cells, -1, dtype=np.int64)
            self.touched = np.empty(cells, dtype=np.int32)
        else:
            reached = self.touched[: self.n_touched]
            self.g[reached] = math.inf
            self.parent[reached] = -1
        self.codes = np.frombuffer(graph.codes, dtype=np.uint8)
        self.table = np.asarray(graph.table, dtype=np.float64)
        self.blocked = np.frombuffer(graph.blocked, dtype=np.uint8)
        np.copyto(self.closed, self.blocked)
        self.g[start] = 0.0
        self.touched[0], self.n_touched = start, 1
        self.keys[0], self.items[0], self.size = 0.0, start, 1

    def make_room(self, pushes: int) -> None:
        """Grow the heap (doubling) until ``pushes`` more entries fit: a slice cannot reallocate."""
        while len(self.keys) < self.size + pushes:
            self.keys = np.concatenate([self.keys, np.empty(len(self.keys))])
            self.items = np.concatenate([self.items, np.empty(len(self.items), dtype=np.int64)])


def warm_up() -> None:
    """Compile (or load from the cache) the search now, on a 3 x 3 grid."""
    graph = SearchGraph.build(np.zeros((3, 3), dtype=np.uint8), [1.0] * 256)
    for use_astar in (True, False):
        search(graph, graph.index(0, 0), graph.index(2, 2), use_astar, 100, lambda: False)


def search(
    graph: SearchGraph,
    start: int,
    goal: int,
    use_astar: bool,
    max_iterations: int,
    deadline_passed: Callable[[], bool],
    arrays: SearchArrays | None = None,
) -> SearchResult:
    """grid_search.search, compiled: the same arguments, result and SearchTimeoutError.

    ``arrays``: what to search on. A planner passes the same :class:`SearchArrays` to every plan (the
    result is then valid until its next search); None allocates fresh ones for this search alone.
    """
    a = arrays if arrays is not None else SearchArrays()
    a.start(graph, start)
    h_straight = NEUTRAL_COST * _TIE_BREAK if use_astar else 0.0
    expansions = 0
    while True:
        # up to max_iterations + 1: the reference fails on the pop past the cap, unless it is the goal
        budget = min(_DEADLINE_CHECK_EVERY, max_iterations + 1 - expansions)
        a.make_room(8 * budget)
        status, a.size, done, a.n_touched = _expand(
            a.codes, a.table, a.closed, a.g, a.parent, a.touched, a.n_touched, a.keys, a.items, a.size,
            goal, graph.stride, h_straight, budget)
        expansions += done
        if status == REACHED:
            return SearchResult(goal, a.parent, a.g, a.closed, expansions)
        if status == EXHAUSTED:
            return SearchResult(None, a.parent, a.g, a.closed, expansions)
        if expansions > max_iterations:
            raise SearchTimeoutError(f"iteration cap of {max_iterations} expansions reached")
        if deadline_passed():
            raise SearchTimeoutError(f"planning deadline passed after {expansions} expansions")
