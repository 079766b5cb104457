"""Cost-aware 8-connected A* / Dijkstra over a costmap, on flat indices of a padded grid.

Why this shape: the search runs in pure Python, so everything that can be done once per plan is
done before the loop, and preparing a costmap must be cheap because the global costmap changes
about once a second. The graph keeps the costmap's own uint8 codes (padded with a one-cell
impassable border so the loop needs no bounds checks, flattened to ``bytes``) and a 256-entry
table from code to traversal cost (NavFn's c' = 50 + 0.8·c). Preparing a 1000 × 1000 map is then a
pad and a copy (about 2 ms) instead of a million Python floats (about 45 ms, plus as much again
to free the previous ones). Impassable cells start "closed", so one bytearray lookup rejects both
visited and blocked neighbours; the cost table is only read for passable cells. Moving into a
cell costs its traversal cost times the step length in cells (1 or √2); the start cell is free.

A* uses the octile distance times the neutral cost (50), admissible and consistent because no
step is cheaper than 50 per cell; it is inflated by 1e-6 so ties on f prefer the deeper node,
which keeps open-space expansions close to the path length (the returned cost is within 1e-6
relative of the optimum). Dijkstra (``use_astar=False``, NavFn's default) is the same loop with a
zero heuristic.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.grid import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION

NEUTRAL_COST = 50.0  # NavFn COST_NEUTRAL: traversal cost of a free cell
COST_FACTOR = 0.8  # NavFn COST_FACTOR: weight of the costmap value
UNKNOWN_TRAVERSAL_COST = 253.0  # NavFn charges an allowed unknown cell COST_OBS - 1
_TIE_BREAK = 1.0 + 1e-6
_SQRT2 = math.sqrt(2.0)
_CLOSED_BLOCKED = 1
_CLOSED_EXPANDED = 2
_DEADLINE_CHECK_EVERY = 2048


#: The code whose table entry is the escape cost: costmap cells of this code (inscribed) are
#: impassable, except the ones :func:`open_escape` opens around a wedged robot.
ESCAPE_CODE = INSCRIBED_INFLATED_OBSTACLE


def navfn_cost_table(allow_unknown: bool) -> list[float]:
    """Traversal cost per costmap code: 50 + 0.8·c below 253, 253 for allowed unknown, else inf."""
    table = [NEUTRAL_COST + COST_FACTOR * code if code < INSCRIBED_INFLATED_OBSTACLE else math.inf
             for code in range(256)]
    if allow_unknown:
        table[NO_INFORMATION] = UNKNOWN_TRAVERSAL_COST
    return table


def navfn_traversal_costs(costs: npt.NDArray[np.uint8], allow_unknown: bool) -> npt.NDArray[np.float64]:
    """Per-cell traversal cost array of a costmap (``navfn_cost_table`` applied to every cell)."""
    return np.asarray(navfn_cost_table(allow_unknown))[costs]


class SearchTimeoutError(Exception):
    """The search exceeded its iteration cap or deadline."""


@dataclass
class SearchGraph:
    """A costmap prepared for the search loop: padded codes, their cost table and the blocked cells.

    A passable cell at flat index i costs ``table[codes[i]]``; cells with ``blocked[i]`` set are
    never entered, whatever their table entry.
    """

    width: int
    height: int
    codes: bytes
    table: list[float]
    blocked: bytes

    @classmethod
    def build(cls, codes: npt.NDArray[np.uint8], table: list[float]) -> SearchGraph:
        """Pad and flatten a (height, width) code grid; a cell is blocked when its table cost is inf."""
        if len(table) != 256:
            raise ValueError(f"the cost table needs 256 entries (one per uint8 code), got {len(table)}")
        height, width = codes.shape
        padded = np.pad(codes.astype(np.uint8, copy=False), 1)
        impassable = np.isinf(np.asarray(table, dtype=np.float64))
        blocked = impassable[padded]
        blocked[0, :] = blocked[-1, :] = blocked[:, 0] = blocked[:, -1] = True
        return cls(width, height, padded.tobytes(), list(table), blocked.view(np.uint8).tobytes())

    @property
    def stride(self) -> int:
        return self.width + 2

    def index(self, mx: int, my: int) -> int:
        """Flat index of grid cell (mx, my)."""
        return (my + 1) * self.stride + mx + 1

    def cell(self, index: int) -> tuple[int, int]:
        """Grid cell (mx, my) of a flat index."""
        row, col = divmod(index, self.stride)
        return col - 1, row - 1

    def passable(self, mx: int, my: int) -> bool:
        return not self.blocked[self.index(mx, my)]


def open_escape(
    graph: SearchGraph,
    costs: npt.NDArray[np.uint8],
    start: tuple[int, int],
    radius_cells: int,
    escape_cost: float,
) -> SearchGraph:
    """A copy of ``graph`` in which the robot can leave the inscribed band it starts in.

    A robot that ended up with its centre in the inscribed band of an obstacle (cost 253, not lethal)
    would otherwise get START_OCCUPIED or NO_VALID_PATH and stay wedged. NavFn clears only the robot's
    own cell, which does not help when its neighbours are inscribed too. Here the start cell and the
    inscribed cells within ``radius_cells`` of it that are no closer to a lethal cell than the start
    (to within half a cell) become passable at ``escape_cost`` (the planner's highest traversal cost),
    so the path leaves the band the shortest way. Lethal cells stay blocked.

    Why "no closer": with every inscribed cell near the start open, a robot at the edge of a pillar's
    band planned straight through the band, 7 cm from the pillar's cells, because that was cheaper than
    going round; the controller found no valid command on that path and the seed tree's patrol failed
    (a looped system test, 1 run in 15). The escape must lead out, never deeper in.
    """
    mx, my = start
    height, width = costs.shape
    x0, x1 = max(0, mx - radius_cells), min(width, mx + radius_cells + 1)
    y0, y1 = max(0, my - radius_cells), min(height, my + radius_cells + 1)
    yy, xx = np.mgrid[y0:y1, x0:x1]
    near = (xx - mx) ** 2 + (yy - my) ** 2 <= radius_cells**2
    clearance = _lethal_distance(costs, xx, yy, radius_cells)  # cells
    outward = clearance >= clearance[my - y0, mx - x0] - 0.5
    escape = near & (costs[y0:y1, x0:x1] == INSCRIBED_INFLATED_OBSTACLE) & outward
    escape[my - y0, mx - x0] = True
    codes = bytearray(graph.codes)
    blocked = bytearray(graph.blocked)
    for y, x in zip(*np.nonzero(escape), strict=True):
        index = graph.index(int(x0 + x), int(y0 + y))
        codes[index] = ESCAPE_CODE
        blocked[index] = 0
    table = list(graph.table)
    table[ESCAPE_CODE] = escape_cost
    return SearchGraph(graph.width, graph.height, bytes(codes), table, bytes(blocked))


def _lethal_distance(costs: npt.NDArray[np.uint8], xx: npt.NDArray[np.int64], yy: npt.NDArray[np.int64],
                     reach: int) -> npt.NDArray[np.float64]:
    """Distance (cells) from each cell (``xx``, ``yy``) to the nearest lethal cell at most ``reach``
    cells beyond the window they span; inf where none is that close."""
    height, width = costs.shape
    x0, x1 = max(0, int(xx.min()) - reach), min(width, int(xx.max()) + reach + 1)
    y0, y1 = max(0, int(yy.min()) - reach), min(height, int(yy.max()) + reach + 1)
    ly, lx = np.nonzero(costs[y0:y1, x0:x1] == LETHAL_OBSTACLE)
    if len(lx) == 0:
        return np.full(xx.shape, np.inf)
    dx = xx[..., None] - (lx + x0)
    dy = yy[..., None] - (ly + y0)
    return np.asarray(np.sqrt(dx * dx + dy * dy).min(axis=-1), dtype=np.float64)


@dataclass
class SearchResult:
    """Outcome of one search, on flat indices: the goal if reached, parent links (-1: none), the cost
    g of every reached cell (inf: not reached) and which cells were expanded."""

    reached: int | None
    parent: npt.NDArray[np.int64]
    g: npt.NDArray[np.float64]
    expanded: npt.NDArray[np.uint8]
    expansions: int

    def cells_to(self, graph: SearchGraph, index: int) -> list[tuple[int, int]]:
        """Cells (mx, my) from the start to ``index`` following the parent links."""
        parent = self.parent
        chain = [index]
        while parent[chain[-1]] >= 0:
            chain.append(int(parent[chain[-1]]))
        rows, cols = np.divmod(np.array(chain[::-1], dtype=np.int64), graph.stride)
        return list(zip((cols - 1).tolist(), (rows - 1).tolist(), strict=True))

    def was_expanded(self, index: int) -> bool:
        return bool(self.expanded[index] == _CLOSED_EXPANDED)

    @classmethod
    def from_dicts(cls, reached: int | None, parent: dict[int, int], g: dict[int, float],
                   closed: bytearray, expansions: int) -> SearchResult:
        """The reference loop's dictionaries as arrays over the ``len(closed)`` flat cells."""
        parents = np.full(len(closed), -1, dtype=np.int64)
        parents[list(parent)] = list(parent.values())
        costs = np.full(len(closed), math.inf)
        costs[list(g)] = list(g.values())
        return cls(reached, parents, costs, np.frombuffer(bytes(closed), dtype=np.uint8), expansions)


def search(
    graph: SearchGraph,
    start: int,
    goal: int,
    use_astar: bool,
    max_iterations: int,
    deadline_passed: Callable[[], bool],
) -> SearchResult:
    """Best-first search from ``start`` to ``goal`` (flat indices); exhausts the reachable set on failure.

    Raises SearchTimeoutError after ``max_iterations`` expansions or once ``deadline_passed()`` is true
    (polled every 2048 expansions).
    """
    stride = graph.stride
    codes, table = graph.codes, graph.table
    closed = bytearray(graph.blocked)
    g: dict[int, float] = {start: 0.0}
    parent: dict[int, int] = {}
    steps = [
        (-stride - 1, _SQRT2),
        (-stride, 1.0),
        (-stride + 1, _SQRT2),
        (-1, 1.0),
        (1, 1.0),
        (stride - 1, _SQRT2),
        (stride, 1.0),
        (stride + 1, _SQRT2),
    ]
    gy, gx = divmod(goal, stride)
    h_straight = NEUTRAL_COST * _TIE_BREAK if use_astar else 0.0
    h_diag = (_SQRT2 - 2.0) * h_straight
    heap: list[tuple[float, int]] = [(0.0, start)]
    pop, push = heapq.heappop, heapq.heappush
    inf = math.inf
    expansions = 0
    while heap:
        _, cur = pop(heap)
        if closed[cur]:
            continue
        closed[cur] = _CLOSED_EXPANDED
        if cur == goal:
            return SearchResult.from_dicts(cur, parent, g, closed, expansions)
        expansions += 1
        if expansions > max_iterations:
            raise SearchTimeoutError(f"iteration cap of {max_iterations} expansions reached")
        if expansions % _DEADLINE_CHECK_EVERY == 0 and deadline_passed():
            raise SearchTimeoutError(f"planning deadline passed after {expansions} expansions")
        g_cur = g[cur]
        for offset, length in steps:
            n = cur + offset
            if closed[n]:
                continue
            ng = g_cur + table[codes[n]] * length
            if ng < g.get(n, inf):
                g[n] = ng
                parent[n] = cur
                ny, nx = divmod(n, stride)
                dx = nx - gx if nx > gx else gx - nx
                dy = ny - gy if ny > gy else gy - ny
                push(heap, (ng + (dx + dy) * h_straight + (dx if dx < dy else dy) * h_diag, n))
    return SearchResult.from_dicts(None, parent, g, closed, expansions)
