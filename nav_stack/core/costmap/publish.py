"""What a costmap publishes each cycle: the whole grid or only the cells that changed (Nav2's rules).

Why: nav2_costmap_2d's Costmap2DPublisher sends the full grid only when a subscriber needs it (the
grid's size, resolution or origin changed since the last full message, or ``always_send_full_costmap``)
and otherwise the smallest window holding every cell the updates redrew since the last publication.
On a 1000 x 1700 warehouse map the full grid, converted cell by cell, was a quarter of the navigation
process's CPU (issue 44); a scan changes a few thousand cells.

:class:`PublishTracker` keeps that state without any message type; the ROS node asks it what to send.
The cost → OccupancyGrid value conversion is one lookup in :data:`COST_TRANSLATION_TABLE` (Nav2's cost
translation table: 0 → 0, 1..252 → 1..98, 253 → 99, 254 → 100, 255 → -1), run on the window only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt

from nav_stack.core.costmap.layer import CostArray, Window
from nav_stack.core.grid import GridSpec, occupancy_from_cost

#: OccupancyGrid value of each Nav2 cost, indexed by the cost (int8[256]).
COST_TRANSLATION_TABLE: npt.NDArray[np.int8] = occupancy_from_cost(np.arange(256, dtype=np.uint8))
COST_TRANSLATION_TABLE.setflags(write=False)


def occupancy_of(costs: CostArray) -> npt.NDArray[np.int8]:
    """OccupancyGrid values (a new int8 array of the same shape) of Nav2 ``costs``, by table lookup."""
    return COST_TRANSLATION_TABLE[costs]


@dataclass(frozen=True)
class Publication:
    """What to send now: ``kind`` "full" (the whole grid), "update" (``window`` only) or "none"."""

    kind: Literal["full", "update", "none"]
    window: Window


class PublishTracker:
    """Accumulates the windows the updates redrew and decides, per publish cycle, what to send.

    The full grid goes out when the grid's geometry differs from the last full message's (first
    publication, resize, a rolling window's move), when asked to (``force_full``: a new subscriber, or
    ``always_send_full_costmap``), else an update of the redrawn window, else nothing. After a full
    message the accumulated window is dropped: the full grid already holds those cells.
    """

    def __init__(self) -> None:
        self._changed = Window.empty()
        self._sent_spec: GridSpec | None = None

    @property
    def changed(self) -> Window:
        """The cells redrawn since the last publication (end-exclusive, grid cells)."""
        return self._changed

    def add(self, window: Window) -> None:
        """Record a window an update redrew (LayeredCostmap.update's return value)."""
        self._changed = self._changed.union(window)

    def invalidate(self) -> None:
        """Forget the last full message (deactivate, cleanup): the next publication is full again."""
        self._sent_spec = None

    def next(self, spec: GridSpec, force_full: bool = False) -> Publication:
        """What to publish now for a grid of ``spec``; the caller then sends it (or drops it unsent)."""
        if force_full or spec != self._sent_spec:
            self._sent_spec = spec
            self._changed = Window.empty()
            return Publication("full", Window.full(spec))
        window = self._changed.clipped(spec)
        self._changed = Window.empty()
        return Publication("update" if not window.is_empty else "none", window)


def apply_update(grid: npt.NDArray[np.generic], x: int, y: int, width: int, height: int,
                 data: npt.ArrayLike) -> None:
    """Write an update's row-major ``data`` (``width`` x ``height`` cells from cell ``(x, y)``) into
    ``grid`` ``[row, col]`` in place, as a costmap subscriber does with ``costmap_updates`` or
    ``costmap_raw_updates``; raises ValueError when the window does not fit the grid or the data."""
    rows, cols = grid.shape
    if x < 0 or y < 0 or x + width > cols or y + height > rows:
        raise ValueError(f"update window {width} x {height} at ({x}, {y}) lies outside the "
                         f"{cols} x {rows} grid")
    values = np.asarray(data, dtype=grid.dtype)
    if values.size != width * height:
        raise ValueError(f"update of {width} x {height} cells carries {values.size} values")
    grid[y : y + height, x : x + width] = values.reshape(height, width)
