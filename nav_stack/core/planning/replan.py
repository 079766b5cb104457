"""When a replan may keep the rest of the last plan instead of searching again (issue 44).

Why: Nav2's default tree asks for a new plan to the same goal every second. On a warehouse map
(1.6 M cells at 3 cm) one A* search takes 35 to 95 ms of wall time depending on load, against
the 50 ms of ``expected_planner_frequency`` (20 Hz in the Jazzy yaml): the benchmark
bench/bench_large_world.py logged budget warnings for searches whose answer was, cell for cell,
the rest of the plan the robot was already driving. Searching faster only moves the bar (a C++ A*,
pyastar2d, takes 32 ms on that map on an idle machine); not searching when the answer is known
removes the overrun.

The rule (exact: the kept plan costs no more than a new search's would):

* same goal pose, same grid (size, resolution, origin), the last plan ended on the goal's own cell
  (no tolerance choice involved), and it was searched on the costmap's own costs (no escape from an
  inscribed band opened around its start);
* the robot's cell is a cell of that plan, say its i-th, and is passable;
* no cell of the plan after the i-th changed its traversal cost, so the rest still costs C, the
  cost the search computed for it;
* every cell whose traversal cost went down since then lies too far off to offer anything
  cheaper: any path from the start through cell x to the end costs at least NEUTRAL_COST times the
  octile distance start→x plus x→end (no step costs less per cell), and that bound is >= C.

Why that suffices: the kept part is a suffix of a cost-optimal path, hence optimal from its first
cell on the costs it was searched on (Bellman's principle). Costs that went up elsewhere only make
other paths dearer; a path cheaper than C would have to cross a cell that got cheaper, which the
bound excludes. A new search could only return another path of the same cost (a tie), so the plan a
Nav2 user sees differs from a fresh one at most by which of two equal-cost paths it is.

Off the plan (the robot's cell not on it), another goal, a moved window or an escape: search again.
(A*'s heuristic carries a 1e-6 tie-break, so "optimal" means within 1e-6 of the optimum, as for a
search.)

Numbers (issue 44): on bench_planning's 1.67 M-cell warehouse a kept replan takes 1.3 ms of CPU
against 50 to 90 ms for the A* search; in bench_large_world (office, 1.61 M cells, TB4, 5 goals)
about two replans in three were kept; the others were searched (the robot's cell off the plan, or
a changed cell the rule could not rule out).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nav_stack.core.geometry import Pose2D
from nav_stack.core.grid import GridSpec
from nav_stack.core.planning.grid_search import NEUTRAL_COST

CostArray = npt.NDArray[np.uint8]
Cells = npt.NDArray[np.int64]  # (N, 2) grid cells (mx, my)


@dataclass(frozen=True)
class LastPlan:
    """What a replan needs to know about the previous plan.

    ``cells`` (N, 2) are the plan's grid cells (mx, my) from its start to its end; ``cost_to_end``
    (N,) the traversal cost from each of them to the end along the plan (NavFn units: 50 per free
    cell); ``costs`` the costmap (a private copy) it was searched on.
    """

    goal: Pose2D
    spec: GridSpec
    costs: CostArray
    cells: Cells
    cost_to_end: npt.NDArray[np.float64]


def octile(ax: npt.ArrayLike, ay: npt.ArrayLike, bx: npt.ArrayLike, by: npt.ArrayLike
           ) -> npt.NDArray[np.float64]:
    """Length in cells of the shortest 8-connected walk between cells a and b (no obstacles)."""
    dx = np.abs(np.asarray(ax, dtype=np.float64) - np.asarray(bx, dtype=np.float64))
    dy = np.abs(np.asarray(ay, dtype=np.float64) - np.asarray(by, dtype=np.float64))
    return np.maximum(dx, dy) + (math.sqrt(2.0) - 1.0) * np.minimum(dx, dy)


def changed_cells(before: CostArray, after: CostArray) -> tuple[npt.NDArray[np.intp], npt.NDArray[np.intp]]:
    """(rows, cols) of the cells whose code differs between two grids of one shape.

    Why not ``np.nonzero(before != after)``: on a 1.6 M-cell map that pass took 2-3 ms, most of a
    kept replan. Eight cells are compared at once as one 64-bit word, and only the few words that
    differ are looked at cell by cell.
    """
    a, b = np.ascontiguousarray(before).reshape(-1), np.ascontiguousarray(after).reshape(-1)
    whole = len(a) - len(a) % 8
    words = np.flatnonzero(a[:whole].view(np.uint64) != b[:whole].view(np.uint64))
    candidates = np.concatenate(((words[:, None] * 8 + np.arange(8)).reshape(-1), np.arange(whole, len(a))))
    flat = candidates[a[candidates] != b[candidates]]
    rows, cols = np.divmod(flat, before.shape[1])
    return rows, cols


class ReplanMemory:
    """Keeps the last plan of one planner and answers whether a replan may keep its rest.

    ``table``: the planner's traversal cost per costmap code (inf: impassable), the same table its
    search uses, so "changed" means changed for the search, not merely a different code.
    """

    def __init__(self, table: list[float]) -> None:
        self._table = np.asarray(table, dtype=np.float64)
        self._last: LastPlan | None = None
        self.kept = 0  # replans answered from the last plan (for logs and benchmarks)

    def forget(self) -> None:
        self._last = None

    def remember(self, goal: Pose2D, spec: GridSpec, costs: CostArray, cells: Cells,
                 g_along: npt.NDArray[np.float64]) -> None:
        """Store a searched plan: ``cells`` (N, 2) ending on the goal's cell, ``g_along`` (N,) the
        search's cost from the plan's start to each of them. ``costs`` is copied."""
        g_along = np.asarray(g_along, dtype=np.float64)
        self._last = LastPlan(goal, spec, costs.copy(), np.asarray(cells, dtype=np.int64).reshape(-1, 2),
                              g_along[-1] - g_along)

    def rest_of_plan(self, start_cell: tuple[int, int], goal: Pose2D, spec: GridSpec,
                     costs: CostArray) -> Cells | None:
        """The last plan's cells from ``start_cell`` on when the rule above allows, else None."""
        last = self._last
        if last is None or last.goal != goal or last.spec != spec or last.costs.shape != costs.shape:
            return None
        on_plan = np.nonzero((last.cells[:, 0] == start_cell[0]) & (last.cells[:, 1] == start_cell[1]))[0]
        if len(on_plan) == 0 or not math.isfinite(self._table[costs[start_cell[1], start_cell[0]]]):
            return None
        rest = last.cells[on_plan[0]:]
        before = self._table[last.costs[rest[1:, 1], rest[1:, 0]]]
        if not np.array_equal(before, self._table[costs[rest[1:, 1], rest[1:, 0]]]):
            return None  # the rest of the plan itself changed
        rows, cols = changed_cells(last.costs, costs)
        if len(rows):
            cheaper = self._table[costs[rows, cols]] < self._table[last.costs[rows, cols]]
            cols, rows = cols[cheaper], rows[cheaper]
            end = rest[-1]
            bound = NEUTRAL_COST * (octile(start_cell[0], start_cell[1], cols, rows)
                                    + octile(cols, rows, end[0], end[1]))
            if len(bound) and float(bound.min()) < float(last.cost_to_end[on_plan[0]]):
                return None  # a cell that got cheaper could offer a cheaper path
        self.kept += 1
        return rest
